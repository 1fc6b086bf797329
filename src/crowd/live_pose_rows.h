// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The engine's joint matrices of a live pose (CrowdManager::setLivePose) checked and stored as
// palette rows: the three rows of each 3x4 skinning matrix, one texel each, in the palette's
// format. The poses of a thousand instances of 60 joints pass here every frame, so both run
// four floats at a time where the CPU has SSE2 (every x86-64), with no branch per value; the
// Reference versions do the same one value at a time (the tests hold the two equal, and
// builds without SSE2 use them). No GL.

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/span.h"

namespace si::detail {

/// The first of `skinning` whose last row is not 0 0 0 1 or which holds a value whose
/// magnitude passes `range` (or is not finite), or skinning.size() when there is none.
size_t firstBadJoint(Span<const glm::mat4> skinning, float range);
size_t firstBadJointReference(Span<const glm::mat4> skinning, float range);

/// Stores each of `skinning`'s first three rows as texels `j * joint_stride_texels + row` of
/// `frame` in `format` (kMatrix3x4F32, or kMatrix3x4F16 rounded to nearest even as
/// floatToHalf does). Every value must pass firstBadJoint's check with the format's range.
void storeJointRows(PaletteFormat format, Span<const glm::mat4> skinning,
                    uint32_t joint_stride_texels, uint8_t* frame);
void storeJointRowsReference(PaletteFormat format, Span<const glm::mat4> skinning,
                             uint32_t joint_stride_texels, uint8_t* frame);

}  // namespace si::detail
