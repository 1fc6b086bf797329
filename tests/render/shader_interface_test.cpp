// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The C++ structs and their GLSL twins agree: GL's program introspection gives the offset of
// every field of the instance record (uniform block and storage buffer) and of the GPU-driven
// crowd state, as each program the renderer builds sees it, and each must equal the C++
// offsetof. The structs' static_asserts pin the C++ side; this pins the GLSL side.
#include <glad/gl.h>

#include <cstddef>

#include "gl/programs/program_set.h"
#include "render/render_fixture.h"
#include "si/crowd/gpu_crowd_state.h"

namespace si {
namespace {

using namespace test;
using detail::ProgramId;

// GL_OFFSET of `name` in `program`'s `interface`; -1 when it is not an active resource.
GLint offsetOf(GLuint program, GLenum interface, const char* name) {
  const GLuint index = glGetProgramResourceIndex(program, interface, name);
  if (index == GL_INVALID_INDEX) return -1;
  const GLenum prop = GL_OFFSET;
  GLint value = -1;
  glGetProgramResourceiv(program, interface, index, 1, &prop, 1, nullptr, &value);
  return value;
}

GLint topLevelStride(GLuint program, const char* name) {
  const GLuint index = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, name);
  if (index == GL_INVALID_INDEX) return -1;
  const GLenum prop = GL_TOP_LEVEL_ARRAY_STRIDE;
  GLint value = -1;
  glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &value);
  return value;
}

class ShaderInterface : public RenderTest {
 protected:
  void SetUp() override {
    RenderTest::SetUp();
    if (IsSkipped() || HasFailure()) return;
    detail::ShaderConfig config;
    config.max_instances = 819;
    config.max_joints = 1024;
    const Status s = programs_.build(config);
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  void TearDown() override {
    if (context_) programs_.release();
  }
  detail::ProgramSet programs_;
};

TEST_P(ShaderInterface, InstanceRecordMatchesTheCppStruct) {
  // The uniform block (std140) of the vertex-shader path.
  const GLuint skinned = programs_[ProgramId::kSkinned].id;
  EXPECT_EQ(offsetOf(skinned, GL_UNIFORM, "si_instances[0].world_rows[0]"),
            GLint(offsetof(InstanceRecord, world_rows)));
  EXPECT_EQ(offsetOf(skinned, GL_UNIFORM, "si_instances[0].frames"),
            GLint(offsetof(InstanceRecord, frames)));
  EXPECT_EQ(offsetOf(skinned, GL_UNIFORM, "si_instances[0].blend"),
            GLint(offsetof(InstanceRecord, blend)));
  EXPECT_EQ(offsetOf(skinned, GL_UNIFORM, "si_instances[1].world_rows[0]"),
            GLint(sizeof(InstanceRecord)));
  // The storage buffers (std430) the GPU-driven passes write and the draw reads.
  const GLuint cull = programs_[ProgramId::kCull].id;
  EXPECT_EQ(topLevelStride(cull, "si_records[0].frames"), GLint(sizeof(InstanceRecord)));
  EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, "si_records[0].frames"),
            GLint(offsetof(InstanceRecord, frames)));
  EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, "si_records[0].blend"),
            GLint(offsetof(InstanceRecord, blend)));
  const GLuint drawn = programs_[ProgramId::kGpuDrivenSkinned].id;
  EXPECT_EQ(topLevelStride(drawn, "si_records[0].blend"), GLint(sizeof(InstanceRecord)));
}

