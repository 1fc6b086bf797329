// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the impostor tests share: a small atlas, crowds drawn every one as an impostor or as a
// mesh, and a camera at the origin.

#include "render/render_fixture.h"

namespace si::test {

inline uint32_t impostorLevels() {
  return uint32_t(impostorCharacter().mesh.maxLodCount());
}

inline ImpostorDesc smallImpostor() {
  ImpostorDesc d;
  d.azimuths = 8;
  d.elevations_degrees = {0.0f, 30.0f};
  d.frames_per_clip = 4;
  d.cell_pixels = 32;
  return d;
}

// Lines of `levels` levels: the impostor's at `impostor_line` radii, the others before it.
inline std::vector<float> linesTo(float impostor_line) {
  std::vector<float> lines;
  for (uint32_t l = 1; l + 1 < impostorLevels(); ++l)
    lines.push_back(impostor_line * float(l) / 8.0f);
  lines.push_back(impostor_line);
  return lines;
}

// A crowd of impostorCharacter() that draws every instance as an impostor (`impostors`) or at
// LOD 0, whatever its distance.
inline void initEveryOneAt(bool impostors, CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = impostorLevels();
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = linesTo(impostors ? 1e-3f : 1e6f);
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = impostorLevels() - 1;
  ASSERT_TRUE(crowd->init(cd).isOk());
}

// Adds an instance held at `time_seconds` of clip `clip` (modulo the clips) at `position`,
// turned `turn` radians about y, wearing every part.
inline void addHeld(CrowdManager* crowd, const glm::dvec3& position, float turn, uint32_t clip,
                    double time_seconds) {
  InstanceDesc inst;
  inst.position = position;
  inst.rotation = glm::angleAxis(turn, glm::vec3(0, 1, 0));
  inst.clip = clip % uint32_t(palette().clips.size());
  inst.time_seconds = time_seconds;
  inst.speed = 0.0f;
  inst.variation_mask = 0xFFFFFFFFu;
  InstanceHandle h;
  ASSERT_TRUE(crowd->add(inst, &h).isOk());
}

// At the origin looking along -z, lodCamera()'s field of view.
inline Camera flatCamera() {
  return Camera::lookAt({0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

// A vertex-shader renderer of impostorCharacter() (character 0) with its atlas built from `id`.
inline void impostorRenderer(const GlInfo& info, const ImpostorDesc& id, Renderer* r) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r->init(info, rd).isOk());
  CharacterId cid;
  ASSERT_TRUE(r->addCharacter(impostorCharacter(), palette(), &cid).isOk());
  ASSERT_TRUE(r->buildImpostor(cid, id).isOk());
}

}  // namespace si::test
