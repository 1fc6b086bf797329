// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Blending two skinning matrices without collapsing them. Lerping matrices element by element
/// shrinks whatever the two rotate apart: half-way between an arm hanging down and one raised
/// overhead, the lerped matrix squashes the arm towards its pivot. rigidBlend instead applies a
/// fraction of the rigid motion between them, as a dual quaternion blended with the identity
/// (the screw motion's path, its weight chosen so that the rotation turns by t of its angle, as
/// a slerp does), so the arm swings on its arc:
///
///   rigidBlend(A, C, t) = blend(identity, C * inverse(A), t) * A
///
/// The result does not depend on the space both matrices are expressed in (it is the same for
/// A and C multiplied on the left or on the right by one matrix), so blending skinning matrices
/// this way equals blending the joints' transforms relative to any common parent. The delta's
/// uniform scale (the cube root of its determinant) is blended linearly, and whatever the delta
/// holds beyond a rotation, translation and uniform scale (shear, non-uniform scale) is added in
/// proportion to t, so t = 0 gives A and t = 1 gives C. A delta that mirrors (determinant <= 0)
/// falls back to the element-wise lerp.
///
/// si_skinning.glsl's siRigidBlend computes the same in float; this is its CPU emulation.

#include <glm/glm.hpp>

namespace si {

/// A blended a fraction `t` in [0, 1] of the way from affine matrix `a` to affine matrix `c`
/// (last rows 0 0 0 1) as described above, in float as the shader computes it. The rotation
/// turns the way whose quaternion lies in `hemisphere`'s half (dot >= 0): the identity (the
/// default) takes the shorter way; a parent joint's rigidDeltaRotation turns a joint the way
/// its parent turns, even past 180 degrees.
glm::mat4 rigidBlend(const glm::mat4& a, const glm::mat4& c, float t,
                     const glm::vec4& hemisphere = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));

/// The unit quaternion (x, y, z, w) of the rotation from `a` to `c` in the frame both are in
/// (that of c * inverse(a), its uniform scale removed), in `hemisphere`'s half. The identity
/// for a delta that mirrors or is degenerate.
glm::vec4 rigidDeltaRotation(const glm::mat4& a, const glm::mat4& c,
                             const glm::vec4& hemisphere = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));

}  // namespace si
