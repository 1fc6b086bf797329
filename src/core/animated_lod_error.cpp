// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD errors over animated poses: each sampled pose skins the mesh once, and every sub-mesh's
// levels are measured against its LOD 0 on those positions (surfaceDistance).
#include <algorithm>
#include <vector>

#include "si/core/lod_error.h"
#include "si/core/reference_evaluator.h"
#include "core/str_cat.h"

namespace si {
using detail::strCat;

Status measureAnimatedLodErrors(Character* character, const AnimatedLodErrorDesc& desc,
                                std::vector<std::vector<int>>* worst_pose_clip) {
  if (character == nullptr)
    return {StatusCode::kInvalidArgument, "measureAnimatedLodErrors: character is null"};
  const uint32_t per_clip = desc.poses_per_clip ? desc.poses_per_clip : 8u;
  const uint32_t max_poses = desc.max_poses ? desc.max_poses : 256u;
  SkinnedMesh mesh = character->mesh;  // Untouched on failure.
  Status s = measureLodErrors(&mesh, false);
  if (!s.isOk()) return s;
  s = mesh.validate(uint32_t(character->skeleton.parents.size()));
  if (!s.isOk()) return s;
  std::vector<std::vector<int>> worst(mesh.sub_meshes.size());
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    worst[sm].assign(mesh.sub_meshes[sm].lods.size(), -1);

  // The poses: the rest pose, then per_clip per clip, at most max_poses in all.
  struct PoseAt {
    int clip;
    double time;
  };
  std::vector<PoseAt> poses = {{-1, 0.0}};
  for (size_t c = 0; c < character->clips.size() && poses.size() < max_poses; ++c) {
    const double duration = character->clips[c].duration_seconds;
    const uint32_t n = duration > 0.0 ? per_clip : 1u;
    for (uint32_t k = 0; k < n && poses.size() < max_poses; ++k)
      poses.push_back({int(c), n > 1 ? duration * double(k) / double(n - 1) : 0.0});
  }

  ReferencePose pose;
  std::vector<glm::dvec3> skinned(mesh.vertexCount());
  std::vector<glm::vec3> positions(mesh.vertexCount());
  const auto range = [&](const IndexRange& r) {
    return Span<const uint32_t>(mesh.indices.data() + r.first_index, r.index_count);
  };
  for (const PoseAt& at : poses) {
    s = at.clip < 0 ? evaluateRestPose(character->skeleton, &pose)
                    : evaluateLocalPose(character->skeleton, character->clips[size_t(at.clip)],
                                        at.time, &pose);
    if (s.isOk())
      s = skinVertices(mesh, pose.skinning, Span<glm::dvec3>(skinned.data(), skinned.size()), {},
                       {});
    if (!s.isOk())
      return {s.code(), strCat("measureAnimatedLodErrors: clip ", at.clip, ": ", s.message())};
    for (size_t v = 0; v < skinned.size(); ++v) positions[v] = glm::vec3(skinned[v]);
    for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm) {
      SubMesh& sub = mesh.sub_meshes[sm];
      for (size_t l = 1; l < sub.lods.size(); ++l) {
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
