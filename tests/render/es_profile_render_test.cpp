// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The OpenGL ES profile (GlInfo::es) on an ES 3 context (EGL only: OSMesa makes none): the
// golden scenes within the desktop goldens' tolerance; every palette format and cubic clips
// equal to a desktop context's image of the same crowd; many batches (the smallest uniform block)
// equal to one; depth-only and rigid draws; the host's state as it was; the named refusals of
// what ES 3.0 lacks; the record ring's uploads into buffers no queued draw reads. The custom
// texture's tests run on the profile too (custom_texture_test.cpp).
#include <glad/gl.h>

#include <cstring>

#include "gl/profile/gl_profile.h"
#include "gl/resources/record_ring.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/image_lod_error.h"

namespace si {
namespace {

using namespace test;

class EsRenderTest : public RenderTest {
 protected:
  bool es() const override { return true; }

  // A renderer of the embedded character (with `rd` when given) and the LOD crowd
  // (populateLodCrowd) selected for lodCamera(), with a batcher for the renderer.
  void lodScene(Renderer* r, CrowdManager* crowd, InstanceBatcher* batcher,
                const RendererDesc* rd = nullptr) {
    makeRenderer(r, 0, PaletteFormat::kMatrix3x4F32, rd);
    makeCrowd(crowd);
    populateLodCrowd(crowd);
    ASSERT_TRUE(crowd->update(0.0, lodCamera()).isOk());
    ASSERT_TRUE(batcher->init(r->batchLimits()).isOk());
  }

  // A field of `count` walkers facing the camera at LOD distances, tinted by index.
  static void populateField(CrowdManager* crowd, int count) {
    for (int i = 0; i < count; ++i) {
      InstanceDesc d;
      d.position = glm::dvec3((i % 25 - 12) * 1.1, 0.0, -3.0 - (i / 25) * 2.5);
      d.clip = uint32_t(i) % uint32_t(palette().clips.size());
      d.time_seconds = 0.07 * i;
      d.speed = 0.0f;
      d.color = glm::u8vec4(uint8_t(40 + i * 7), uint8_t(200 - i * 3), uint8_t(90 + i * 5), 255);
      d.variation_mask = 1u | (uint32_t(i) % 8u) << 1;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
  }
};

TEST_P(EsRenderTest, GoldenSingleCharacter) {
  goldenSingleCharacter();
}
TEST_P(EsRenderTest, GoldenCrowdWithEveryLodVariationAndTint) {
  goldenCrowdLods();
}
TEST_P(EsRenderTest, GoldenCrossfadeMidpoint) {
  goldenCrossfadeMidpoint();
}

// The same crowd on a desktop 4.5 context of the same back-end and on the ES context: every
// palette format, linear and cubic, within 0.1 % of pixels.
TEST_P(EsRenderTest, EveryPaletteFormatDrawsTheDesktopImage) {
  struct Case {
    PaletteFormat format;
    InterpolationChoice interpolation;
  };
  const Case cases[] = {{PaletteFormat::kMatrix3x4F32, InterpolationChoice::kLinear},
                        {PaletteFormat::kMatrix3x4F16, InterpolationChoice::kLinear},
                        {PaletteFormat::kQuatTranslationF32, InterpolationChoice::kLinear},
                        {PaletteFormat::kMatrix3x4F32, InterpolationChoice::kCubic}};
  std::vector<std::vector<uint8_t>> es_images;
  const auto drawAll = [&](std::vector<std::vector<uint8_t>>* out) {
    for (const Case& k : cases) {
      Renderer r;
      makeRenderer(&r, 0, k.format, nullptr, k.interpolation);
      CrowdManager crowd;
      makeCrowd(&crowd, k.format, k.interpolation);
      populateLodCrowd(&crowd);
      addFadingCharacter(&crowd, k.format);
      ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
      out->push_back(draw(r, crowd, lodCamera(), 0));
    }
  };
  drawAll(&es_images);
  HeadlessDesc d;
  d.width = d.height = kSize;
  d.backend = GetParam();
  std::unique_ptr<HeadlessContext> desktop;
  ASSERT_TRUE(HeadlessContext::create(d, &desktop).isOk());
  std::swap(desktop, context_);  // draw() reads context_.
  ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_).isOk());
  ASSERT_FALSE(info_.es);
  std::vector<std::vector<uint8_t>> desktop_images;
  drawAll(&desktop_images);
  std::swap(desktop, context_);
  desktop.reset();
  ASSERT_TRUE(context_->makeCurrent().isOk());
  ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_).isOk());
  ASSERT_TRUE(info_.es);
  ASSERT_EQ(es_images.size(), desktop_images.size());
  for (size_t i = 0; i < es_images.size(); ++i) {
    const Diff diff = compare(es_images[i], desktop_images[i], nullptr);
    EXPECT_LE(diff.share, 0.001) << "case " << i << ": max channel " << diff.max_channel;
  }
}

