// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// An impostor atlas planned before anything is allocated, the same for both back-ends'
// buildImpostor (si::gl's impostor_capture.cpp, si::vk's impostor_capture.cpp): the desc
// checked, the frames captured per clip, the grid of cells, the mip levels, the bytes, the cell's
// size in model units, and the capture crowd (one instance per cell, every cell's character at
// LOD 0, seen by an orthographic camera over the whole grid), bounded by each API's own limits
// on the atlas's sides. No GL, no Vulkan.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/impostor_desc.h"

namespace si::detail {

/// One captured frame: the clip and its baked frame.
struct CapturedFrame {
  uint32_t clip, frame;
};

struct ImpostorPlan {
  ImpostorInfo info;  ///< What the build makes (also when refused past a limit).
  uint32_t azimuths = 0, cell = 0, mask = 0;
  std::vector<float> elevations_degrees;
  float elevations_radians[4] = {};  ///< The same, for the shaders (u_impostor_elevations).
  std::vector<CapturedFrame> frames;
  /// Per clip, by increasing first texel: its first palette texel, baked frames, first atlas
  /// frame and atlas frames (the impostor shaders' clip table, impostor_quad.glsl).
  std::vector<glm::uvec4> clips;
  uint32_t columns = 0, rows = 0;  ///< Cells across and down.
  uint32_t levels = 0;             ///< Mip levels, down to one texel a cell.
  uint64_t cells = 0;              ///< frames x views (may pass 2^32 before it is refused).
  glm::vec3 centre{0.0f};          ///< Every clip's bounds' centre, model units.
  float cell_units = 0.0f;         ///< A cell's side in model units.
};

/// The numbers both back-ends' atlases keep for the impostor shaders' uniforms and clip table
/// (impostor_quad.glsl: u_impostor_grid, u_impostor_counts, u_impostor_elevations,
/// u_impostor_cell).
struct ImpostorGrid {
  uint32_t clip_count = 0;
  uint32_t columns = 0, rows = 0;  ///< Cells across and down.
  uint32_t azimuths = 0, elevations = 0;
  float elevations_radians[4] = {};
  uint32_t frame_stride_texels = 0;  ///< The palette's.
  glm::vec3 centre{0.0f};            ///< The cell's centre in model units.
  float cell_units = 0.0f;           ///< The cell's side in model units.
  uint32_t cell_texels = 0;          ///< The cell's side in level-0 texels.
  uint32_t levels = 0;               ///< The atlas's mip levels.

  glm::uvec4 grid() const { return {columns, rows, azimuths, elevations}; }
  glm::uvec4 counts() const {
    return {clip_count, frame_stride_texels, azimuths * elevations, levels};
  }
  glm::vec4 cell() const { return {centre, cell_units}; }
};

/// A limit on the atlas's sides, named as its API names it (GL_MAX_TEXTURE_SIZE,
/// maxImageDimension2D ...).
struct ImpostorSide {
  uint32_t limit;
  const char* name;
};

/// Plans `desc` for a character of `sub_meshes` sub-meshes baked as `palette`, its atlas's and
/// capture's sides bounded by `sides` (the API's limits), captured at most `max_supersample`
/// texels each way per atlas texel (what the back-end resolves). kInvalidArgument (named after
/// `call`) for more than 4 elevations, elevations not increasing within [-90, 90], a variation
/// mask that wears none of the sub-meshes, a capture_supersample other than 0, 1, 2 or 4 or a
/// lod_bias outside [-2, 2] (every GL 4 and Vulkan device takes 2: GL_MAX_TEXTURE_LOD_BIAS,
/// maxSamplerLodBias);
/// kUnsupported for one past `max_supersample`; kLimitExceeded naming the first of `sides` the
/// capture's width or height passes, for more cells than a crowd holds (HandlePool::kMaxSlots),
/// or for an atlas and capture past ImpostorDesc::max_bytes. The automatic supersampling (0)
/// takes 2 where that passes none of these limits, else 1. `plan->info` is filled before the
/// limits are checked.
Status planImpostor(const BakedPalette& palette, uint32_t sub_meshes, const ImpostorDesc& desc,
                    Span<const ImpostorSide> sides, uint32_t max_supersample, const char* call,
                    ImpostorPlan* plan);

/// The capture: `crowd` initialized with one instance per cell (cell i at column i % columns,
/// row i / columns from the bottom, playing its frame held, seen from its view direction) and
/// updated with `*camera`, the orthographic camera over the whole grid (its viewport the atlas's
/// height in texels).
Status makeCaptureCrowd(const ImpostorPlan& plan, const BakedPalette& palette, uint32_t sub_meshes,
                        CrowdManager* crowd, Camera* camera);

/// The impostor shaders' u_viewer for `camera`: its back direction (row 2 of its view rotation)
/// and 1 when it is orthographic (every view ray parallel: a projection whose last row is
/// (0, 0, 0, 1)), else 0.
glm::vec4 impostorViewer(const Camera& camera);

/// `plan`'s grid for an atlas of a character baked as `palette`.
ImpostorGrid impostorGrid(const ImpostorPlan& plan, const BakedPalette& palette);

/// The impostor shaders' clip table (impostor_quad.glsl's SiImpostorClips): `plan.clips`, then
/// `rects` (every cell's covered rectangle at every mip level, cell c's level l at c * levels +
/// l), padded to whole 16-byte words.
std::vector<uint32_t> impostorClipTable(const ImpostorPlan& plan,
                                        const std::vector<uint32_t>& rects);

}  // namespace si::detail
