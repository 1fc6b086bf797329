// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Motion vectors, the GL half. An engine's own program built on the public include
// (si_skinning.glsl with SI_PREVIOUS_RECORDS, InstanceBatcher::buildPrevious) draws each vertex
// at its previous position with the previous camera: that image is the previous frame's image,
// pixel for pixel, across crossfades and speed changes. The renderer's motion output (both
// skinning paths, and the GPU-driven path from the records it kept itself) equals what that
// program computes from the same records.
#include <glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <cstring>
#include <string>
#include <memory>

#include "gl/resources/palette_texture.h"
#include "render/render_fixture.h"
#include "si/core/shader_inputs.h"
#include "si/gl/motion_target.h"
#include "si/gl/skinning_glsl.h"

namespace si {
namespace {

// The fixture's instance k's tint (distinct for its 16 instances): how a failure names it.
glm::u8vec3 tintOf(int k) {
  return glm::u8vec3(uint8_t(40 + 13 * k), uint8_t(230 - 11 * k), uint8_t(60 + 37 * (k % 5)));
}

using namespace test;

// The engine's shaders. Mode 0 draws each vertex where it is now (current camera), mode 1
// where it was drawn in the previous frame (previous camera); both write the flat tint and the
// motion, as the renderer defines it, to outputs 0 and 1.
const char* kEngineVertex = R"(
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
const char* kEngineFragment = R"(#version 450 core
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

GLuint compile(GLenum type, const std::string& text) {
  const GLuint s = glCreateShader(type);
  const char* p = text.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    ADD_FAILURE() << log;
  }
  return s;
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
    std::vector<uint8_t> current(batcher.recordBufferBound(crowd_) + slack), prior(current.size());
    std::vector<DrawBatch> draws;
    ASSERT_TRUE(batcher.build(crowd_, current, &draws).isOk());
    ASSERT_TRUE(batcher.buildPrevious(crowd_, prior).isOk());
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
    const glm::mat4 now = crowd_.updateCamera().viewProjection();
    const glm::mat4 then = crowd_.previousUpdateCamera().viewProjection();
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

  // A vertex-shader renderer with motion vectors on.
  void makeMotionRenderer(Renderer* r) {
    RendererDesc rd;
    rd.motion_vectors = true;
    rd.skinning_path = SkinningPath::kVertexShader;
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

size_t differingPixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  size_t n = 0;
  for (size_t p = 0; p < a.size(); p += 4) n += std::memcmp(&a[p], &b[p], 4) != 0;
  return n;
}

// Drawing frame N+1 at each vertex's previous position with frame N's camera gives frame N's
// image exactly; drawing it where it is now does not.
TEST_P(MotionVectorTest, PreviousPositionsDrawTheLastFrame) {
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());  // Frame N.
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<uint8_t> frame_n = colors();
  nextFrame();
  ASSERT_EQ(crowd_.records().size(), handles_.size());  // Every instance in view in both.
  target_.clear(glm::vec4(0.0f));
  drawEngine(true);
  const std::vector<uint8_t> previous = colors();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<uint8_t> frame_n1 = colors();
  size_t covered = 0;
  for (size_t p = 3; p < frame_n.size(); p += 4) covered += frame_n[p] != 0;
  EXPECT_GT(covered, size_t(kSize) * kSize / 10);
  EXPECT_EQ(differingPixels(previous, frame_n), 0u);
  EXPECT_GT(differingPixels(frame_n1, frame_n), covered / 4);  // There was motion.
}

// The renderer's motion output, on both skinning paths, equals the engine program's (the same
// records, the same cameras) where both drew; nothing is written for paths that draw none.
TEST_P(MotionVectorTest, TheRendererWritesTheIncludesMotion) {
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  nextFrame();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  float largest = 0.0f;
  for (const glm::vec2& m : expected) largest = std::max(largest, glm::length(m));
  EXPECT_GT(largest, 0.02f);  // At least 5 pixels somewhere.
  for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
    SCOPED_TRACE(skinningPathName(path));
    RendererDesc rd;
    rd.skinning_path = path;
    rd.motion_vectors = true;
    Renderer r;
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    target_.clear(glm::vec4(0.0f));
    const Status s = r.drawCrowd(crowd_, batcher, crowd_.updateCamera(), nullptr);
    ASSERT_TRUE(s.isOk()) << s.toString();
    const std::vector<glm::vec2> motion = motions();
    const std::vector<float> depth = depths();
    size_t compared = 0, within = 0;
    double worst = 0.0;
    for (size_t p = 0; p < motion.size(); ++p) {
      if (depth[p] >= 1.0f || expected_depth[p] >= 1.0f) continue;  // Drawn by both.
      ++compared;
      const double off = glm::length(motion[p] - expected[p]);
      within += off <= 1e-4;  // 0.026 pixels.
      worst = std::max(worst, off);
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 10);
    // Silhouette pixels may come from another triangle where rounding differs.
    EXPECT_GE(double(within), 0.995 * double(compared)) << "worst " << worst;
    // The target's summary: the drawn pixels and their motion in pixels.
    MotionSummary summary;
    ASSERT_TRUE(target_.summarize(&summary).isOk());
    EXPECT_EQ(summary.drawn_pixels, size_t(std::count_if(depth.begin(), depth.end(),
                                                         [](float z) { return z < 1.0f; })));
    EXPECT_NEAR(summary.max_pixels, double(largest) * kSize, 0.5);
    EXPECT_GT(summary.mean_pixels, 0.5);
    // Motion vectors only from drawCrowd and drawCrowdGpuCulled.
    EXPECT_EQ(r.drawTraditional(crowd_, crowd_.updateCamera(), nullptr).code(),
              StatusCode::kUnsupported);
    EXPECT_EQ(r.drawCpuSkinned(crowd_, crowd_.updateCamera(), nullptr).code(),
              StatusCode::kUnsupported);
    r.setMotionVectors(false);
    EXPECT_FALSE(r.motionVectors());
    EXPECT_TRUE(r.drawCpuSkinned(crowd_, crowd_.updateCamera(), nullptr).isOk());
    r.shutdown();
  }
}

