// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The image error of each LOD level: how many pixels of a character's image a level changes
/// against LOD 0, shading included, measured by drawing the character with the renderer's own
/// programs at several heights in pixels, poses of its clips and view directions. A geometric
/// error (si::lodErrorsByLevel) bounds how far the surface moves; it does not see normals and
/// texture coordinates interpolated over larger triangles, nor a dropped helmet uncovering hair.
/// The image error does, and as "equivalent units" it can drive the crowd's screen-error LOD
/// choice in place of the geometric error: the pixel budget then bounds the pixels that change.
///
/// Usage (a GL context current, as for si::Renderer):
/// \code
///   si::ImageLodErrorReport report;
///   si::Status s = si::measureImageLodErrors(info, character, palette, {}, &report);
///   crowd_desc.lod_errors_units = si::imageLodErrorsUnits(report);  // or the geometric ones
/// \endcode

#include <cstdint>
#include <vector>

#include "si/core/baked_palette.h"
#include "si/core/character.h"
#include "si/core/status.h"
#include "si/gl/gl_context.h"
#include "si/gl/impostor.h"
#include "si/gl/material.h"

namespace si {

/// Options of measureImageLodErrors(). Zero or empty fields take the documented defaults.
struct ImageLodErrorDesc {
  /// The character's height on screen (its largest bind-pose extent, si::Character::height),
  /// in display pixels, at which every level is drawn; empty means 4, 8, 16, 32 and 64.
  std::vector<uint32_t> heights_pixels;
  /// Each image is drawn at this many times the display size and box-filtered down before it
  /// is compared (an antialiased display, where a sub-pixel change moves a pixel a little
  /// instead of flipping it); 0 means 4, 1 compares the aliased images.
  uint32_t supersample = 0;
  /// View directions around the vertical axis; 0 means 8.
  uint32_t azimuths = 0;
  /// View elevations in degrees (0: level, 90: from above); empty means 0 and 30.
  std::vector<float> elevations_degrees;
  /// Poses per clip, evenly over its duration; 0 means 2. At most max_poses in all (0: 6),
  /// clips taken in order.
  uint32_t poses_per_clip = 0;
  uint32_t max_poses = 0;
  /// A pixel differs when a channel is off by more than this (of 255); 0 means 8.
  uint32_t channel_tolerance = 0;
  /// The first view direction's azimuth in degrees (the others follow every 360 / azimuths).
  /// An impostor is exact at its captured views: measure it between them (half its step).
  float azimuth_offset_degrees = 0.0f;
  /// Where the poses sit between their even steps, as a fraction of a step in [0, 1): clip c's
  /// pose k at (k + pose_phase) / poses_per_clip of its duration.
  float pose_phase = 0.0f;
  /// Non-null: the mesh's last level is its impostor level (si::appendImpostorLevel), drawn as
  /// the impostor this desc captures (Renderer::buildImpostor), and measured like the others.
  const ImpostorDesc* impostor = nullptr;
  /// Non-null: every level (the impostor too) is drawn through this material
  /// (Renderer::addMaterial) and its output 0 compared, so the error is the one the host's look
  /// shows; null: the built-in material.
  const MaterialDesc* material = nullptr;
};

/// One LOD level's errors.
struct ImageLodLevel {
  /// si::lodErrorsByLevel's value: the geometric error in model units.
  float geometric_units = 0.0f;
  /// Per height (ImageLodErrorReport::heights_pixels): the pixels of one character's image
  /// that differ from LOD 0, the mean and the largest over the poses and view directions.
  std::vector<double> mean_differing_pixels, max_differing_pixels;
  /// The height in display pixels at which the level changes one pixel of the character's
  /// image on average (interpolated between the measured heights on a log-log scale, and
  /// extrapolated past them along the nearest two): below it, the level changes less.
  /// Infinite when it changes nothing at any height; 0 for level 0.
  double one_pixel_height = 0.0;
  /// The image error as a length in model units: the character's height over
  /// one_pixel_height. Projected like a geometric error, it reaches 1 pixel exactly where the
  /// level changes one pixel of the image, so a screen-error budget of 1 pixel selects the level
  /// where it changes at most one pixel per character (another budget scales that height in
  /// proportion, which the differing pixels follow only roughly: they grow faster than the
  /// height). Level 0: 0.
  float image_units = 0.0f;
};

struct ImageLodErrorReport {
  std::vector<uint32_t> heights_pixels;  ///< The heights measured.
  float character_height_units = 0.0f;   ///< si::Character::height().
  uint32_t views = 0, poses = 0;         ///< Drawn at every height and level.
  std::vector<ImageLodLevel> levels;     ///< maxLodCount() of the mesh, LOD 0 first.
  bool impostor = false;  ///< The last level was drawn as the impostor (ImageLodErrorDesc).
};

/// Draws the character (every sub-mesh worn, its palette's poses, the renderer's vertex-shader
/// program and default light, through the built-in material or ImageLodErrorDesc::material, an
/// orthographic camera, offscreen) at every level, height, pose and view direction, and compares
/// each level's image with LOD 0's, per character. The host's framebuffer bindings, viewport and
/// pixel-pack state are restored. kInvalidArgument for a null report, a height of 0, an invalid
/// character or a palette without clips; the status of lodErrorsByLevel() when the mesh has no LOD
/// errors; kLimitExceeded when the images would pass GL_MAX_TEXTURE_SIZE; the renderer's status for
/// what it refuses; kBackend naming the GL error or an incomplete framebuffer; kInvalidArgument for
/// a pose_phase outside [0, 1) or an azimuth offset that is not finite; with an impostor,
/// buildImpostor's errors and kInvalidArgument for a mesh of one level; with a material,
/// addMaterial's errors. Nothing is written on failure.
Status measureImageLodErrors(const GlInfo& info, const Character& character,
                             const BakedPalette& palette, const ImageLodErrorDesc& desc,
                             ImageLodErrorReport* report);

/// The report's image errors, made non-decreasing (a coarser level never claims less), ready
/// for CrowdDesc::lod_errors_units. With an impostor (report.impostor), a mesh level whose
/// image error exceeds the impostor's is dominated (more triangles, and more pixels changed)
/// and gets the impostor's error: the screen-error choice then hands the character straight to
/// the impostor wherever its error is within the budget, skipping those levels.
std::vector<float> imageLodErrorsUnits(const ImageLodErrorReport& report);

/// The crowd's errors (CrowdDesc::lod_errors_units) for mesh levels selected by their geometric
/// errors `geometric_units` (si::lodErrorsByLevel, the impostor level's entry included) with an
/// impostor level last (report.impostor), for the screen-error choice at `budget_pixels`
/// (CrowdDesc::pixel_error_budget; 0, negative or not finite: 1). The impostor takes the
/// characters from the smallest up to the height where its measured curve (the report's mean
/// differing pixels, read on a log-log scale between the measured heights and along the
/// nearest two past them) first rises above the curve of the mesh level the budget would draw
/// there: its error is the one that projects to the budget at that height (budget x character
/// height / the height, in model units; a level's own error where the height is where the
/// level's characters end), and the mesh levels whose errors are larger get that error too, so
/// the choice skips them. The curves are compared, not the one-pixel heights (image_units): the
/// impostor's error grows faster with the height than a mesh level's, so an impostor that
/// changes one pixel at a greater height than LOD 2 may change more pixels than LOD 2 where LOD
/// 2's characters are tallest. Where it changes more than the coarsest mesh level from 1 pixel
/// on, it comes after that level, at the larger of that level's error and its own image error.
/// Without an impostor, or with counts that differ, `geometric_units` unchanged; a report
/// without curves (levels measured at no height) compares image_units instead: the trailing
/// mesh levels whose image error exceeds the impostor's hand over to it at the first one's
/// geometric error.
std::vector<float> impostorLodErrorsUnits(const std::vector<float>& geometric_units,
                                          const ImageLodErrorReport& report,
                                          float budget_pixels = 1.0f);

}  // namespace si