// 600 instances at the smallest uniform block GL allows (204 records a draw) draw the image of
// one batch per bucket, in more draw calls.
TEST_P(EsRenderTest, BatchesOfTheSmallestUniformBlockDrawTheImageOfOne) {
  Renderer whole, smallest;
  makeRenderer(&whole);
  makeRenderer(&smallest, 16384);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateField(&crowd, 600);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  DrawStats one, many;
  const std::vector<uint8_t> a = draw(whole, crowd, lodCamera(), 0, false, &one);
  const std::vector<uint8_t> b = draw(smallest, crowd, lodCamera(), 16384, false, &many);
  EXPECT_GT(many.draw_calls, one.draw_calls);
  EXPECT_EQ(many.triangles, one.triangles);
  EXPECT_EQ(compare(a, b, nullptr).max_channel, 0);
}

// A depth-only pass writes the depth the shaded draw then fails against (GL_LESS), and no
// colour; rigid instancing draws the bind pose (another image, the same triangles).
TEST_P(EsRenderTest, DepthOnlyAndRigidDraws) {
  Renderer r;
  CrowdManager crowd;
  InstanceBatcher batcher;
  lodScene(&r, &crowd, &batcher);
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  r.clear(background);
  std::vector<uint8_t> cleared, depth_then_colour;
  ASSERT_TRUE(context_->readPixels(&cleared).isOk());
  DrawStats depth, colour, rigid;
  ASSERT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), &depth, DrawMode::kDepthOnly)
          .isOk());
  std::vector<uint8_t> after_depth;
  ASSERT_TRUE(context_->readPixels(&after_depth).isOk());
  EXPECT_EQ(compare(cleared, after_depth, nullptr).max_channel, 0) << "depth-only wrote colour";
  ASSERT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr, DrawMode::kSkinned)
          .isOk());
  ASSERT_TRUE(context_->readPixels(&depth_then_colour).isOk());
  EXPECT_LE(compare(cleared, depth_then_colour, nullptr).share, 0.005)
      << "the shaded draw passed the depth-only pass's depth";
  const std::vector<uint8_t> skinned = draw(r, crowd, lodCamera(), 0, false, &colour);
  EXPECT_GT(compare(cleared, skinned, nullptr).share, 0.02);
  EXPECT_EQ(depth.triangles, colour.triangles);
  r.clear(background);
  ASSERT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), &rigid, DrawMode::kRigid)
          .isOk());
  std::vector<uint8_t> bind_pose;
  ASSERT_TRUE(context_->readPixels(&bind_pose).isOk());
  EXPECT_EQ(rigid.triangles, colour.triangles);
  EXPECT_GT(compare(skinned, bind_pose, nullptr).share, 0.005) << "rigid drew the animated pose";
}

