// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The layouts C++ and GLSL share, checked when this file compiles: each C++ struct against the
// std430 offsets computed from its GLSL twin's declaration (cmake/glsl_layouts.cmake writes
// si_gl/glsl_layouts.h at build time). A field added, moved or resized on one side only fails
// the build here, naming the field. GL introspection checks the same at run time, per program
// (tests/render/shader_interface_test.cpp).
#include <cstddef>

#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/instance_record.h"
#include "si_gl/glsl_layouts.h"

namespace si::detail {
namespace {

namespace glsl = glsl_layout;

#define SI_SAME_OFFSET(cpp_struct, cpp_field, glsl_struct, glsl_field)            \
  static_assert(offsetof(cpp_struct, cpp_field) == glsl::glsl_struct::glsl_field, \
                #cpp_struct "::" #cpp_field " is not where " #glsl_struct "." #glsl_field " is")
#define SI_SAME_SIZE(cpp_struct, glsl_struct)                   \
  static_assert(sizeof(cpp_struct) == glsl::glsl_struct::kSize, \
                #cpp_struct " and " #glsl_struct " differ in size")

// The instance record: std140 in uniform blocks, std430 in storage buffers, the same bytes.
SI_SAME_SIZE(InstanceRecord, SiInstance);
static_assert(glsl::SiInstance::kStd140Same, "SiInstance must lay out alike in std140");
SI_SAME_OFFSET(InstanceRecord, world_rows, SiInstance, world_rows);
SI_SAME_OFFSET(InstanceRecord, frames, SiInstance, frames);
SI_SAME_OFFSET(InstanceRecord, blend, SiInstance, blend);

// The GPU-driven crowd state.
SI_SAME_SIZE(GpuInstanceState, SiGpuInstance);
SI_SAME_OFFSET(GpuInstanceState, position, SiGpuInstance, px);
static_assert(glsl::SiGpuInstance::py == glsl::SiGpuInstance::px + sizeof(double) &&
                  glsl::SiGpuInstance::pz == glsl::SiGpuInstance::py + sizeof(double),
              "SiGpuInstance's px, py, pz are GpuInstanceState::position[3]");
SI_SAME_OFFSET(GpuInstanceState, placement, SiGpuInstance, placement);
SI_SAME_OFFSET(GpuInstanceState, live_pose, SiGpuInstance, live_pose);
SI_SAME_OFFSET(GpuInstanceState, rotation, SiGpuInstance, rotation);
SI_SAME_OFFSET(GpuInstanceState, scale, SiGpuInstance, scale);
SI_SAME_OFFSET(GpuInstanceState, color, SiGpuInstance, color);
SI_SAME_OFFSET(GpuInstanceState, variation_mask, SiGpuInstance, mask);
SI_SAME_OFFSET(GpuInstanceState, lod, SiGpuInstance, lod);
SI_SAME_OFFSET(GpuInstanceState, start_clock, SiGpuInstance, start_clock);
SI_SAME_OFFSET(GpuInstanceState, start_time, SiGpuInstance, start_time);
SI_SAME_OFFSET(GpuInstanceState, clip, SiGpuInstance, clip);
SI_SAME_OFFSET(GpuInstanceState, loop, SiGpuInstance, loop);
SI_SAME_OFFSET(GpuInstanceState, speed, SiGpuInstance, speed);
SI_SAME_OFFSET(GpuInstanceState, fading, SiGpuInstance, fading);
SI_SAME_OFFSET(GpuInstanceState, fade_start, SiGpuInstance, fade_start);
SI_SAME_OFFSET(GpuInstanceState, fade_duration, SiGpuInstance, fade_duration);
SI_SAME_OFFSET(GpuInstanceState, from_start_clock, SiGpuInstance, from_start_clock);
SI_SAME_OFFSET(GpuInstanceState, from_start_time, SiGpuInstance, from_start_time);
SI_SAME_OFFSET(GpuInstanceState, from_clip, SiGpuInstance, from_clip);
SI_SAME_OFFSET(GpuInstanceState, from_loop, SiGpuInstance, from_loop);
SI_SAME_OFFSET(GpuInstanceState, from_speed, SiGpuInstance, from_speed);
SI_SAME_OFFSET(GpuInstanceState, handle, SiGpuInstance, handle);

SI_SAME_SIZE(GpuOverlayState, SiGpuOverlay);
SI_SAME_OFFSET(GpuOverlayState, start_clock, SiGpuOverlay, start_clock);
SI_SAME_OFFSET(GpuOverlayState, start_time, SiGpuOverlay, start_time);
SI_SAME_OFFSET(GpuOverlayState, fade_start, SiGpuOverlay, fade_start);
SI_SAME_OFFSET(GpuOverlayState, fade_duration, SiGpuOverlay, fade_duration);
SI_SAME_OFFSET(GpuOverlayState, clip, SiGpuOverlay, clip);
SI_SAME_OFFSET(GpuOverlayState, loop, SiGpuOverlay, loop);
SI_SAME_OFFSET(GpuOverlayState, speed, SiGpuOverlay, speed);
SI_SAME_OFFSET(GpuOverlayState, mask, SiGpuOverlay, mask);
SI_SAME_OFFSET(GpuOverlayState, weight_from, SiGpuOverlay, weight_from);
SI_SAME_OFFSET(GpuOverlayState, weight_to, SiGpuOverlay, weight_to);
SI_SAME_OFFSET(GpuOverlayState, active, SiGpuOverlay, playing);

SI_SAME_SIZE(GpuLivePose, SiGpuLivePose);
SI_SAME_OFFSET(GpuLivePose, fade_start, SiGpuLivePose, fade_start);
SI_SAME_OFFSET(GpuLivePose, fade_duration, SiGpuLivePose, fade_duration);
SI_SAME_OFFSET(GpuLivePose, weight_from, SiGpuLivePose, weight_from);
SI_SAME_OFFSET(GpuLivePose, weight_to, SiGpuLivePose, weight_to);
SI_SAME_OFFSET(GpuLivePose, first_texel, SiGpuLivePose, first_texel);
SI_SAME_OFFSET(GpuLivePose, bounded, SiGpuLivePose, bounded);
SI_SAME_OFFSET(GpuLivePose, sphere, SiGpuLivePose, sphere);
SI_SAME_OFFSET(GpuLivePose, box_min, SiGpuLivePose, box_min);
SI_SAME_OFFSET(GpuLivePose, box_max, SiGpuLivePose, box_max);

SI_SAME_SIZE(GpuClipInfo, SiGpuClip);
SI_SAME_OFFSET(GpuClipInfo, duration, SiGpuClip, duration);
SI_SAME_OFFSET(GpuClipInfo, inv_duration, SiGpuClip, inv_duration);
SI_SAME_OFFSET(GpuClipInfo, interval, SiGpuClip, interval);
SI_SAME_OFFSET(GpuClipInfo, inv_interval, SiGpuClip, inv_interval);
SI_SAME_OFFSET(GpuClipInfo, sphere, SiGpuClip, sphere);
SI_SAME_OFFSET(GpuClipInfo, first_texel, SiGpuClip, first_texel);
SI_SAME_OFFSET(GpuClipInfo, last_interval, SiGpuClip, last_interval);
SI_SAME_OFFSET(GpuClipInfo, uniform_grid, SiGpuClip, uniform_grid);
SI_SAME_OFFSET(GpuClipInfo, frame_count, SiGpuClip, frame_count);
SI_SAME_OFFSET(GpuClipInfo, times_offset, SiGpuClip, times_offset);
SI_SAME_OFFSET(GpuClipInfo, modes_offset, SiGpuClip, modes_offset);
SI_SAME_OFFSET(GpuClipInfo, box_min, SiGpuClip, box_min);
SI_SAME_OFFSET(GpuClipInfo, box_max, SiGpuClip, box_max);

#undef SI_SAME_OFFSET
#undef SI_SAME_SIZE

}  // namespace
}  // namespace si::detail