TEST_P(ShaderInterface, GpuCrowdStateMatchesTheCppStructs) {
  const GLuint cull = programs_[ProgramId::kCull].id;
  struct Field {
    const char* glsl;
    size_t offset;
  };
  const Field instance_fields[] = {
      {"si_state[0].px", offsetof(GpuInstanceState, position)},
      {"si_state[0].placement", offsetof(GpuInstanceState, placement)},
      {"si_state[0].live_pose", offsetof(GpuInstanceState, live_pose)},
      {"si_state[0].rotation", offsetof(GpuInstanceState, rotation)},
      {"si_state[0].scale", offsetof(GpuInstanceState, scale)},
      {"si_state[0].color", offsetof(GpuInstanceState, color)},
      {"si_state[0].mask", offsetof(GpuInstanceState, variation_mask)},
      {"si_state[0].lod", offsetof(GpuInstanceState, lod)},
      {"si_state[0].start_clock", offsetof(GpuInstanceState, start_clock)},
      {"si_state[0].start_time", offsetof(GpuInstanceState, start_time)},
      {"si_state[0].clip", offsetof(GpuInstanceState, clip)},
      {"si_state[0].loop", offsetof(GpuInstanceState, loop)},
      {"si_state[0].speed", offsetof(GpuInstanceState, speed)},
      {"si_state[0].fading", offsetof(GpuInstanceState, fading)},
      {"si_state[0].fade_start", offsetof(GpuInstanceState, fade_start)},
      {"si_state[0].fade_duration", offsetof(GpuInstanceState, fade_duration)},
      {"si_state[0].from_start_clock", offsetof(GpuInstanceState, from_start_clock)},
      {"si_state[0].from_start_time", offsetof(GpuInstanceState, from_start_time)},
      {"si_state[0].from_clip", offsetof(GpuInstanceState, from_clip)},
      {"si_state[0].from_loop", offsetof(GpuInstanceState, from_loop)},
      {"si_state[0].from_speed", offsetof(GpuInstanceState, from_speed)},
      {"si_state[0].handle", offsetof(GpuInstanceState, handle)},
  };
  for (const Field& f : instance_fields)
    EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, f.glsl), GLint(f.offset)) << f.glsl;
  EXPECT_EQ(topLevelStride(cull, "si_state[0].px"), GLint(sizeof(GpuInstanceState)));
  const Field clip_fields[] = {
      {"si_clips[0].duration", offsetof(GpuClipInfo, duration)},
      {"si_clips[0].inv_duration", offsetof(GpuClipInfo, inv_duration)},
      {"si_clips[0].interval", offsetof(GpuClipInfo, interval)},
      {"si_clips[0].inv_interval", offsetof(GpuClipInfo, inv_interval)},
      {"si_clips[0].sphere", offsetof(GpuClipInfo, sphere)},
      {"si_clips[0].first_texel", offsetof(GpuClipInfo, first_texel)},
      {"si_clips[0].last_interval", offsetof(GpuClipInfo, last_interval)},
      {"si_clips[0].uniform_grid", offsetof(GpuClipInfo, uniform_grid)},
      {"si_clips[0].frame_count", offsetof(GpuClipInfo, frame_count)},
      {"si_clips[0].times_offset", offsetof(GpuClipInfo, times_offset)},
      {"si_clips[0].box_min", offsetof(GpuClipInfo, box_min)},
      {"si_clips[0].box_max", offsetof(GpuClipInfo, box_max)},
  };
  for (const Field& f : clip_fields)
    EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, f.glsl), GLint(f.offset)) << f.glsl;
  EXPECT_EQ(topLevelStride(cull, "si_clips[0].duration"), GLint(sizeof(GpuClipInfo)));
  const Field overlay_fields[] = {
      {"si_overlays[0].start_clock", offsetof(GpuOverlayState, start_clock)},
      {"si_overlays[0].start_time", offsetof(GpuOverlayState, start_time)},
      {"si_overlays[0].fade_start", offsetof(GpuOverlayState, fade_start)},
      {"si_overlays[0].fade_duration", offsetof(GpuOverlayState, fade_duration)},
      {"si_overlays[0].clip", offsetof(GpuOverlayState, clip)},
      {"si_overlays[0].loop", offsetof(GpuOverlayState, loop)},
      {"si_overlays[0].speed", offsetof(GpuOverlayState, speed)},
      {"si_overlays[0].mask", offsetof(GpuOverlayState, mask)},
      {"si_overlays[0].weight_from", offsetof(GpuOverlayState, weight_from)},
      {"si_overlays[0].weight_to", offsetof(GpuOverlayState, weight_to)},
      {"si_overlays[0].playing", offsetof(GpuOverlayState, active)},
  };
  for (const Field& f : overlay_fields)
    EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, f.glsl), GLint(f.offset)) << f.glsl;
  EXPECT_EQ(topLevelStride(cull, "si_overlays[0].start_clock"), GLint(sizeof(GpuOverlayState)));
  const Field live_fields[] = {
      {"si_live_poses[0].fade_start", offsetof(GpuLivePose, fade_start)},
      {"si_live_poses[0].fade_duration", offsetof(GpuLivePose, fade_duration)},
      {"si_live_poses[0].weight_from", offsetof(GpuLivePose, weight_from)},
      {"si_live_poses[0].weight_to", offsetof(GpuLivePose, weight_to)},
      {"si_live_poses[0].first_texel", offsetof(GpuLivePose, first_texel)},
      {"si_live_poses[0].bounded", offsetof(GpuLivePose, bounded)},
      {"si_live_poses[0].sphere", offsetof(GpuLivePose, sphere)},
      {"si_live_poses[0].box_min", offsetof(GpuLivePose, box_min)},
      {"si_live_poses[0].box_max", offsetof(GpuLivePose, box_max)},
  };
  for (const Field& f : live_fields)
    EXPECT_EQ(offsetOf(cull, GL_BUFFER_VARIABLE, f.glsl), GLint(f.offset)) << f.glsl;
  EXPECT_EQ(topLevelStride(cull, "si_live_poses[0].fade_start"), GLint(sizeof(GpuLivePose)));
}

INSTANTIATE_TEST_SUITE_P(Backends, ShaderInterface, test::allBackends(), test::backendTestName);

}  // namespace
}  // namespace si
