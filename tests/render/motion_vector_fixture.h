// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The motion vector render tests' fixture (motion_vectors_render_test.cpp, and the GPU-driven
// path's in gpu_driven_motion_render_test.cpp): a crowd of 16 distinct tints over frames with a
// moving camera, an engine's own program on the public include that draws each vertex at its
// previous position, and the renderer's motion target read back.
#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "gl/programs/program_set.h"
#include "gl/resources/palette_texture.h"
#include "render/render_fixture.h"
#include "si/core/shader_inputs.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/motion_target.h"
#include "si/gl/skinning_glsl.h"

namespace si::test {

// The fixture's instance k's tint (distinct for its 16 instances): how a failure names it.
inline glm::u8vec3 tintOf(int k) {
  return glm::u8vec3(uint8_t(40 + 13 * k), uint8_t(230 - 11 * k), uint8_t(60 + 37 * (k % 5)));
}

// The engine's shaders. Mode 0 draws each vertex where it is now (current camera), mode 1
// where it was drawn in the previous frame (previous camera); both write the flat tint and the
// motion, as the renderer defines it, to outputs 0 and 1.
inline constexpr const char* kEngineVertex = R"(
layout(location = 0) in vec3 a_position;
layout(location = 3) in uvec4 a_joints;
layout(location = 4) in vec4 a_weights;
uniform mat4 u_current;
uniform mat4 u_previous;
uniform int u_draw_previous;
out vec4 v_current;
out vec4 v_previous;
flat out uint v_color;
void main() {
  SiInstance inst = si_instances[gl_InstanceID];
  vec4 m0, m1, m2;
  siSkin(inst, a_joints, a_weights, m0, m1, m2);
  vec3 world = siTransformPoint(inst.world_rows[0], inst.world_rows[1], inst.world_rows[2],
                                siTransformPoint(m0, m1, m2, a_position));
  v_current = u_current * vec4(world, 1.0);
  v_previous = u_previous * vec4(siSkinPrevious(uint(gl_InstanceID), a_joints, a_weights, a_position), 1.0);
  v_color = inst.blend.w;
  gl_Position = u_draw_previous != 0 ? v_previous : v_current;
}
)";
inline constexpr const char* kEngineFragment = R"(#version 450 core
in vec4 v_current;
in vec4 v_previous;
flat in uint v_color;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec2 o_motion;
void main() {
  o_color = vec4(unpackUnorm4x8(v_color).rgb, 1.0);
  o_motion = 0.5 * (v_current.xy / v_current.w - v_previous.xy / v_previous.w);
}
)";

// The library's own compile step (the driver's log in the failure).
inline GLuint compile(GLenum type, const std::string& text) {
  GLuint shader = 0;
  const Status s = detail::compileShader(type, text, "engine", &shader);
  EXPECT_TRUE(s.isOk()) << s.toString();
  return shader;
}

