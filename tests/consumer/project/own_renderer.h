// An engine's own renderer on SkinnedInstancing's CPU side and its public GLSL include: the
// engine's own GL loader (its glad, loaded by the caller), its own shaders built on
// si_skinning.glsl as installed (through a tiny include resolver), its own buffers.
// docs/glsl-interface.md walks through it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"

namespace consumer {

/// With the engine's loader loaded for the current context: clears the current framebuffer to `clear_rgb` and draws `crowd` (after its update) with the
/// character and palette, camera-relative `view_projection` and light `light`. `glsl_dir` holds
/// si_skinning.glsl. Returns "" or what failed.
std::string drawWithOwnRenderer(const std::string& glsl_dir,
                                const si::Character& character, const si::BakedPalette& palette,
                                const si::CrowdManager& crowd, const float view_projection[16],
                                const float light[3], const float clear_rgb[3],
                                uint32_t max_uniform_block_bytes,
                                uint32_t uniform_offset_alignment);

}  // namespace consumer
