// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// GL faults become named errors at the call that meets them, never a GL error later: uploads
// past the context's limits, allocations the driver refuses, a crowd whose GPU state exceeds
// the storage-block limit, a compute ring past it, and no current context; and the
// application's own pending errors are given back or left pending, never dropped.
#include <glad/gl.h>

#include <algorithm>

#include "gl/host_errors.h"
#include "gl/resources/gl_allocation.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, UploadsPastTheContextsLimitsAreNamedErrors) {
  // A palette taller than GL_MAX_TEXTURE_SIZE, as if baked for a larger GPU: refused by name.
  GlInfo small = info_;
  small.max_texture_size = palette().layout.height - 1;
  Renderer limited;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(limited.init(small, rd).isOk());
  CharacterId id;
  const Status s = limited.addCharacter(character(), palette(), &id);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("GL_MAX_TEXTURE_SIZE"), std::string::npos) << s.message();
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_P(RenderTest, AllocationsTheDriverRefusesAreNamedErrors) {
  GLuint buffer = 0, texture = 0;
  // 2^50 bytes: no driver gives that.
  Status s = detail::createBuffer(&buffer, uint64_t(1) << 50, nullptr, 0, "a test buffer");
  EXPECT_FALSE(s.isOk());
  EXPECT_TRUE(s.code() == StatusCode::kLimitExceeded || s.code() == StatusCode::kBackend);
  EXPECT_NE(s.message().find("a test buffer"), std::string::npos) << s.message();
  EXPECT_EQ(buffer, 0u);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "an error was left for a later call";
  // A texture past GL_MAX_TEXTURE_SIZE (GL_INVALID_VALUE).
  const GLsizei side = GLsizei(info_.max_texture_size) * 2;
  s = detail::createTexture2D(&texture, 1, GL_RGBA32F, side, side, "a test texture");
  EXPECT_EQ(s.code(), StatusCode::kBackend);
  EXPECT_NE(s.message().find("GL_INVALID_VALUE"), std::string::npos) << s.message();
  EXPECT_EQ(texture, 0u);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  // The helpers succeed for sane sizes, and a pending error of the application's is not
  // blamed on them.
  glBindBuffer(GL_ARRAY_BUFFER, 0xFFFFFF);  // GL_INVALID_OPERATION: not a buffer name.
  s = detail::createBuffer(&buffer, 4096, nullptr, 0, "a small buffer");
  EXPECT_TRUE(s.isOk()) << s.toString();
  EXPECT_NE(buffer, 0u);
  glDeleteBuffers(1, &buffer);
}

// A GL error the application left pending is never the library's to drop: a call that reads
// errors (an allocation, any call with debug checks, the calls that always check) takes it and
// gives it back through takeHostGlErrors, naming the call, and still succeeds; a release draw
// that allocates nothing reads none and leaves it pending in GL for the application.
TEST_P(RenderTest, TheApplicationsPendingErrorsAreGivenBackOrLeftPending) {
  takeHostGlErrors(nullptr);                                           // What earlier tests left.
  const auto raise = [] { glBindBuffer(GL_ARRAY_BUFFER, 0xFFFFFF); };  // GL_INVALID_OPERATION.
  std::vector<HostGlError> taken;
  raise();
  GLuint buffer = 0;
  Status s = detail::createBuffer(&buffer, 4096, nullptr, 0, "a small buffer");
  EXPECT_TRUE(s.isOk()) << s.toString();
  glDeleteBuffers(1, &buffer);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  takeHostGlErrors(&taken);
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].error, uint32_t(GL_INVALID_OPERATION));
  EXPECT_EQ(taken[0].taken_by, "a small buffer");
  takeHostGlErrors(&taken);  // Given back once.
  EXPECT_TRUE(taken.empty());
  CrowdManager crowd;
  makeOneInstanceCrowd(&crowd);
  for (uint32_t checks : {1u, 2u}) {  // Debug checks on, then off.
    SCOPED_TRACE(checks == 1 ? "debug checks" : "release");
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    rd.debug_checks = checks;
    Renderer r;
    raise();
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);  // init allocates: takes it.
    takeHostGlErrors(&taken);
    ASSERT_EQ(taken.size(), 1u);
    EXPECT_EQ(taken[0].error, uint32_t(GL_INVALID_OPERATION));
    if (checks == 1) {
      EXPECT_EQ(taken[0].taken_by, "Renderer::init");
    }
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), nullptr)
                    .isOk());  // Sizes its buffers.
    raise();
    s = r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), nullptr);
    EXPECT_TRUE(s.isOk()) << s.toString();
    takeHostGlErrors(&taken);
    if (checks == 1) {
      ASSERT_EQ(taken.size(), 1u);
      EXPECT_EQ(taken[0].taken_by, "drawCrowd");
      EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    } else {
      EXPECT_TRUE(taken.empty());
      EXPECT_EQ(glGetError(), GLenum(GL_INVALID_OPERATION));  // Still the application's.
    }
    // A call that always checks its errors takes it whatever the checks.
    std::vector<glm::uvec2> selection;
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), nullptr).isOk());
    raise();
    s = r.readGpuSelection(CharacterId{}, &selection);
    EXPECT_TRUE(s.isOk()) << s.toString();
    takeHostGlErrors(&taken);
    ASSERT_EQ(taken.size(), 1u);
    EXPECT_EQ(taken[0].taken_by, "readGpuSelection");
    r.shutdown();
  }
  // At most 64 kept; the rest counted.
  for (int k = 0; k < 66; ++k) {
    raise();
    detail::takeHostErrors("a test");
  }
  uint64_t dropped = 0;
  takeHostGlErrors(&taken, &dropped);
  EXPECT_EQ(taken.size(), 64u);
  EXPECT_EQ(dropped, 2u);
  takeHostGlErrors(&taken, &dropped);
  EXPECT_EQ(dropped, 0u);
}