// The GPU-driven path keeps what it drew: its motion, with both of its draws and with occlusion
// culling, equals the engine program's across the same crossfades, cut and speed change (the
// crowd's previous records are not used: it draws the crowd's clock with the draw camera, which
// here is the update camera). With jittered draw cameras, setGpuMotionProjection keeps the
// jitter out of the motion; without it, the jitter shows.
TEST_P(MotionVectorTest, TheGpuDrivenPathKeepsWhatItDrew) {
  // Jitter: each frame's draw camera is moved by a different part of a pixel (as temporal
  // anti-aliasing does); setGpuMotionProjection gives the unjittered projection for the motion.
  enum class Jitter { kNone, kUnjitteredMotion, kInMotion };
  struct Variant {
    DrawMode mode;
    bool occlusion;
    Jitter jitter;
    std::unique_ptr<Renderer> renderer;
  };
  std::vector<Variant> variants;
  const auto add = [&](DrawMode mode, bool occlusion, Jitter jitter) {
    RendererDesc rd;
    rd.motion_vectors = true;
    rd.gpu_occlusion_culling = occlusion;
    rd.gpu_driven_ring_bytes = 4u << 20;  // Plenty for 16 instances.
    rd.skinning_path = SkinningPath::kVertexShader;  // The draws name their mode: no timing.
    variants.push_back({mode, occlusion, jitter, std::make_unique<Renderer>()});
    makeRenderer(variants.back().renderer.get(), 0, PaletteFormat::kMatrix3x4F32, &rd);
  };
  for (const bool occlusion : {false, true})
    for (const DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned})
      add(mode, occlusion, Jitter::kNone);
  add(DrawMode::kComputeSkinned, false, Jitter::kUnjitteredMotion);
  add(DrawMode::kSkinned, false, Jitter::kInMotion);
  const auto draw = [&](Variant& v, int frame) {
    Camera c = camera(frame);
    if (v.jitter == Jitter::kNone) {
      ASSERT_TRUE(v.renderer->drawCrowdGpuCulled(crowd_, c, nullptr, v.mode).isOk());
      return;
    }
    const glm::mat4 unjittered = c.projection;
    const float px = 2.0f / float(kSize);  // One pixel in normalized device coordinates.
    const glm::vec3 shift = frame == 1 ? glm::vec3(0.4f * px, -0.3f * px, 0.0f)
                                       : glm::vec3(-0.35f * px, 0.25f * px, 0.0f);
    c.projection = glm::translate(glm::mat4(1.0f), shift) * c.projection;
    v.renderer->setGpuMotionProjection(v.jitter == Jitter::kUnjitteredMotion ? &unjittered
                                                                             : nullptr);
    ASSERT_TRUE(v.renderer->drawCrowdGpuCulled(crowd_, c, nullptr, v.mode).isOk());
  };
  // Frame N, drawn at its clock with its camera by every variant; then frame N+1.
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  for (Variant& v : variants) {
    target_.clear(glm::vec4(0.0f));
    draw(v, 1);
  }
  nextFrame();
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  for (Variant& v : variants) {
    SCOPED_TRACE(std::string(v.mode == DrawMode::kSkinned ? "vertex shader" : "pre-skinned") +
                 (v.occlusion ? ", occlusion culling" : "") +
                 (v.jitter == Jitter::kUnjitteredMotion ? ", jittered"
                  : v.jitter == Jitter::kInMotion       ? ", jitter in the motion"
                                                        : ""));
    target_.clear(glm::vec4(0.0f));
    draw(v, 2);
    const std::vector<glm::vec2> motion = motions();
    const std::vector<float> depth = depths();
    // A jittered pixel shows a point of the surface up to half a pixel away: its motion is
    // compared with the closest expected motion of the pixel's 3x3 neighbourhood, to 1e-3 (0.26
    // pixels). The jitter itself moves the image 0.93 pixels (3.6e-3) between the frames.
    const int reach = v.jitter == Jitter::kNone ? 0 : 1;
    size_t compared = 0, within = 0;
    double worst = 0.0;
    for (size_t p = 0; p < motion.size(); ++p) {
      if (depth[p] >= 1.0f || expected_depth[p] >= 1.0f) continue;
      ++compared;
      const int x = int(p % kSize), y = int(p / kSize);
      double off = 1e30;
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= int(kSize) || qy >= int(kSize)) continue;
          const size_t q = size_t(qy) * kSize + size_t(qx);
          if (expected_depth[q] < 1.0f)
            off = std::min(off, double(glm::length(motion[p] - expected[q])));
        }
      within += off <= (reach == 0 ? 1e-4 : 1e-3);
      worst = std::max(worst, off);
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 10);
    // Measured: every pixel without jitter; 99.4 % with the unjittered motion projection (the
    // rest where the jitter shows another instance); 0.04 % with the jitter in the motion.
    if (v.jitter == Jitter::kInMotion)
      EXPECT_LT(double(within), 0.01 * double(compared));
    else
      EXPECT_GE(double(within), (reach == 0 ? 0.995 : 0.99) * double(compared)) << "worst " << worst;
  }
  for (Variant& v : variants) v.renderer->shutdown();
}

