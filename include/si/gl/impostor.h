// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Animated impostors: a character's far LOD drawn as one textured quad per instance. The
/// renderer draws the character into an atlas at upload (Renderer::buildImpostor): every view
/// direction of a ring of azimuths at a few elevations, for a reduced set of every clip's
/// frames, each cell holding the unlit base colour with the coverage, the normal with the tint
/// mask, and the metallic, roughness, occlusion and material index. At draw time each instance at
/// the crowd's impostor level (CrowdDesc::impostor_lod, si::appendImpostorLevel) shows the cell of
/// the view direction and frame nearest its own, lit by the renderer's light and tinted by its
/// colour as the mesh would be.
///
/// What the atlas keeps and loses:
/// - kept: the pose (nearest of the reduced frames, crossfades show the heavier clip; morph
///   targets at that frame's weights), the
///   view direction (nearest of azimuths x elevations), the base colour and material factors,
///   metallic, roughness, occlusion and material index (what a material reads: it lights an
///   impostor as it lights the mesh), the tint and its mask, the lighting (from the captured
///   normals), the instance's scale;
/// - lost: the variation parts (the atlas shows the parts of ImpostorDesc::variation_mask for
///   every instance), the custom texture layer, overlays (layered animation), the depth within
///   the character (the quad has one depth, at the character's centre) and, between the
///   captured views and frames, the in-between views and poses; emissive light. Motion vectors
///   are not drawn for impostors (the draws return kUnsupported while they are on).
/// How much this changes the image is measured like every other level's error:
/// si::measureImageLodErrors with ImageLodErrorDesc::impostor.
///
/// \code
///   si::appendImpostorLevel(&character.mesh);
///   renderer.addCharacter(character, palette, &id);
///   renderer.buildImpostor(id, {}, &info);
///   crowd_desc.impostor_lod = uint32_t(character.mesh.maxLodCount()) - 1;
/// \endcode

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
  /// Side of one cell in texels; 0 means 32. A cell spans 1.5 character heights, so a cell of
  /// 32 texels serves an impostor up to about 20 pixels tall at one texel per pixel.
  uint32_t cell_pixels = 0;
  /// The parts every impostor shows (bit s: sub-mesh s); 0 means all.
  uint32_t variation_mask = 0;
  /// The most GPU memory the build may take: the atlas with its mip levels and the capture's
  /// depth buffer, which lives during the build only (ImpostorInfo::bytes + capture_bytes);
  /// 0 means 1 GiB. Past it, buildImpostor refuses before allocating (kLimitExceeded).
  uint64_t max_bytes = 0;
};

/// What buildImpostor() made.
struct ImpostorInfo {
  uint32_t views = 0;        ///< azimuths x elevations.
  uint32_t frames = 0;       ///< Captured frames, every clip's together.
  uint32_t cells = 0;        ///< views x frames.
  uint32_t width = 0, height = 0;  ///< Texels of each of the atlas's three layers.
  uint64_t bytes = 0;        ///< GPU memory of the atlas with its mip levels.
  uint64_t capture_bytes = 0;  ///< The capture's depth buffer, freed when the build returns.
};

}  // namespace si