TEST_P(RenderTest, StoragePastTheBlockLimitIsRefusedByName) {
  // The compute ring must fit one storage block.
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.compute_ring_bytes = info_.max_shader_storage_block_size_bytes + 16;
  Renderer r;
  Status s = r.init(info_, rd);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("GL_MAX_SHADER_STORAGE_BLOCK_SIZE"), std::string::npos);
  // So must every buffer the GPU-driven passes bind whole, each refused by name: the crowd
  // state (144 bytes an instance), in a context that allows 100 instances' state and a table
  // entry.
  GlInfo small = info_;
  small.max_shader_storage_block_size_bytes = 144 * 100 + 16;
  rd.compute_ring_bytes = 4096;
  ASSERT_TRUE(r.init(small, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(character(), palette(), &id).isOk());
  CrowdManager crowd;
  makeCrowd(&crowd);
  std::vector<glm::dvec3> positions(100, glm::dvec3(0.0, 0.0, -5.0));
  RandomCrowdDesc rc;
  rc.positions = positions;
  std::vector<InstanceHandle> handles;
  ASSERT_TRUE(crowd.addRandom(rc, &handles).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  DrawStats stats;
  EXPECT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats).isOk());
  // 2D blends: 192 bytes of overlays an instance (the overlay and two extra layers).
  LayerMask body;
  ASSERT_TRUE(buildFullBodyMask(character().skeleton, palette(), "body", &body).isOk());
  uint32_t mask = 0, space = 0;
  ASSERT_TRUE(crowd.addLayerMask(body, &mask).isOk());
  BlendSpace grid;
  grid.name = "grid";
  for (const char* name : {"idle", "walk", "run", "wave"})
    grid.clips.push_back(uint32_t(palette().findClip(name)));
  grid.positions = {0.0f, 1.0f};
  grid.positions_y = {0.0f, 1.0f};
  grid.mask = mask;
  ASSERT_TRUE(crowd.addBlendSpace(grid, &space).isOk());
  ASSERT_TRUE(crowd.playBlend(handles[0], space, glm::vec2(0.3f, 0.6f), 0.0).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("100 instances need 19200 bytes of overlays"), std::string::npos)
      << s.message();
  ASSERT_TRUE(crowd.remove(handles[0]).isOk());  // The only overlay gone: 64 bytes, then none.
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats);
  EXPECT_TRUE(s.isOk()) << s.toString();
  ASSERT_TRUE(crowd.addRandom(rc, nullptr).isOk());  // 199: past the limit.
  s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("199 instances need 28656 bytes of crowd state"), std::string::npos)
      << s.message();
  r.shutdown();
  // The state fits exactly; the staging copy does not (its table entry), so it goes in
  // chunks, which draw the same selection as one upload does.
  small.max_shader_storage_block_size_bytes = 144 * 199;
  ASSERT_TRUE(r.init(small, rd).isOk());
  ASSERT_TRUE(r.addCharacter(character(), palette(), &id).isOk());
  s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats);
  EXPECT_TRUE(s.isOk()) << s.toString();
  std::vector<glm::uvec2> chunked, whole;
  ASSERT_TRUE(r.readGpuSelection(CharacterId{}, &chunked).isOk());
  r.shutdown();
  ASSERT_TRUE(r.init(info_, rd).isOk());
  ASSERT_TRUE(r.addCharacter(character(), palette(), &id).isOk());
  ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats).isOk());
  ASSERT_TRUE(r.readGpuSelection(CharacterId{}, &whole).isOk());
  const auto order = [](std::vector<glm::uvec2>* v) {
    std::sort(v->begin(), v->end(),
              [](glm::uvec2 a, glm::uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  };
  order(&chunked);
  order(&whole);
  EXPECT_EQ(chunked.size(), 199u);
  EXPECT_TRUE(chunked == whole);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_P(RenderTest, NoCurrentContextIsANamedError) {
  context_.reset();  // Destroys the context: none is current now.
  Renderer r;
  const Status s = r.init(info_, {});
  EXPECT_EQ(s.code(), StatusCode::kBackend);
  EXPECT_NE(s.message().find("no GL context is current"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace si
