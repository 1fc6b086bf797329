// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Blending a joint's transform relative to its parent the way the reference blends local
/// transforms (slerp the rotation, lerp the translation and the scale), from skinning matrices
/// alone. A baked palette stores each joint's skinning matrix S = global * inverse bind, so
/// what it gives for a joint relative to its parent is
///
///   D = inverse(S_parent) * S_joint = bind_parent * local * inverse(bind_joint),
///
/// the local transform seen through the two bind matrices. localBlend(D_a, D_c, pivot, t)
/// equals bind_parent * blend(local_a, local_c, t) * inverse(bind_joint) when the bind
/// matrices are rotations, translations and uniform scales and the local scale is uniform:
/// - the rotation: a slerp along the shorter arc is unchanged by rotating both ends on the left
///   or the right, so slerping D's rotations is slerping the local rotations;
/// - the translation: D maps the joint's bind-pose origin `pivot` (inverse(inverse bind)'s
///   translation) to where bind_parent puts the local translation, an affine function of it, so
///   lerping that image is lerping the local translation;
/// - the uniform scale (the cube root of the determinant) is lerped; whatever the linear part
///   holds beyond rotation and uniform scale (shear, non-uniform scale) is lerped separately.
/// Matrices that mirror or are degenerate (determinant <= 0) fall back to the element-wise lerp.
///
/// si_skinning.glsl's siLocalBlend computes the same in float; this is its CPU emulation.

#include <glm/glm.hpp>

namespace si {

/// The joint transform a fraction `t` in [0, 1] of the way from `a` to `c` (affine matrices,
/// last rows 0 0 0 1: a joint's skinning matrix relative to its parent's) as described above,
/// with `pivot` the joint's bind-pose origin. t = 0 gives `a`, t = 1 gives `c` (to float
/// rounding).
glm::mat4 localBlend(const glm::mat4& a, const glm::mat4& c, const glm::vec3& pivot, float t);

/// The affine inverse of `m` (last row 0 0 0 1): the 3x3's inverse and -inverse * translation,
/// as the shader forms it.
glm::mat4 affineInverse(const glm::mat4& m);

}  // namespace si
