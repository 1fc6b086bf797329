// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The crowd's state as GPU-driven culling reads it (std430). C++ twins: si::GpuInstanceState,
// si::GpuOverlayState, si::GpuLivePose and si::GpuClipInfo (include/si/crowd/gpu_crowd_state.h); the build
// checks the layouts (src/gl/shader_layouts.cpp), the render tests by GL introspection.
#ifndef SI_GPU_CROWD_STATE_GLSL
#define SI_GPU_CROWD_STATE_GLSL
struct SiGpuInstance {
  double px, py, pz;
  uint placement, live_pose;
  vec4 rotation;
  float scale; uint color; uint mask; uint lod;
  double start_clock, start_time;
  uint clip, loop; float speed; uint fading;
  double fade_start, fade_duration;
  double from_start_clock, from_start_time;
  uint from_clip, from_loop; float from_speed; uint handle;
};
struct SiGpuOverlay {
  double start_clock, start_time, fade_start, fade_duration;
  uint clip, loop; float speed; uint mask;
  float weight_from, weight_to; uint playing, pad;
};
struct SiGpuLivePose {
  double fade_start, fade_duration;
  float weight_from, weight_to;
  uint first_texel, bounded;
  vec4 sphere, box_min, box_max;
};
struct SiGpuClip {
  double duration, inv_duration, interval, inv_interval;
  vec4 sphere;
  uint first_texel, last_interval, uniform_grid, frame_count;
  uint times_offset, modes_offset, pad1, pad2;
  vec4 box_min, box_max;
};
#endif