// The host's bindings that the emulated direct-state-access calls bind through (copy-write and
// array buffers, the active unit's textures, the current program, the vertex array) and the
// uniform bindings the draws use, as the host left them after an upload and a draw.
TEST_P(EsRenderTest, TheHostsBindingsStayAsTheyWere) {
  GLuint buffers[3] = {0, 0, 0}, textures[2] = {0, 0}, vao = 0;
  glGenBuffers(3, buffers);
  glGenTextures(2, textures);
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  glBindBuffer(GL_COPY_WRITE_BUFFER, buffers[1]);
  glBindBufferBase(GL_UNIFORM_BUFFER, 11, buffers[2]);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, buffers[2]);
  glActiveTexture(GL_TEXTURE5);
  glBindTexture(GL_TEXTURE_2D, textures[0]);
  glBindTexture(GL_TEXTURE_2D_ARRAY, textures[1]);
  const auto bindings = [] {
    std::vector<GLint> v;
    for (GLenum name :
         {GL_VERTEX_ARRAY_BINDING, GL_ARRAY_BUFFER_BINDING, GL_COPY_WRITE_BUFFER_BINDING,
          GL_ACTIVE_TEXTURE, GL_TEXTURE_BINDING_2D, GL_TEXTURE_BINDING_2D_ARRAY, GL_CURRENT_PROGRAM,
          GL_UNIFORM_BUFFER_BINDING}) {
      GLint value = -1;
      glGetIntegerv(name, &value);
      v.push_back(value);
    }
    for (GLuint index : {0u, 4u, 11u}) {
      GLint value = -1;
      glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, index, &value);
      v.push_back(value);
    }
    return v;
  };
  const std::vector<GLint> before = bindings();
  {
    Renderer r;
    CrowdManager crowd;
    InstanceBatcher batcher;
    lodScene(&r, &crowd, &batcher);
    ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr).isOk());
    EXPECT_EQ(bindings(), before);
  }
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  glBindVertexArray(0);
  glDeleteVertexArrays(1, &vao);
  glDeleteBuffers(3, buffers);
  glDeleteTextures(2, textures);
}

// Under WebGL (GlInfo::webgl; the profile's flag set here on the native ES context) the state
// contract does not ask for the cull face mode, front face, colour mask and depth write mask,
// which WebGL may answer only by a round trip to the GPU process: it leaves them at GL's
// defaults, unless RendererDesc::webgl_restore_raster_state asks for them. Desktop-like ES
// restores them.
TEST_P(EsRenderTest, UnderWebGlTheRoundTripValuesAreLeftAtDefaultsUnlessAsked) {
  struct WebGl {
    explicit WebGl(bool on) { detail::setWebglProfile(on); }
    ~WebGl() { detail::setWebglProfile(false); }
  };
  const auto raster = [] {
    GLint cull = 0, front = 0;
    GLboolean mask[4] = {}, depth = GL_FALSE;
    glGetIntegerv(GL_CULL_FACE_MODE, &cull);
    glGetIntegerv(GL_FRONT_FACE, &front);
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth);
    return std::vector<GLint>{cull, front, mask[0], mask[1], mask[2], mask[3], depth};
  };
  const std::vector<GLint> host = {GL_FRONT, GL_CW, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE,
                                   GL_FALSE};
  const std::vector<GLint> defaults = {GL_BACK, GL_CCW, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE,
                                       GL_TRUE};
  for (const bool webgl : {true, false}) {
    for (const bool ask : {false, true}) {
      SCOPED_TRACE(testing::Message() << "webgl " << webgl << ", asked " << ask);
      const WebGl profile(webgl);
      glCullFace(GL_FRONT);
      glFrontFace(GL_CW);
      glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
      RendererDesc rd;
      rd.skinning_path = SkinningPath::kVertexShader;
      rd.webgl_restore_raster_state = ask;
      Renderer r;
      CrowdManager crowd;
      InstanceBatcher batcher;
      lodScene(&r, &crowd, &batcher, &rd);
      glDepthMask(GL_FALSE);
      ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr).isOk());
      EXPECT_EQ(raster(), webgl && !ask ? defaults : host);
      glDepthMask(GL_TRUE);
    }
  }
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// What ES 3.0 lacks is refused by name (kUnsupported, "the OpenGL ES profile has no ..."), and
// the automatic path choice takes the vertex shader without measuring.
TEST_P(EsRenderTest, RefusesWhatEs30LacksByName) {
  const auto refused = [](const Status& s, const char* capability) {
    EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
    EXPECT_NE(s.message().find(std::string("OpenGL ES profile has no ") + capability),
              std::string::npos)
        << s.message();
  };
  {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kCompute;
    Renderer r;
    refused(r.init(info_, rd), "compute shaders");
    rd = RendererDesc();
    rd.gpu_occlusion_culling = true;
    refused(r.init(info_, rd), "compute shaders");
    rd = RendererDesc();
    rd.motion_vectors = true;
    refused(r.init(info_, rd), "motion-vector programs");
    rd = RendererDesc();
    rd.measure_gpu_time = true;
    refused(r.init(info_, rd), "timer queries");
    rd = RendererDesc();
    rd.measure_gpu_passes = true;
    refused(r.init(info_, rd), "timer queries (RendererDesc::measure_gpu_passes)");
  }
  RendererDesc automatic;
  automatic.skinning_path = SkinningPath::kAutomatic;
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &automatic);
  EXPECT_EQ(r.skinningPath(CharacterId{0}), SkinningPath::kVertexShader);
  EXPECT_NE(r.skinningPathReason(CharacterId{0}).find("OpenGL ES"), std::string::npos);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  refused(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr,
                      DrawMode::kComputeSkinned),
          "compute shaders");
  refused(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), nullptr),
          "compute shaders");
  refused(r.drawTraditional(CharacterId{}, crowd.view(), lodCamera(), nullptr),
          "traditional program");
  refused(r.drawCpuSkinned(CharacterId{}, crowd.view(), lodCamera(), nullptr), "storage buffers");
  refused(r.buildImpostor(CharacterId{0}, ImpostorDesc{}), "impostor programs");
  GpuMemory memory;
  refused(r.gpuMemory(&memory), "texture size queries");
  std::vector<glm::vec3> positions;
  refused(r.captureSkinnedPositions(CharacterId{}, crowd.view().records()[0], &positions),
          "capture programs");
  ImageLodErrorReport report;
  refused(measureImageLodErrors(info_, character(), palette(), ImageLodErrorDesc{}, &report),
          "compute or impostor programs");
  MaterialDesc material;
  material.name = "es";
  material.source = "layout(location = 0) out vec4 o;\nvoid siMaterial(SiSurface s) { o = s.base_color; }";
  MaterialId material_id;
  refused(r.addMaterial(material, &material_id), "host materials");
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  // A refused draw left the renderer whole: the vertex-shader path still draws.
  EXPECT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr).isOk());
}

