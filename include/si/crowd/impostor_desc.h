// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// What a character's impostor atlas captures (ImpostorDesc) and what the build made
/// (ImpostorInfo): the same for si::Renderer::buildImpostor (OpenGL, si/gl/impostor.h says what
/// an impostor keeps and loses) and si::vk::Renderer::buildImpostor (Vulkan).

#include <cstdint>
#include <vector>

namespace si {

/// What the atlas captures. Zero or empty fields take the documented defaults.
struct ImpostorDesc {
  /// View directions around the character's vertical axis; 0 means 16.
  uint32_t azimuths = 0;
  /// View elevations in degrees (0: level, 90: from above), increasing, at most 4; empty means
  /// 0, 30 and 60.
  std::vector<float> elevations_degrees;
  /// Frames per clip, spread evenly over its baked frames (first and last included; a clip of
  /// fewer baked frames keeps them all); 0 means 8.
  uint32_t frames_per_clip = 0;
  /// Side of one cell in texels, a power of two (each mip level halves every cell; others are
  /// refused with kInvalidArgument); 0 means 32. A cell spans 1.5 character heights, so a cell
  /// of 32 texels serves an impostor up to about 20 pixels tall at one texel per pixel.
  uint32_t cell_pixels = 0;
  /// The parts every impostor shows (bit s: sub-mesh s); 0 means all.
  uint32_t variation_mask = 0;
  /// The capture draws this many texels each way per atlas texel and averages them into it
  /// (an antialiased atlas: thin parts such as a spear kept as partial coverage instead of
  /// appearing and vanishing between views). 1, 2 or 4; 0 means 2, or 1 where 2 would pass a
  /// side limit or max_bytes. Both back-ends capture and resolve alike. At the captured views and
  /// frames, 2 halves the pixels an 8-pixel impostor changes (docs/accuracy.md); drawing costs
  /// the same, the atlas being as large. kInvalidArgument for other values.
  uint32_t capture_supersample = 0;
  /// Added to the mip level the impostor fragments sample (a sampler's LOD bias), within
  /// [-2, 2]; others (and NaN) are refused with kInvalidArgument. 0 (the default) reads the level
  /// trilinear filtering picks; negative reads finer levels: sharper impostors of a few pixels
  /// that keep their thin limbs, for more texels read a fragment and more fragments. On the 10k
  /// field drawn every character an impostor at 960x540 (llvmpipe), -1 raises the frame's SSIM
  /// against LOD 0 from 0.895 to 0.925 with no more temporal error (docs/accuracy.md, "The
  /// impostor's mip level"). On the H200 it costs the 100k field at 1920x1080 6 % (1.06 ->
  /// 1.13 ms; nothing at 1M, whose impostor pass is bound by its quads more than their
  /// fragments) and lowers its 4 x 4 SSIM at 7680x4320 slightly (0.96722 -> 0.96682): it pays
  /// only where the characters are a few display pixels tall, hence 0 by default.
  float lod_bias = 0.0f;
  /// The most GPU memory the build may take: the atlas with its mip levels and the capture
  /// (its depth buffer and, when supersampled, its own three layers), which lives during the
  /// build only (ImpostorInfo::bytes + capture_bytes); 0 means 1 GiB. Past it, buildImpostor
  /// refuses before allocating (kLimitExceeded).
  uint64_t max_bytes = 0;
};

/// What buildImpostor() made (or planned, when it refused).
struct ImpostorInfo {
  uint32_t views = 0;              ///< azimuths x elevations.
  uint32_t frames = 0;             ///< Captured frames, every clip's together.
  uint32_t cells = 0;              ///< views x frames.
  uint32_t cell_pixels = 0;        ///< A cell's side in texels (ImpostorDesc's, 0 resolved).
  uint32_t width = 0, height = 0;  ///< Texels of each of the atlas's three layers.
  uint64_t bytes = 0;              ///< GPU memory of the atlas with its mip levels.
  /// The capture's depth buffer and, supersampled, its three layers: freed when the build
  /// returns.
  uint64_t capture_bytes = 0;
  uint32_t capture_supersample = 0;  ///< Capture texels each way per atlas texel (1, 2 or 4).
  /// Set once the atlas is captured (si::gl): its surface layer (metallic, roughness, occlusion
  /// and the material) holds one value wherever the character was drawn, as for a character of
  /// one material without metallic-roughness or occlusion images. Its impostor fragments then
  /// take that value from a uniform and read two of the three layers (at 100k impostors of a
  /// few pixels, the fragment stage's reads bound the frame: docs/performance.md). si::vk's
  /// impostors read the layer always and leave it false.
  bool uniform_surface = false;
};

}  // namespace si