// What the GPU-driven path drew belongs to its crowd: a crowd re-initialized in place with the
// same handles, drawn at the next clock, gets the fallback (still camera: no motion), not the
// old crowd's records.
TEST_P(MotionVectorTest, AnotherCrowdStartsOverOnTheGpuDrivenPath) {
  Renderer r;
  makeMotionRenderer(&r);
  const auto populate = [&](double x) {
    CrowdDesc cd = crowd_.desc();
    ASSERT_TRUE(crowd_.init(cd).isOk());
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(x + (k % 4 - 1.5) * 1.3, 0.0, -3.0 - 1.6 * (k / 4));
      d.clip = uint32_t(palette().findClip("walk"));
      d.time_seconds = 0.2 * k;
      InstanceHandle h;
      ASSERT_TRUE(crowd_.add(d, &h).isOk());
    }
  };
  populate(0.0);
  ASSERT_TRUE(r.drawCrowdGpuCulled(crowd_, camera(1), nullptr, DrawMode::kSkinned).isOk());
  const uint64_t first = crowd_.identity();
  populate(0.4);  // Same handles, other places and clock 0 again: then the next clock.
  ASSERT_NE(crowd_.identity(), first);
  ASSERT_TRUE(crowd_.advanceClock(1.0 / 30.0).isOk());
  target_.clear(glm::vec4(0.0f));
  ASSERT_TRUE(r.drawCrowdGpuCulled(crowd_, camera(1), nullptr, DrawMode::kSkinned).isOk());
  MotionSummary summary;
  ASSERT_TRUE(target_.summarize(&summary).isOk());
  EXPECT_GT(summary.drawn_pixels, size_t(kSize) * kSize / 20);
  EXPECT_LT(summary.max_pixels, 1e-3);
  // The same crowd's next frame moves (the clips play).
  ASSERT_TRUE(crowd_.advanceClock(1.0 / 30.0).isOk());
  target_.clear(glm::vec4(0.0f));
  ASSERT_TRUE(r.drawCrowdGpuCulled(crowd_, camera(1), nullptr, DrawMode::kSkinned).isOk());
  ASSERT_TRUE(target_.summarize(&summary).isOk());
  EXPECT_GT(summary.max_pixels, 0.5);
  r.shutdown();
}