// The ES profile's record ring: consecutive frames upload into buffers of their regions' own,
// rotating (and each orphaned before its upload), so no upload writes storage a queued draw
// still reads (a stall or a copy on tile-based GPUs); what each frame binds holds its records.
TEST_P(EsRenderTest, TheRecordRingUploadsIntoBuffersNoQueuedDrawReads) {
  detail::RecordRing ring;
  ring.configure(16384, 256, 3);
  ASSERT_TRUE(ring.reserve(1024).isOk());
  std::vector<GLint> bound;
  for (int frame = 0; frame < 4; ++frame) {
    size_t base = 0;
    ASSERT_TRUE(ring.acquire(&base).isOk());
    std::memset(ring.mapped(base), 10 + frame, 1024);
    ring.publish(base, 1024);
    ring.bindBatch(base, DrawBatch{}, 0);
    GLint buffer = 0;
    GLint64 start = 0;
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, 0, &buffer);
    glGetInteger64i_v(GL_UNIFORM_BUFFER_START, 0, &start);
    bound.push_back(buffer);
    glBindBuffer(GL_UNIFORM_BUFFER, GLuint(buffer));
    const auto* bytes = static_cast<const uint8_t*>(
        glMapBufferRange(GL_UNIFORM_BUFFER, GLintptr(start), 1024, GL_MAP_READ_BIT));
    ASSERT_NE(bytes, nullptr);
    EXPECT_EQ(bytes[0], 10 + frame);
    EXPECT_EQ(bytes[1023], 10 + frame);
    glUnmapBuffer(GL_UNIFORM_BUFFER);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    ring.finishFrame();
  }
  EXPECT_NE(bound[0], bound[1]);
  EXPECT_NE(bound[1], bound[2]);
  EXPECT_NE(bound[0], bound[2]);
  EXPECT_EQ(bound[3], bound[0]);  // Round again to the first region's.
  ring.release();
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

INSTANTIATE_TEST_SUITE_P(Backends, EsRenderTest, test::esBackends(), test::backendTestName);

}  // namespace
}  // namespace si
