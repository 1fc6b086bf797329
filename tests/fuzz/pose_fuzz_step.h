// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's pose steps (crowd_api_fuzz.cpp): the drawn pose as local transforms
// with a hostile look-at on it, and hostile live poses.

#include <cmath>
#include <vector>

#include "fuzz_input.h"
#include "si/core/look_at.h"
#include "si/crowd/crowd_manager.h"

namespace si::fuzz {

inline bool finitePose(const std::vector<TransformD>& pose) {
  for (const TransformD& t : pose)
    if (!std::isfinite(t.translation.x + t.translation.y + t.translation.z + t.rotation.w +
                       t.rotation.x + t.rotation.y + t.rotation.z + t.scale.x + t.scale.y +
                       t.scale.z))
      return false;
  return true;
}

// localPose of `h`, then a hostile look-at on it: a pose given is finite, a refusal is named
// and leaves the pose as it was.
inline void fuzzLocalPose(const CrowdManager& crowd, InstanceHandle h, const Skeleton& sk,
                          Input& in, void (*fail)(const char*)) {
  std::vector<TransformD> pose(sk.jointCount());
  const Status s = crowd.localPose(h, sk, pose);
  if (!s.isOk()) {
    if (s.message().empty()) fail("a refused localPose has no message");
    return;
  }
  if (!finitePose(pose)) fail("a local pose is not finite");
  LookAt look;
  const uint32_t links = 1 + in.u8() % 3;
  for (uint32_t k = 0; k < links; ++k)
    look.chain.push_back({uint32_t(in.u8() % 4), in.u8() < 32 ? in.f64() : 0.5 + 0.5 * k,
                          in.u8() < 32 ? in.f64() : 1.0});
  if (in.u8() < 32) look.forward = glm::dvec3(in.f64(), in.f64(), in.f64());
  if (in.u8() < 32) look.weight = in.f64();
  const glm::dvec3 target(in.f32(), in.f32(), in.f32());
  const std::vector<TransformD> kept = pose;
  const Status st = applyLookAt(sk, look, target, pose);
  if (!st.isOk()) {
    if (st.message().empty()) fail("a refused applyLookAt has no message");
    for (size_t j = 0; j < pose.size(); ++j)
      if (!(pose[j].translation == kept[j].translation && pose[j].rotation == kept[j].rotation &&
            pose[j].scale == kept[j].scale))
        fail("a refused applyLookAt changed the pose");
  } else if (!finitePose(pose)) {
    fail("a looked-at pose is not finite");
  }
}

// setLivePose (or setLivePoses) with a pose of the palette's joint count give or take one, its
// matrices sometimes holding a hostile value anywhere (the last row included), handed over from
// the clip at once or over a hostile blend.
inline Status setFuzzedLivePose(CrowdManager& crowd, InstanceHandle h, const BakedPalette& palette,
                                Input& in) {
  std::vector<glm::mat4> pose(palette.palette_joints.size() + in.u8() % 3 - 1, glm::mat4(1.0f));
  for (glm::mat4& m : pose)
    if (in.u8() < 64) m[in.u8() % 4][in.u8() % 4] = in.f32();
  const double blend = in.u8() < 128 ? 0.0 : in.f64();
  if (in.u8() < 192) return crowd.setLivePose(h, pose, blend);
  // setLivePoses: the same pose for `h` one to three times over (its last one holds; a refusal
  // refuses each alike, so the crowd stays as it was), sometimes a matrix short.
  const size_t times = 1 + in.u8() % 3;
  std::vector<glm::mat4> all;
  for (size_t k = 0; k < times; ++k) all.insert(all.end(), pose.begin(), pose.end());
  if (!all.empty() && in.u8() < 32) all.pop_back();
  const std::vector<InstanceHandle> handles(times, h);
  return crowd.setLivePoses(handles, all, blend);
}

}  // namespace si::fuzz