class MotionVectorTest : public RenderTest {
 protected:
  void SetUp() override {
    RenderTest::SetUp();
    if (IsSkipped() || HasFailure()) return;
    const Status made = target_.create(kSize, kSize);
    ASSERT_TRUE(made.isOk()) << made.toString();
    target_.bind();
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = 1;  // The same triangles in both frames: images compare exactly.
    cd.previous_records = true;
    ASSERT_TRUE(crowd_.init(cd).isOk());
    const uint32_t clips = uint32_t(palette().clips.size());
    for (int k = 0; k < 16; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k % 4 - 1.5) * 1.3, 0.0, -3.0 - 1.6 * (k / 4));
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.13 * k;
      d.speed = 1.0f + 0.1f * float(k % 3);
      d.color = glm::u8vec4(tintOf(k), 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd_.add(d, &h).isOk());
      handles_.push_back(h);
    }
    ASSERT_TRUE(crowd_.update(0.05, camera(0)).isOk());
    for (size_t k = 0; k < handles_.size(); k += 3)  // Crossfading through frame N.
      ASSERT_TRUE(crowd_.crossfade(handles_[k], (uint32_t(k) + 1) % clips, 0.4).isOk());
  }
  void TearDown() override {
    if (context_) {
      target_.restore();
      target_.release();
    }
  }

  // The camera of frame `f`: moving sideways and turning.
  static Camera camera(int f) {
    return Camera::lookAt({0.3 * f, 1.6, 2.5 - 0.2 * f}, {0.1 * f, 0.9, -5.0},
                          glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 100.0f);
  }
  // Frame N+1 after frame N: new crossfades, a cut and a speed change between them.
  void nextFrame() {
    const uint32_t clips = uint32_t(palette().clips.size());
    for (size_t k = 1; k < handles_.size(); k += 4)
      ASSERT_TRUE(crowd_.crossfade(handles_[k], (uint32_t(k) + 2) % clips, 0.3).isOk());
    ASSERT_TRUE(crowd_.play(handles_[0], 0, 0.5, 1.0f).isOk());  // A cut, mid-crossfade.
    ASSERT_TRUE(crowd_.play(handles_[2], 2 % clips, 0.2, 2.5f).isOk());
    ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(2)).isOk());
  }

  // Draws the crowd's last update with the engine's program (mode 1: previous positions).
  void drawEngine(bool previous) {
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init({65536, 256, 0}).isOk());
    const uint32_t capacity = batcher.capacityPerDraw();
    std::string vs = "#version 450 core\n#define SI_MAX_INSTANCES " + std::to_string(capacity) +
                     "\n#define SI_PREVIOUS_RECORDS\n" + skinningGlsl() + kEngineVertex;
    const GLuint program = glCreateProgram();
    const GLuint v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, kEngineFragment);
    glAttachShader(program, v);
    glAttachShader(program, f);
    glLinkProgram(program);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    ASSERT_TRUE(linked);

    const size_t slack = size_t(capacity) * kInstanceRecordSize;
    std::vector<uint8_t> current(batcher.recordBufferBound(crowd_.view()) + slack),
        prior(current.size());
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(batcher.build(crowd_.view(), current, &draws).isOk());
    ASSERT_TRUE(batcher.buildPrevious(crowd_.view(), prior).isOk());
    VertexStream stream;
    ASSERT_TRUE(buildVertexStream(character().mesh, palette(), &stream).isOk());
    GLuint buffers[4];
    glCreateBuffers(4, buffers);
    glNamedBufferStorage(buffers[0], GLsizeiptr(stream.bytes.size()), stream.bytes.data(), 0);
    const std::vector<uint32_t>& indices = character().mesh.indices;
    glNamedBufferStorage(buffers[1], GLsizeiptr(indices.size() * 4), indices.data(), 0);
    glNamedBufferStorage(buffers[2], GLsizeiptr(current.size()), current.data(), 0);
    glNamedBufferStorage(buffers[3], GLsizeiptr(prior.size()), prior.data(), 0);
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, buffers[0], 0, GLsizei(stream.stride_bytes));
    glVertexArrayElementBuffer(vao, buffers[1]);
    for (GLuint loc : {0u, 3u, 4u}) {
      glEnableVertexArrayAttrib(vao, loc);
      glVertexArrayAttribBinding(vao, loc, 0);
    }
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, VertexStream::kPositionOffset);
    glVertexArrayAttribIFormat(vao, 3, 4, stream.wide_joints ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE,
                               VertexStream::kJointsOffset);
    glVertexArrayAttribFormat(vao, 4, 4, GL_UNSIGNED_SHORT, GL_TRUE, stream.weights_offset);
    detail::PaletteTexture texture;
    ASSERT_TRUE(texture.upload(palette(), info_).isOk());

    glUseProgram(program);
    glBindVertexArray(vao);
    texture.bind();  // The palette at unit 0, its info block at uniform binding 4.
    const glm::mat4 now = crowd_.view().camera().viewProjection();
    const glm::mat4 then = crowd_.view().previousCamera().viewProjection();
    glUniformMatrix4fv(glGetUniformLocation(program, "u_current"), 1, GL_FALSE, &now[0][0]);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_previous"), 1, GL_FALSE, &then[0][0]);
    glUniform1i(glGetUniformLocation(program, "u_draw_previous"), previous ? 1 : 0);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    for (const DrawBatch& d : draws) {
      const IndexRange range = character().mesh.sub_meshes[d.sub_mesh].lods[d.lod];
      glBindBufferRange(GL_UNIFORM_BUFFER, 0, buffers[2], d.byte_offset, GLsizeiptr(slack));
      glBindBufferRange(GL_UNIFORM_BUFFER, 1, buffers[3], d.byte_offset, GLsizeiptr(slack));
      glDrawElementsInstanced(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                              reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4),
                              GLsizei(d.instance_count));
    }
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    texture.release();
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(4, buffers);
    glDeleteProgram(program);
  }

  // A renderer on skinning path `path` (vertex-shader by default) with motion vectors on.
  void makeMotionRenderer(Renderer* r, SkinningPath path = SkinningPath::kVertexShader) {
    RendererDesc rd;
    rd.motion_vectors = true;
    rd.skinning_path = path;
    makeRenderer(r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  }

  // Which instances (by their tint in the engine's image) drew motion more than 1e-4 off `expected`, with the mean
  // motion drawn and expected there: what a failure says.
  std::string offByInstance(const std::vector<uint8_t>& color, const std::vector<glm::vec2>& motion,
                            const std::vector<glm::vec2>& expected, const std::vector<float>& depth,
                            const std::vector<float>& expected_depth) const {
    std::string out;
    for (size_t i = 0; i < handles_.size(); ++i) {
      const int k = int(i);
      const glm::u8vec3 tint = tintOf(k);
      size_t off = 0;
      glm::vec2 drawn(0.0f), wanted(0.0f);
      for (size_t p = 0; p < motion.size(); ++p) {
        if (depth[p] >= 1.0f || expected_depth[p] >= 1.0f) continue;
        if (glm::u8vec3(color[4 * p], color[4 * p + 1], color[4 * p + 2]) != tint) continue;
        if (glm::length(motion[p] - expected[p]) <= 1e-4f) continue;
        ++off;
        drawn += motion[p];
        wanted += expected[p];
      }
      if (off == 0) continue;
      char line[160];
      std::snprintf(line, sizeof line, "instance %d: %zu pixels off, mean drawn (%.5f, %.5f), expected (%.5f, %.5f)\n",
                    k, off, drawn.x / float(off), drawn.y / float(off), wanted.x / float(off), wanted.y / float(off));
      out += line;
    }
    return out;
  }

  // Expects `motion` (drawn with `depth`) within 1e-4 of the expected motion on 99.5 % of the
  // pixels both images drew, and those a twentieth of the image; a failure names the instances
  // off (by their tint in `expected_color`).
  void expectMotion(const std::vector<glm::vec2>& motion, const std::vector<float>& depth,
                    const std::vector<glm::vec2>& expected,
                    const std::vector<float>& expected_depth,
                    const std::vector<uint8_t>& expected_color) const {
    size_t compared = 0, close = 0;
    for (size_t p = 0; p < expected.size(); ++p) {
      if (expected_depth[p] >= 1.0f || depth[p] >= 1.0f) continue;
      ++compared;
      close += glm::length(motion[p] - expected[p]) <= 1e-4f;
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 20);
    EXPECT_GE(double(close), 0.995 * double(compared))
        << offByInstance(expected_color, motion, expected, depth, expected_depth);
  }

  MotionTarget target_;

  std::vector<uint8_t> colors() {
    std::vector<uint8_t> out;
    const Status s = target_.readColor(&out);
    EXPECT_TRUE(s.isOk()) << s.toString();
    return out;
  }
  std::vector<glm::vec2> motions() {
    std::vector<glm::vec2> out;
    const Status s = target_.readMotion(&out);
    EXPECT_TRUE(s.isOk()) << s.toString();
    return out;
  }
  std::vector<float> depths() {
    std::vector<float> out;
    EXPECT_TRUE(target_.readDepth(&out).isOk());
    return out;
  }
  CrowdManager crowd_;
  std::vector<InstanceHandle> handles_;
};

inline size_t differingPixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  size_t n = 0;
  for (size_t p = 0; p < a.size(); p += 4) n += std::memcmp(&a[p], &b[p], 4) != 0;
  return n;
}

}  // namespace si::test
