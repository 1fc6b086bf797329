// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "web_scene.h"

#include <cmath>
#include <vector>

namespace si::web {

Status buildCrowd(const Character& character, const BakedPalette& palette, uint32_t instances,
                  CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character.mesh.maxLodCount());
  cd.worker_threads = 1;  // The page's thread only.
  Status s = crowd->init(cd);
  if (!s.isOk()) return s;
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
  return crowd->addRandom(rc, &handles);
}

Camera orbitCamera(const Orbit& orbit, uint32_t instances, float aspect) {
  const double half = 0.5 * std::ceil(std::sqrt(double(instances))) * 1.6;
  const glm::dvec3 target(half, 0.8, half);
  const glm::dvec3 eye =
      target + orbit.distance * glm::dvec3(std::cos(orbit.pitch) * std::sin(orbit.yaw),
                                           std::sin(orbit.pitch),
                                           std::cos(orbit.pitch) * std::cos(orbit.yaw));
  return Camera::lookAt(eye, target, glm::vec3(0, 1, 0), 0.9f, aspect, 0.2f, 2000.0f);
}

}  // namespace si::web
