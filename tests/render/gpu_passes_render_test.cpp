// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// RendererDesc::measure_gpu_passes (si/gl/gpu_passes.h): each draw's GPU time per pass, read
// later by its ticket without waiting; the passes a path runs have time, the others none, and
// they add up to the draw.
#include <numeric>

#include "render/render_fixture.h"
#include "render/render_scenes.h"

namespace si {
namespace {

using namespace test;

// The times of `ticket` once the GPU is past it (the image read back waits for it).
GpuPassTimes readAfterFinish(const Renderer& r, uint64_t ticket) {
  GpuPassTimes t;
  const Status s = r.readGpuPasses(ticket, &t);
  EXPECT_TRUE(s.isOk()) << s.toString();
  EXPECT_TRUE(t.ready);
  return t;
}

void expectPassesAddUp(const GpuPassTimes& t) {
  EXPECT_GT(t.total_ms, 0.0);
  EXPECT_NEAR(std::accumulate(std::begin(t.ms), std::end(t.ms), 0.0), t.total_ms, 1e-9);
}

class GpuPassTest : public RenderTest {
 protected:
  // A renderer of `rd` with pass times on, and the LOD crowd (render_scenes.h) 0.3 s in.
  void makeTimedScene(RendererDesc rd, Renderer* r, CrowdManager* crowd) {
    rd.measure_gpu_passes = true;
    makeRenderer(r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    makeCrowd(crowd);
    populateLodCrowd(crowd);
    ASSERT_TRUE(crowd->advance(0.3).isOk());
  }
};

// The GPU-driven path with occlusion culling and compute pre-skinning: every pass it runs is
// timed by name, both phases summed; impostors and layers do not run and take no time.
TEST_P(GpuPassTest, GpuDrivenPassesAreTimedByName) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kCompute;
  rd.gpu_occlusion_culling = true;
  Renderer r;
  CrowdManager crowd;
  makeTimedScene(rd, &r, &crowd);
  uint64_t tickets[2] = {};
  for (uint64_t& ticket : tickets) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats st;
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &st).isOk());
    ticket = st.gpu_pass_ticket;
  }
  EXPECT_GT(tickets[0], 0u);
  EXPECT_EQ(tickets[1], tickets[0] + 1);
  std::vector<uint8_t> image;
  ASSERT_TRUE(context_->readPixels(&image).isOk());
  for (const uint64_t ticket : tickets) {
    const GpuPassTimes t = readAfterFinish(r, ticket);
    expectPassesAddUp(t);
    for (const GpuPass ran : {GpuPass::kCull, GpuPass::kCommands, GpuPass::kScatter, GpuPass::kSkin,
                              GpuPass::kDraw, GpuPass::kDepthPyramid})
      EXPECT_GT(t.at(ran), 0.0) << gpuPassName(ran);
    EXPECT_EQ(t.at(GpuPass::kCompose), 0.0);
    EXPECT_EQ(t.at(GpuPass::kImpostors), 0.0);
  }
  // Read again: the same times (reading frees nothing).
  GpuPassTimes again;
  ASSERT_TRUE(r.readGpuPasses(tickets[1], &again).isOk());
  EXPECT_EQ(again.total_ms, readAfterFinish(r, tickets[1]).total_ms);
  r.shutdown();
}

// drawCrowd's paths: the vertex-shader path's time is its draws (its records are written by
// the CPU), the compute path's its skinning and its draws.
TEST_P(GpuPassTest, InstancedPathsTimeTheirSkinningAndDraws) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;  // kDefault draws (Path::kInstanced) skin there.
  Renderer r;
  CrowdManager crowd;
  makeTimedScene(rd, &r, &crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  for (const Path path : {Path::kInstanced, Path::kCompute}) {
    SCOPED_TRACE(path == Path::kCompute ? "compute" : "vertex shader");
    DrawStats st;
    draw(r, crowd, lodCamera(), 0, false, &st, path);  // Reads the image back.
    const GpuPassTimes t = readAfterFinish(r, st.gpu_pass_ticket);
    expectPassesAddUp(t);
    EXPECT_GT(t.at(GpuPass::kDraw), 0.0);
    EXPECT_EQ(t.at(GpuPass::kSkin) > 0.0, path == Path::kCompute);
    for (const GpuPass none : {GpuPass::kCull, GpuPass::kCommands, GpuPass::kScatter,
                               GpuPass::kDepthPyramid, GpuPass::kImpostors})
      EXPECT_EQ(t.at(none), 0.0) << gpuPassName(none);
  }
  r.shutdown();
}

// Tickets: none without the option; one never given is refused, one whose stamps were reused
// (older than the last kGpuPassTickets draws) is not found, and a null output is refused.
TEST_P(GpuPassTest, GpuPassTicketsAreKeptForTheLastDraws) {
  CrowdManager crowd;
  makeOneInstanceCrowd(&crowd);
  {
    Renderer plain;
    makeRenderer(&plain);
    DrawStats st;
    draw(plain, crowd, closeCamera(), 0, false, &st);
    EXPECT_EQ(st.gpu_pass_ticket, 0u);
    GpuPassTimes t;
    EXPECT_EQ(plain.readGpuPasses(1, &t).code(), StatusCode::kInvalidArgument);
    plain.shutdown();
  }
  RendererDesc rd;
  rd.measure_gpu_passes = true;
  Renderer r;
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  std::vector<uint64_t> tickets;
  for (uint32_t k = 0; k < Renderer::kGpuPassTickets + 1; ++k) {
    DrawStats st;
    ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), &st).isOk());
    tickets.push_back(st.gpu_pass_ticket);
  }
  // A draw without stats takes no ticket.
  ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), nullptr).isOk());
  std::vector<uint8_t> image;
  ASSERT_TRUE(context_->readPixels(&image).isOk());
  GpuPassTimes t;
  EXPECT_EQ(r.readGpuPasses(tickets.front(), &t).code(), StatusCode::kNotFound);
  EXPECT_TRUE(r.readGpuPasses(tickets[1], &t).isOk());
  EXPECT_TRUE(t.ready);
  EXPECT_TRUE(r.readGpuPasses(tickets.back(), &t).isOk());
  EXPECT_TRUE(t.ready);
  EXPECT_EQ(r.readGpuPasses(tickets.back() + 1, &t).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.readGpuPasses(0, &t).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.readGpuPasses(tickets.back(), nullptr).code(), StatusCode::kInvalidArgument);
  Renderer none;
  EXPECT_EQ(none.readGpuPasses(1, &t).code(), StatusCode::kInvalidArgument);
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, GpuPassTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
