// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Internal: GLSL pieces shared by the shipped include (skinningGlsl) and the renderer's programs.

namespace si {

/// siTransformPoint, siTransformNormal (sign(det) x cofactor) and siTransformVector.
const char* transformGlsl();

}  // namespace si
