// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The crowd's state as GPU-driven culling (si::gl, Renderer::drawCrowdGpuCulled) reads it:
/// std430 structs (their GLSL twins are in src/gl/shaders/gpu_crowd_state.glsl; the build
/// checks the layouts against them, src/gl/shader_layouts.cpp, and the render tests by GL
/// introspection), and the per-frame selection parameters.
/// Plain data, no GL: si::CrowdExport (crowd_export.h) exports it.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace si {

/// A run of dense instance indices [first, first + count) (CrowdExport::changedSince).
struct DenseRange {
  uint32_t first = 0;
  uint32_t count = 0;
};

/// One instance (std430, 144 bytes; array stride 144).
struct GpuInstanceState {
  double position[3];         ///< World position (double, as the crowd keeps it).
  /// Teleports: CrowdManager::setTransform() calls so far. The GPU-driven path draws no object
  /// motion for an instance whose placement differs from the one drawn in the previous frame.
  uint32_t placement;
  /// Live poses (CrowdManager::setLivePose): the slot of CrowdExport::livePoses() whose pose
  /// the instance draws, or kGpuNoLivePose. While the slot's live weight is 1 its record names
  /// the slot's frame alone; between 0 and 1 the frame as clip A and the playback below as
  /// clip B at the weight 1 - live weight; at 0 the playback alone.
  uint32_t live_pose;
  float rotation[4];          ///< Quaternion x, y, z, w.
  float scale;
  uint32_t color;             ///< The appearance word (si::packAppearance).
  uint32_t variation_mask;
  uint32_t lod;               ///< The LOD hysteresis starts from.
  double start_clock, start_time;  ///< Current playback: crowd clock and clip time at start,
  uint32_t clip, loop;             ///< clip and si::LoopMode (kLoop or kOnce, resolved),
  float speed;
  uint32_t fading;                 ///< 1 while a crossfade from the `from_` playback runs.
  double fade_start, fade_duration;
  double from_start_clock, from_start_time;
  uint32_t from_clip, from_loop;
  float from_speed;
  /// The instance's InstanceHandle::id: the GPU-driven path keys what it drew last frame by it
  /// (motion vectors), so dense indices may change between frames.
  uint32_t handle;
};
static_assert(sizeof(GpuInstanceState) == 144, "std430 layout");

/// GpuInstanceState::live_pose of an instance without a live pose.
inline constexpr uint32_t kGpuNoLivePose = 0xFFFFFFFFu;

/// One live pose slot (std430, 80 bytes; CrowdExport::livePoses): where its current frame is,
/// its hand-over and what bounds its pose. The live weight fades linearly from `weight_from` to
/// `weight_to` over [fade_start, fade_start + fade_duration) of the crowd clock and is
/// `weight_to` from then on (at once for a duration of 0), as CrowdManager::setLivePose and
/// clearLivePose set it.
struct GpuLivePose {
  double fade_start, fade_duration;
  float weight_from, weight_to;
  /// The first texel of the slot's current frame, in the palette texture after the palette's
  /// own texels (CrowdExport::livePoseFirstTexel): what a record names as a frame.
  uint32_t first_texel;
  /// 1 when `sphere` and the box bound the current pose (the palette has joint bounds,
  /// BakedPalette::joint_bounds), else 0: the instance's clip bounds it alone.
  uint32_t bounded;
  /// The pose's bounds in the instance's model space, culled as a second clip's (a clip faded
  /// from): the sphere (centre xyz, radius in w) and the box (xyz; w 0).
  float sphere[4];
  float box_min[4], box_max[4];
};
static_assert(sizeof(GpuLivePose) == 80, "std430 layout");

/// One instance's overlay (layered animation; std430, 64 bytes): CrowdManager's overlay state,
/// from which the GPU writes the layer record at the crowd's clock as update() does.
struct GpuOverlayState {
  double start_clock, start_time;    ///< The overlay's playback: crowd clock and clip time at
  double fade_start, fade_duration;  ///< start; its weight fades over this span of the clock
  uint32_t clip, loop;               ///< clip and si::LoopMode,
  float speed;
  uint32_t mask;                     ///< the crowd's mask index,
  float weight_from, weight_to;      ///< from this weight to that one;
  uint32_t active;                   ///< 0: none played (a zero layer record).
  uint32_t pad;
};
static_assert(sizeof(GpuOverlayState) == 64, "std430 layout");

/// One clip (std430, 80 bytes).
struct GpuClipInfo {
  double duration, inv_duration, interval, inv_interval;
  float sphere[4];            ///< Bounding sphere centre (model units) and radius.
  uint32_t first_texel, last_interval;
  uint32_t uniform_grid;      ///< 1: frames on a uniform grid; 0: search frame_times.
  uint32_t frame_count;
  uint32_t times_offset;      ///< Into the frame-times array (doubles), for non-uniform clips.
  /// For a cubic clip, where its interval modes (si::IntervalMode values, one per interval,
  /// each stored as a double) start in the same array; 0xFFFFFFFF for a linear clip.
  uint32_t modes_offset;
  uint32_t pad[2];
  float box_min[4];           ///< The clip's bounding box (model units; w unused): tighter
  float box_max[4];           ///< than the sphere for occlusion culling.
};
static_assert(sizeof(GpuClipInfo) == 112, "std430 layout");

/// One frame's selection parameters (see src/crowd/cull_math.h for the arithmetic).
struct CullParams {
  std::array<glm::vec4, 6> planes{};  ///< Camera::frustumPlanes(), camera-relative.
  float radius = 1.0f;                ///< Character radius (model units).
  float max_distance_radii = 100.0f;  ///< Negative: no far line.
  float hysteresis = 0.05f;
  uint32_t lod_count = 1;
  float lod_lines[7] = {};            ///< In radii, lod_count - 1 of them.
  uint32_t animation_lod_start = 8;   ///< LODs at or past this step their animation,
  double animation_step_seconds = 0.1;  ///< at this interval.
  /// Drawn LODs are this many levels coarser than the hysteresis LOD, clamped to the coarsest
  /// (a view's CrowdViewDesc::lod_bias); animation stepping follows the drawn LOD.
  uint32_t lod_bias = 0;
};

}  // namespace si
