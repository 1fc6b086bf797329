// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD errors over animated poses: each sampled pose skins the mesh once, and every sub-mesh's
// levels are measured against its LOD 0 on those positions (surfaceDistance).
#include <algorithm>
#include <vector>

#include "si/core/lod_error.h"
#include "core/lod_poses.h"

namespace si {

Status measureAnimatedLodErrors(Character* character, const AnimatedLodErrorDesc& desc,
                                std::vector<std::vector<int>>* worst_pose_clip) {
  if (character == nullptr)
    return {StatusCode::kInvalidArgument, "measureAnimatedLodErrors: character is null"};
  SkinnedMesh mesh = character->mesh;  // Untouched on failure.
  Status s = measureLodErrors(&mesh, false);
  if (!s.isOk()) return s;
  s = mesh.validate(uint32_t(character->skeleton.parents.size()));
  if (!s.isOk()) return s;
  std::vector<std::vector<int>> worst(mesh.sub_meshes.size());
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    worst[sm].assign(mesh.sub_meshes[sm].lods.size(), -1);

  const std::vector<detail::LodPose> poses = detail::lodPoses(*character, desc);
  ReferencePose pose;
  std::vector<glm::dvec3> skinned;
  std::vector<glm::vec3> positions;
  const auto range = [&](const IndexRange& r) {
    return Span<const uint32_t>(mesh.indices.data() + r.first_index, r.index_count);
  };
  for (const detail::LodPose& at : poses) {
    s = detail::skinLodPose(*character, mesh, at, "measureAnimatedLodErrors", &pose, &skinned,
                            &positions);
    if (!s.isOk()) return s;
    for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm) {
      SubMesh& sub = mesh.sub_meshes[sm];
      for (size_t l = 1; l < sub.lods.size(); ++l) {
        if (sub.lods[l].index_count == 0) continue;  // Dropped: measured by buildPartLods.
        float e = 0.0f;
        s = surfaceDistance(positions, range(sub.lods[0]), range(sub.lods[l]), &e);
        if (!s.isOk()) return s;
        if (e > sub.lod_error_units[l]) {
          sub.lod_error_units[l] = e;
          worst[sm][l] = at.clip;
        }
      }
    }
  }
  for (SubMesh& sub : mesh.sub_meshes)  // Coarser never claims less than finer.
    for (size_t l = 1; l < sub.lod_error_units.size(); ++l)
      sub.lod_error_units[l] = std::max(sub.lod_error_units[l], sub.lod_error_units[l - 1]);
  character->mesh = std::move(mesh);
  if (worst_pose_clip != nullptr) *worst_pose_clip = std::move(worst);
  return Status::ok();
}

}  // namespace si
