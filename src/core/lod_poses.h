// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The poses LOD errors are measured over (measureAnimatedLodErrors, buildPartLods): the rest
// pose, then evenly spaced times of each clip (its last frame included), at most a budget.
#include <vector>

#include "si/core/character.h"
#include "si/core/lod_error.h"
#include "si/core/reference_evaluator.h"
#include "core/str_cat.h"

namespace si::detail {

struct LodPose {
  int clip;  // -1: the rest pose.
  double time;
};

inline std::vector<LodPose> lodPoses(const Character& character, const AnimatedLodErrorDesc& desc) {
  const uint32_t per_clip = desc.poses_per_clip ? desc.poses_per_clip : 8u;
  const uint32_t max_poses = desc.max_poses ? desc.max_poses : 256u;
  std::vector<LodPose> poses = {{-1, 0.0}};
  for (size_t c = 0; c < character.clips.size() && poses.size() < max_poses; ++c) {
    const double duration = character.clips[c].duration_seconds;
    const uint32_t n = duration > 0.0 ? per_clip : 1u;
    for (uint32_t k = 0; k < n && poses.size() < max_poses; ++k)
      poses.push_back({int(c), n > 1 ? duration * double(k) / double(n - 1) : 0.0});
  }
  return poses;
}

/// `mesh` (of `character`'s skeleton) skinned in pose `at` into `positions` (float, as the
/// surface distances take them); `pose` and `skinned` are scratch. Errors name `who` and the clip.
inline Status skinLodPose(const Character& character, const SkinnedMesh& mesh, const LodPose& at,
                          const char* who, ReferencePose* pose, std::vector<glm::dvec3>* skinned,
                          std::vector<glm::vec3>* positions) {
  skinned->resize(mesh.vertexCount());
  positions->resize(mesh.vertexCount());
  Status s = at.clip < 0 ? evaluateRestPose(character.skeleton, pose)
                         : evaluateLocalPose(character.skeleton, character.clips[size_t(at.clip)],
                                             at.time, pose);
  if (s.isOk())
    s = skinVertices(mesh, pose->skinning, Span<glm::dvec3>(skinned->data(), skinned->size()), {},
                     {});
  if (!s.isOk()) return {s.code(), strCat(who, ": clip ", at.clip, ": ", s.message())};
  for (size_t v = 0; v < skinned->size(); ++v) (*positions)[v] = glm::vec3((*skinned)[v]);
  return Status::ok();
}

}  // namespace si::detail
