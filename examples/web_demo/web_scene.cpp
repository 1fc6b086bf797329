// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "web_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace si::web {

Status Scene::init(const GlInfo& info, const RendererDesc& renderer_desc,
                   const Character& character, const BakedPalette& palette, uint32_t instances) {
  character_ = &character;
  palette_ = &palette;
  Status s = renderer_.init(info, renderer_desc);
  if (s.isOk()) s = renderer_.addCharacter(character, palette, &id_);
  if (s.isOk()) s = batcher_.init(renderer_.batchLimits());
  if (s.isOk()) s = setInstances(instances);
  return s;
}

Status Scene::setInstances(uint32_t instances) {
  instances = std::clamp(instances, 1u, kMaxInstances);
  CrowdDesc cd;
  cd.palette = palette_;
  cd.sub_mesh_count = uint32_t(character_->mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character_->mesh.maxLodCount());
  cd.worker_threads = 1;  // The page's thread only.
  Status s = crowd_.init(cd);
  if (!s.isOk()) return s;
  base_lod_lines_ = crowd_.desc().lod_distances_radii;
  base_far_ = crowd_.desc().max_distance_radii;
  instances_ = instances;
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(instances))));
  std::vector<glm::dvec3> positions;
  for (uint32_t i = 0; i < instances; ++i)
    positions.push_back(glm::dvec3((i % side) * 1.6, 0.0, (i / side) * 1.6));
  RandomCrowdDesc rc;
  rc.positions = positions;
  rc.seed = kSeed;
  rc.required_mask = 1u;
  rc.optional_mask = 0xEu;  // Helmet, shield and spear at random.
  std::vector<InstanceHandle> handles;
  s = crowd_.addRandom(rc, &handles);
  return s.isOk() ? setLodScale(lod_scale_) : s;
}

Status Scene::setLodScale(double scale) {
  lod_scale_ = std::clamp(scale, 0.05, 20.0);
  std::vector<float> lines = base_lod_lines_;
  for (float& l : lines) l *= float(lod_scale_);
  return crowd_.setLodDistances(lines, base_far_ * float(lod_scale_));
}

void Scene::drag(double dx, double dy) {
  orbit_.yaw -= dx * kOrbitRadiansPerPixel;
  orbit_.pitch = std::clamp(orbit_.pitch + dy * kOrbitRadiansPerPixel, 0.05, 1.5);
}

void Scene::wheel(double delta_y) {
  orbit_.distance =
      std::clamp(orbit_.distance * std::exp(delta_y * kZoomPerWheelUnit), 2.0, 1500.0);
}

Camera Scene::camera(float aspect) const {
  const double half = 0.5 * std::ceil(std::sqrt(double(instances_))) * 1.6;
  const glm::dvec3 target(half, 0.8, half);
  const glm::dvec3 eye =
      target + orbit_.distance * glm::dvec3(std::cos(orbit_.pitch) * std::sin(orbit_.yaw),
                                            std::sin(orbit_.pitch),
                                            std::cos(orbit_.pitch) * std::cos(orbit_.yaw));
  return Camera::lookAt(eye, target, glm::vec3(0, 1, 0), 0.9f, aspect, 0.2f, 2000.0f);
}

Status Scene::frame(double dt, float aspect, DrawStats* stats) {
  const Camera cam = camera(aspect);
  Status s = crowd_.update(dt, cam);
  renderer_.clear(glm::vec4(0.55f, 0.62f, 0.7f, 1.0f));
  last_draw_ = {};
  if (s.isOk())
    s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, cam, &last_draw_);
  if (stats != nullptr) *stats = last_draw_;
  return s;
}

std::string Scene::statsLine() const {
  const CrowdFrameStats& cs = crowd_.view().stats();
  char text[256];
  std::snprintf(text, sizeof(text),
                "%u characters, %u visible (LOD 0-3: %u %u %u %u) | %u draw calls, %.2f M "
                "triangles",
                instances_, cs.visible, cs.per_lod[0], cs.per_lod[1], cs.per_lod[2], cs.per_lod[3],
                last_draw_.draw_calls, double(last_draw_.triangles) * 1e-6);
  return text;
}

}  // namespace si::web
