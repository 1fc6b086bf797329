// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's LOD quality table: what each LOD choice costs in image error against every
// instance at LOD 0, next to the triangles it saves.
#include <string>
#include <vector>

#include "crowd_bench/bench_scene.h"

namespace si::bench {

/// A pixel differs when a channel is off by more than this (of 255), as in the render tests.
inline constexpr int kQualityChannelTolerance = 8;

struct QualityRow {
  std::string scene, lod;
  uint32_t instances = 0;
  double triangles = 0;           ///< Mean over the frames.
  double triangles_per_pixel = 0; ///< Triangles over covered pixels, summed over the frames.
  double differing_share = 0;     ///< Pixels off by > kQualityChannelTolerance, of all pixels.
  double psnr_db = 0;             ///< Against the LOD 0 image (RGB); infinite when equal.
  double ssim = 0;                ///< Mean SSIM against the LOD 0 image (luma), over the frames.
  int max_channel = 0;            ///< Largest channel difference seen.
  /// Temporal error (shimmer): of all pixels of every pair of consecutive frames, those whose
  /// change from one frame to the next differs from the LOD 0 image's change by more than
  /// kQualityChannelTolerance in a channel. What a still frame's differing share misses: an
  /// approximation whose error moves with the animation or the camera. 0 for one frame.
  double temporal_share = 0;
};

/// Draws `frames` camera positions of the scene with every instance at LOD 0 (the reference)
/// and with each LOD choice (same clock, same instances), with `path`, and compares images.
/// The reference's own row comes first; every row's temporal share compares consecutive frames.
/// With `supersample` > 1, both images are box-filtered
/// by supersample x supersample pixels before they are compared (render at that multiple of
/// the display size: an antialiased image, where a sub-pixel change moves a pixel a little
/// instead of flipping it). With `image_dir`, writes each choice's first (filtered) frame as
/// <image_dir>/<scene>_<lod>.png.
Status measureLodQuality(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                         const std::string& scene, uint32_t count, const std::string& path,
                         uint32_t frames, uint32_t supersample,
                         const std::vector<LodChoice>& choices, const std::string& image_dir,
                         std::vector<QualityRow>* rows);

}  // namespace si::bench
