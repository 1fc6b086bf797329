// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::gpuMemory: the library's GPU memory by what holds it; the GPU-driven state per
// crowd grows with the crowd, and the staging ring stays bounded whatever the crowd.
#include <algorithm>

#include "gl/resources/upload_ring.h"
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
    ASSERT_TRUE(crowds[k].advanceClock(0.0).isOk());
    ASSERT_TRUE(r.drawCrowdGpuCulled(crowds[k], closeCamera(), nullptr).isOk());
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

}  // namespace
}  // namespace si
