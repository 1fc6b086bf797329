// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::gpuMemory: the library's GPU memory by what holds it; the GPU-driven state per
// crowd grows with the crowd and shrinks after a peak, and the staging ring stays bounded
// whatever the crowd.
#include <algorithm>
#include <cstdio>

#include "gl/resources/upload_ring.h"
#include "render/far_crowd.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, GpuMemoryIsReportedByWhatHoldsIt) {
  Renderer r;
  makeRenderer(&r);
  GpuMemory m;
  ASSERT_TRUE(r.gpuMemory(&m).isOk());
  ASSERT_EQ(m.characters.size(), 1u);
  EXPECT_TRUE(m.characters[0].crowds.empty());
  // At least the palette's texels and the mesh's indices.
  EXPECT_GE(m.characters[0].character_bytes,
            palette().texel_bytes.size() + character().mesh.indices.size() * 4);
  EXPECT_EQ(m.staging_bytes, 0u);

  // Two crowds behind the camera (cheap to draw): each its own state, sized by its instances;
  // the first's whole state (40,000 x 144 bytes) is more than one staging chunk.
  CrowdManager crowds[2];
  const uint32_t sizes[2] = {40000, 20000};
  for (int k = 0; k < 2; ++k) {
    makeCrowd(&crowds[k]);
    std::vector<glm::dvec3> positions(sizes[k]);
    for (uint32_t i = 0; i < sizes[k]; ++i) positions[i] = {double(i % 200), 0.0, 50.0 + i / 200};
    RandomCrowdDesc rc;
    rc.positions = positions;
    ASSERT_TRUE(crowds[k].addRandom(rc, nullptr).isOk());
    ASSERT_TRUE(crowds[k].advance(0.0).isOk());
    ASSERT_TRUE(
        r.drawCrowdGpuCulled(CharacterId{}, crowds[k].view(), closeCamera(), nullptr).isOk());
  }
  ASSERT_TRUE(r.gpuMemory(&m).isOk());
  ASSERT_EQ(m.characters[0].crowds.size(), 2u);
  uint64_t sum = m.record_ring_bytes + m.vertex_ring_bytes + m.staging_bytes +
                 m.other_shared_bytes + m.characters[0].character_bytes;
  for (int k = 0; k < 2; ++k) {
    const CrowdGpuMemory& c = m.characters[0].crowds[k];
    EXPECT_EQ(c.crowd, crowds[k].identity());
    EXPECT_EQ(c.capacity, sizes[k]);
    EXPECT_EQ(c.views, 1u);
    // The state, the records and the visible list at least; a view's LODs and flags.
    EXPECT_GE(c.state_bytes, uint64_t(sizes[k]) * (sizeof(GpuInstanceState) + 80 + 16));
    EXPECT_GE(c.view_bytes, uint64_t(sizes[k]) * 8);
    sum += c.state_bytes + c.view_bytes;
  }
  EXPECT_GT(m.characters[0].crowds[0].state_bytes, m.characters[0].crowds[1].state_bytes);
  EXPECT_EQ(m.total(), sum);
  // Bounded by the chunk: regions of at most twice a 4 MiB chunk (and alignment slack), where
  // staging the whole state at once took regions of twice that state (6 x 11.5 MB here).
  EXPECT_GT(m.staging_bytes, 0u);
  EXPECT_LE(m.staging_bytes, uint64_t(detail::UploadRing::kRegions) * ((8u << 20) + 4096));
  EXPECT_TRUE(r.gpuMemory(nullptr).code() == StatusCode::kInvalidArgument);
  r.shutdown();
}

// After a peak the GPU-driven buffers shrink to the crowd (half as much again) once it falls to a
// quarter of them, and the crowd then draws what a fresh renderer draws; growing back within
// the new room re-creates nothing.
TEST_P(RenderTest, TheGpuDrivenStateShrinksAfterAPeak) {
  CrowdManager crowd;
  makeCrowd(&crowd);
  // 12 in view around the origin, 39,988 behind the camera (cheap to draw).
  const std::vector<glm::dvec3> positions = twelveInViewOfForty();
  RandomCrowdDesc rc;
  rc.positions = positions;
  std::vector<InstanceHandle> handles;
  ASSERT_TRUE(crowd.addRandom(rc, &handles).isOk());
  ASSERT_TRUE(crowd.advance(0.3).isOk());
  Renderer r;
  makeRenderer(&r);
  const auto drawn = [&](Renderer& renderer) {
    renderer.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    EXPECT_TRUE(
        renderer.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), nullptr).isOk());
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  };
  const auto memory = [&]() {
    GpuMemory m;
    EXPECT_TRUE(r.gpuMemory(&m).isOk());
    return m.characters.at(0).crowds.at(0);
  };
  (void)drawn(r);
  const CrowdGpuMemory peak = memory();
  EXPECT_EQ(peak.capacity, 40000u);

  // Down to 10,012 (a quarter of 40,000 and more): kept.
  for (uint32_t i = 12; i < 29988 + 12; ++i) ASSERT_TRUE(crowd.remove(handles[i]).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  (void)drawn(r);
  EXPECT_EQ(memory().capacity, 40000u);
  // Down to 2,012: 3,018 instances' buffers, a view's too.
  for (uint32_t i = 29988 + 12; i < 29988 + 12 + 8000; ++i)
    ASSERT_TRUE(crowd.remove(handles[i]).isOk());
  ASSERT_EQ(crowd.size(), 2012u);
  ASSERT_TRUE(crowd.advance(0.1).isOk());
  const std::vector<uint8_t> shrunk = drawn(r);
  const CrowdGpuMemory after = memory();
  std::printf("[ memory ] 40,000 -> 2,012 instances: state %llu -> %llu bytes, view %llu -> %llu\n",
              static_cast<unsigned long long>(peak.state_bytes),
              static_cast<unsigned long long>(after.state_bytes),
              static_cast<unsigned long long>(peak.view_bytes),
              static_cast<unsigned long long>(after.view_bytes));
  EXPECT_EQ(after.capacity, 3018u);
  EXPECT_LT(after.state_bytes * 4, peak.state_bytes)
      << after.state_bytes << " of " << peak.state_bytes;
  EXPECT_LT(after.view_bytes * 4, peak.view_bytes);
  Renderer fresh;
  makeRenderer(&fresh);
  const std::vector<uint8_t> reference = drawn(fresh);
  const Diff d = compare(shrunk, reference, nullptr);
  EXPECT_EQ(d.share, 0.0);
  EXPECT_GT(compare(reference, std::vector<uint8_t>(reference.size(), 0), nullptr).share, 0.0);

  // Back up to 3,012: within the room, nothing re-created.
  std::vector<glm::dvec3> more(1000, glm::dvec3(0.0, 0.0, 80.0));
  rc.positions = more;
  ASSERT_TRUE(crowd.addRandom(rc, nullptr).isOk());
  ASSERT_TRUE(crowd.advance(0.0).isOk());
  DrawStats stats;
  ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats).isOk());
  EXPECT_EQ(memory().capacity, 3018u);
  EXPECT_LT(stats.state_bytes_uploaded, 2000u * sizeof(GpuInstanceState));  // Not the whole.
  r.shutdown();
  fresh.shutdown();
}

}  // namespace
}  // namespace si
