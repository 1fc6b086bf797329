// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/blend_props_table.h"

#include <glm/gtc/matrix_transform.hpp>

#include "si/bake/lod_chain.h"
#include "si/core/layer_mask.h"
#include "si/core/prop.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_prop.h"

namespace si::bench {

namespace {

// The states: plain playback, a 1D blend of two clips, a 2D blend of four, props, a 1D blend
// with props.
const char* const kNames[] = {"plain", "blend 2", "blend 4", "props", "both"};
constexpr int kStates = 5;

// The clips a state blends (walk and run; a 2 x 2 grid of walk, run, idle and wave).
struct BlendClips {
  uint32_t walk, run, idle, wave;
};

// Times `path` on the field of `count` in state `state` (kNames).
Status runState(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                const LayerMask& body, const BlendClips& c, uint32_t staff_bit, uint32_t sub_meshes,
                uint32_t count, const std::string& path, int state, Row* row) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
  Status s = makeCrowd(setup, palette, places, LodChoice(), &crowd, &handles, sub_meshes);
  uint32_t mask = 0, space = 0;
  const bool blend = state == 1 || state == 2 || state == 4, grid = state == 2;
  const bool props = state >= 3;
  if (s.isOk() && blend) s = crowd.addLayerMask(body, &mask);
  if (s.isOk() && blend && !grid)
    s = crowd.addBlendSpace({"locomotion", {c.walk, c.run}, {0.0f, 1.0f}, mask}, &space);
  if (s.isOk() && grid)
    s = crowd.addBlendSpace(
        {"grid", {c.walk, c.run, c.idle, c.wave}, {0.0f, 1.0f}, mask, {0.0f, 1.0f}}, &space);
  for (size_t i = 0; s.isOk() && i < handles.size(); ++i) {
    if (blend && !grid)  // Each at its own parameter and phase.
      s = crowd.playBlend(handles[i], space, float(i % 11) / 10.0f, 0.0, 0.13 * double(i % 7));
    if (grid)  // Each at its own point inside the cell: all four clips drawn.
      s = crowd.playBlend(handles[i], space,
                          glm::vec2(0.05f + 0.09f * float(i % 11), 0.05f + 0.15f * float(i % 7)),
                          0.0, 0.13 * double(i % 5));
    InstanceDesc d;
    if (s.isOk() && props) s = crowd.get(handles[i], &d);
    if (s.isOk() && props)
      s = crowd.setVariationMask(handles[i], d.variation_mask | (1u << staff_bit));
  }
  if (!s.isOk()) return s;
  row->lod = kNames[state];
  return timeCrowd(setup, renderer, crowd, "field", places, path, row);
}

}  // namespace

Status blendPropsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                       const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                       std::FILE* csv) {
  const int32_t walk = palette.findClip("walk"), run = palette.findClip("run");
  const int32_t idle = palette.findClip("idle"), wave = palette.findClip("wave");
  if (walk < 0 || run < 0 || idle < 0 || wave < 0)
    return {StatusCode::kNotFound,
            "blend: the palette has no 'walk', 'run', 'idle' and 'wave' clips"};
  const BlendClips clips{uint32_t(walk), uint32_t(run), uint32_t(idle), uint32_t(wave)};
  // The staff of crowd_demo: RiggedSimple's cylinder, thin and 1.6 units long, in the right hand.
  Character held = setup.character;
  GltfPropDesc pd;
  pd.name = "staff";
  PropMesh staff;
  Status s = importGltfPropFile(
      std::string(SI_BENCH_ASSETS) + "/RiggedSimple/glTF-Binary/RiggedSimple.glb", pd, &staff,
      nullptr);
  glm::mat4 offset = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
  offset = glm::scale(offset, glm::vec3(0.025f, 0.025f, 0.17f));
  Socket grip;
  uint32_t staff_bit = 0;
  if (s.isOk()) s = makeSocket(held.skeleton, "grip", "r_hand", offset, &grip);
  if (s.isOk()) s = attachProp(grip, staff, &held, &staff_bit);
  const uint32_t levels = uint32_t(held.mesh.maxLodCount());
  if (s.isOk() && levels >= 2) {  // The prop's own chain, to the character's levels.
    LodChainDesc chain;
    chain.level_count = levels;
    s = buildLodChain(&held.mesh, chain, nullptr);
  }
  LayerMask body;
  if (s.isOk()) s = buildFullBodyMask(held.skeleton, palette, "body", &body);
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer renderer;
  if (s.isOk()) s = renderer.init(setup.info, rd);
  CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(held, palette, &id);
  if (!s.isOk()) return {s.code(), "blend: " + s.message()};
  std::printf(
      "\nBlend spaces and props (field): every instance playing its clip (plain), blending the "
      "walk and the run (blend 2: a 1D blend space on a full-body mask, parameters 0 to 1), "
      "blending four clips (blend 4: a 2 x 2 grid of walk, run, idle and wave, each instance "
      "inside the cell), holding a staff (%zu triangles at LOD 0, %zu at LOD %u), and blend 2 "
      "with the staff (both), side by side in one run\n",
      held.mesh.triangleCount(staff_bit, 0), held.mesh.triangleCount(staff_bit, levels - 1),
      levels - 1);
  printSideBySideHeader("state");
  std::printf("\n");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if (path != "instanced" && path != "compute" && path != "gpu-culled" && path != "gpu-driven")
        continue;
      Row rows[kStates];
      for (int state = 0; state < kStates; ++state) {
        s = runState(setup, renderer, palette, body, clips, staff_bit,
                     uint32_t(held.mesh.sub_meshes.size()), count, path, state, &rows[state]);
        if (!s.isOk()) return {s.code(), "blend, " + path + ": " + s.message()};
        printSideBySideRow(rows[state], rows[0], "blend", csv);
        std::printf("\n");
      }
    }
  renderer.shutdown();
  return Status::ok();
}

}  // namespace si::bench
