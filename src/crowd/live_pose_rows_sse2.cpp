// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// storePose one joint at a time in SSE2's four lanes (crowd/live_pose_lanes.h).
#include <limits>

#include "crowd/live_pose_lanes.h"
#include "si/core/baked_palette.h"

#if SI_LIVE_ROWS_SSE2

namespace si::detail {

// The one pass: each matrix's columns loaded once, checked, carried into the box and stored
// by `rows`.
template <class Rows>
inline size_t storeLanes(Span<const glm::mat4> skinning, size_t joint_bytes,
                         Span<const JointBox> joints, float range, uint8_t* frame, Aabb* box,
                         Rows rows) {
  const __m128 limit = _mm_setr_ps(range, range, range, std::numeric_limits<float>::infinity());
  BoxLanes lanes;
  const bool bounded = !joints.empty();
  for (size_t j = 0; j < skinning.size(); ++j) {
    const glm::mat4& m = skinning[j];
    const __m128 c0 = _mm_loadu_ps(&m[0][0]), c1 = _mm_loadu_ps(&m[1][0]);
    const __m128 c2 = _mm_loadu_ps(&m[2][0]), c3 = _mm_loadu_ps(&m[3][0]);
    if (badColumns(c0, c1, c2, c3, limit)) return j;
    if (bounded && joints[j].half.x >= 0.0f) lanes.add(c0, c1, c2, c3, joints[j]);
    rows(c0, c1, c2, c3, frame + j * joint_bytes);
  }
  *box = bounded ? lanes.box() : Aabb();
  return skinning.size();
}

size_t storePoseSse2(PaletteFormat format, Span<const glm::mat4> skinning,
                     uint32_t joint_stride_texels, Span<const JointBox> joints, float range,
                     uint8_t* frame, Aabb* box) {
  const size_t joint_bytes = size_t(joint_stride_texels) * bytesPerTexel(format);
  if (format == PaletteFormat::kMatrix3x4F16)
    return storeLanes(skinning, joint_bytes, joints, range, frame, box, Sse2HalfRows());
  return storeLanes(skinning, joint_bytes, joints, range, frame, box, FloatRows());
}

}  // namespace si::detail

#endif  // SI_LIVE_ROWS_SSE2
