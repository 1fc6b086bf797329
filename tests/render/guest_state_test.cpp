// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The guest contract on the EGL back-ends (a GPU's through EGL device), under the sanitizers and
// with the debug checks on: the consumer project's engine (tests/consumer/project/host_state.h,
// guest_calls.h) sets its own state and debug callback, runs every public call of si::gl that
// touches the context, and every piece of its state must be unchanged after each. The consumer test runs the
// same check in an outside project with its own glad loader linked beside the library.
#include <cstdio>

#include <glad/gl.h>

#include "guest_calls.h"
#include "host_state.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/image_lod_error.h"

namespace si {
namespace {

using namespace test;

class GuestStateTest : public RenderTest {};

TEST_P(GuestStateTest, EveryCallLeavesTheEnginesStateAndDebugCallbackAsItFoundThem) {
  const host::GuestReport report =
      host::checkEveryCall(&HeadlessContext::getProcAddress, context_.get(), kSize, kSize);
  for (const std::string& f : report.failures) ADD_FAILURE() << f;
  std::printf("[ guest    ] %d calls, %zu values of the engine's state compared after each\n",
              report.calls, report.values);
  EXPECT_GE(report.calls, 55);
}

// GL's defaults for what the engine's state (host_state.cpp) changed and an offscreen pass or a
// draw reads: the context's framebuffer `framebuffer`, a full viewport, the enables off, depth
// LESS with writes, depth range 0-1, the default clip control, filled polygons, every colour
// channel.
void defaultRasterState(GLuint framebuffer) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, GLsizei(kSize), GLsizei(kSize));
  for (GLenum cap : {GL_BLEND, GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_POLYGON_OFFSET_FILL,
                     GL_POLYGON_OFFSET_LINE, GL_POLYGON_OFFSET_POINT, GL_SAMPLE_ALPHA_TO_COVERAGE,
                     GL_SAMPLE_ALPHA_TO_ONE, GL_SAMPLE_COVERAGE, GL_SAMPLE_MASK, GL_COLOR_LOGIC_OP,
                     GL_DEPTH_CLAMP, GL_FRAMEBUFFER_SRGB, GL_RASTERIZER_DISCARD, GL_CLIP_DISTANCE0})
    glDisable(cap);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDepthRange(0.0, 1.0);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

// The offscreen passes under the engine's state (depth GEQUAL without writes, clip control
// zero-to-one, depth range 0.25-0.75, wireframe polygons, blending, scissor, stencil, polygon
// offset and a masked colour channel among it) do what they do from GL's defaults: an impostor
// atlas (both drawn afterwards from the defaults) and an image-error table with an impostor.
TEST_P(GuestStateTest, OffscreenWorkUnderTheEnginesStateEqualsItsWorkFromDefaults) {
  ImpostorDesc small;
  small.azimuths = 4;
  small.elevations_degrees = {0.0f, 30.0f};
  small.frames_per_clip = 2;
  ImageLodErrorDesc d;
  d.heights_pixels = {8, 16};
  d.supersample = 2;
  d.azimuths = 4;
  d.max_poses = 2;
  d.impostor = &small;
  const auto measure = [&](ImageLodErrorReport* report) {
    const Status s = measureImageLodErrors(info_, impostorCharacter(), palette(), d, report);
    ASSERT_TRUE(s.isOk()) << s.toString();
  };
  const auto atlas = [&](Renderer* r) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(impostorCharacter(), palette(), &id).isOk());
    const Status s = r->buildImpostor(id, small);
    ASSERT_TRUE(s.isOk()) << s.toString();
  };
  ImageLodErrorReport from_defaults, under_host;
  measure(&from_defaults);
  Renderer a, b;
  atlas(&a);
  GLint context_framebuffer = 0;  // EGL surfaceless: the context's own (headless_context.h).
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &context_framebuffer);
  host::HostState state;
  ASSERT_EQ(state.create(kSize, kSize), "");
  measure(&under_host);
  atlas(&b);
  state.release();
  defaultRasterState(GLuint(context_framebuffer));

  ASSERT_EQ(under_host.levels.size(), from_defaults.levels.size());
  for (size_t l = 0; l < from_defaults.levels.size(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    EXPECT_EQ(under_host.levels[l].mean_differing_pixels,
              from_defaults.levels[l].mean_differing_pixels);
    EXPECT_EQ(under_host.levels[l].max_differing_pixels,
              from_defaults.levels[l].max_differing_pixels);
  }
  // Sixteen characters far enough to be impostors, drawn by both renderers.
  CrowdManager crowd;
  impostorRowsCrowd(2.0, 16.0, 8.0, &crowd);
  const std::vector<uint8_t> image_a = draw(a, crowd, lodCamera(), 0);
  const std::vector<uint8_t> image_b = draw(b, crowd, lodCamera(), 0);
  EXPECT_GT(compare(image_a, std::vector<uint8_t>(image_a.size(), 0), nullptr).share, 0.01);
  const Diff diff = compare(image_b, image_a, nullptr);
  EXPECT_EQ(diff.max_channel, 0) << diff.share * 100 << " % of pixels differ";
}

// A draw writes its depth and blends nothing whatever the host's last pass left (depth writes
// off, additive blending on): the image and the depth of a draw from GL's defaults, on the
// instanced and the GPU-driven path; and the host's two settings are back afterwards.
TEST_P(GuestStateTest, DrawsWriteDepthAndBlendNothingWhateverTheHostLeft) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  const auto depth = [&] {
    std::vector<float> z(size_t(kSize) * kSize);
    glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
    return z;
  };
  const std::vector<uint8_t> image = draw(r, crowd, lodCamera(), 0);
  const std::vector<float> z = depth();
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  for (bool gpu_driven : {false, true}) {
    SCOPED_TRACE(gpu_driven ? "gpu-driven" : "instanced");
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));  // Colour and depth, with GL's masks.
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    const Status s = gpu_driven ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(),
                                                       nullptr, DrawMode::kSkinned)
                                : r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(),
                                              nullptr, DrawMode::kSkinned);
    ASSERT_TRUE(s.isOk()) << s.toString();
    GLboolean mask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    EXPECT_EQ(mask, GL_FALSE);  // The host's, back.
    EXPECT_TRUE(glIsEnabled(GL_BLEND));
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    std::vector<uint8_t> host_image;
    ASSERT_TRUE(context_->readPixels(&host_image).isOk());
    EXPECT_LE(compare(host_image, image, nullptr).share, 0.001);
    EXPECT_LE(differingDepths(depth(), z), z.size() / 1000);
  }
}

// EGL only: OSMesa keeps its state in the same Mesa core as EGL surfaceless (llvmpipe), so it
// would check nothing more for 20 s of the test run; the EGL device variant runs on a GPU.
INSTANTIATE_TEST_SUITE_P(Backends, GuestStateTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