// A GPU-driven draw without motion vectors (a shadow view) at a frame's clock changes neither
// that frame's camera nor what was drawn: the next frame's motion is the one without it.
TEST_P(MotionVectorTest, ADrawWithoutMotionLeavesTheGpuDrivenFrameAlone) {
  Renderer plain, shadowed;
  makeMotionRenderer(&plain);
  makeMotionRenderer(&shadowed);
  const Camera shadow = Camera::lookAt({6.0, 9.0, -4.0}, {0.0, 0.0, -5.0}, glm::vec3(0, 1, 0),
                                       0.9f, 1.0f, 0.1f, 100.0f);
  std::vector<glm::vec2> motion[2];
  std::vector<float> depth[2];
  for (int frame = 1; frame <= 2; ++frame) {
    if (frame == 2) nextFrame();
    else ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
    for (int k = 0; k < 2; ++k) {
      Renderer& r = k == 0 ? plain : shadowed;
      target_.clear(glm::vec4(0.0f));
      ASSERT_TRUE(r.drawCrowdGpuCulled(crowd_, camera(frame), nullptr, DrawMode::kSkinned).isOk());
      if (frame == 2) motion[k] = motions(), depth[k] = depths();
      if (k == 1) {  // The shadow view, after the frame's motion draw.
        r.setMotionVectors(false);
        ASSERT_TRUE(r.drawCrowdGpuCulled(crowd_, shadow, nullptr, DrawMode::kSkinned).isOk());
        r.setMotionVectors(true);
      }
    }
  }
  // Both equal the engine program's motion from the crowd's records (as
  // TheGpuDrivenPathKeepsWhatItDrew checks), so neither took the shadow view as its camera.
  target_.clear(glm::vec4(0.0f));
  drawEngine(false);
  const std::vector<glm::vec2> expected = motions();
  const std::vector<float> expected_depth = depths();
  const std::vector<uint8_t> expected_color = colors();  // Each instance's flat tint.
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "without the shadow view" : "with the shadow view");
    size_t compared = 0, within = 0;
    for (size_t p = 0; p < expected.size(); ++p) {
      if (expected_depth[p] >= 1.0f || depth[k][p] >= 1.0f) continue;
      ++compared;
      within += glm::length(motion[k][p] - expected[p]) <= 1e-4f;
    }
    EXPECT_GT(compared, size_t(kSize) * kSize / 20);
    EXPECT_GE(double(within), 0.995 * double(compared)) << offByInstance(expected_color, motion[k], expected,
                                                                      depth[k], expected_depth);
  }
  plain.shutdown();
  shadowed.shutdown();
}

// A crowd without previous records cannot draw motion vectors: a named error, not garbage.
TEST_P(MotionVectorTest, NeedsTheCrowdsPreviousRecords) {
  Renderer r;
  makeMotionRenderer(&r);
  CrowdManager plain;
  makeCrowd(&plain);
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(plain.add(d, &h).isOk());
  ASSERT_TRUE(plain.update(0.1, closeCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const Status s = r.drawCrowd(plain, batcher, closeCamera(), nullptr);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  MotionTarget unmade;
  EXPECT_EQ(unmade.create(0, 16).code(), StatusCode::kInvalidArgument);
  std::vector<glm::vec2> motion;
  EXPECT_EQ(unmade.readMotion(&motion).code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("previous_records"), std::string::npos) << s.message();
  // Depth-only draws write no motion and need none.
  EXPECT_TRUE(r.drawCrowd(plain, batcher, closeCamera(), nullptr, DrawMode::kDepthOnly).isOk());
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, MotionVectorTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
