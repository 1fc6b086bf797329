// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Frames at keys (the default bake's uneven frame times) drawn by the GPU-driven path, which
// finds each instance's frame by a binary search over the clip's frame times, against the
// CPU-selected path, whose records carry the frame the crowd found through its cell table.
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

const BakedPalette& keyedPalette() {
  static const BakedPalette p = [] {
    BakeDesc d;
    d.placement = FramePlacement::kKeys;
    BakedPalette out;
    if (!bakePalette(character(), d, &out, nullptr).isOk()) std::abort();
    return out;
  }();
  return p;
}

TEST_P(RenderTest, GpuDrivenDrawsFramesAtKeysAsTheCpuPathDoes) {
  const BakedPalette& keyed = keyedPalette();
  uint32_t uneven = 0;
  for (const BakedClip& c : keyed.clips) uneven += c.frame_times_seconds.empty() ? 0u : 1u;
  ASSERT_GT(uneven, 0u);
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.measure_gpu_time = true;  // Reads back the GPU's counts.
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(character(), keyed, &id).isOk());
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &keyed;
  cd.sub_mesh_count = 4;
  cd.lod_count = 3;
  ASSERT_TRUE(crowd.init(cd).isOk());
  // Close rows, every clip at many times: frames land all over each clip's uneven frames.
  const uint32_t clips = uint32_t(keyed.clips.size());
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k - 3.5) * 1.1, 0.0, -3.5 - 2.0 * row);
      d.clip = uint32_t(k + row) % clips;
      d.time_seconds = 0.137 * (k + 8 * row);
      d.speed = 0.5f + 0.1f * float(k);
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
    }
  const Camera camera = Camera::lookAt({0.0, 1.6, 2.5}, {0.0, 0.8, -6.0}, glm::vec3(0, 1, 0),
                                       1.0f, 1.0f, 0.1f, 100.0f);
  for (double step : {0.0, 0.31, 0.77}) {
    SCOPED_TRACE(step);
    ASSERT_TRUE(crowd.advance(step).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    const std::vector<uint8_t> cpu = draw(r, crowd, camera, 0);
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats stats;
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, &stats).isOk());
    std::vector<uint8_t> gpu;
    ASSERT_TRUE(context_->readPixels(&gpu).isOk());
    const Diff diff = compare(gpu, cpu, nullptr);
    EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
    EXPECT_EQ(stats.gpu_visible, crowd.view().stats().visible);
  }
}

}  // namespace
}  // namespace si
