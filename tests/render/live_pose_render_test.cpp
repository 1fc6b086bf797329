// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Live poses drawn (CrowdManager::setLivePose): an instance posed with the matrices of a baked
// frame draws exactly what an instance playing that frame draws, on the vertex-shader and
// compute paths of drawCrowd and of GPU-driven culling, the baselines, and the ES profile; a
// hand-over from the clip half-way draws as a crossfade half-way to that frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

// Every path: drawCrowd's two skinnings, GPU-driven culling's two, the baselines.
constexpr PathKind kLivePaths[] = {PathKind::kInstanced,   PathKind::kCompute,
                                   PathKind::kGpuDriven,   PathKind::kGpuDrivenCompute,
                                   PathKind::kTraditional, PathKind::kCpu};

class LivePoseRenderTest : public RenderTest {
 protected:
  // The crowd of the row, with room for `live_poses` live poses.
  void initRow(CrowdManager* crowd, uint32_t live_poses) {
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    cd.live_pose_capacity = live_poses;
    ASSERT_TRUE(crowd->init(cd).isOk());
  }
  // Instance k of the row: playing "walk", each from its own time.
  InstanceDesc rowInstance(int k) {
    InstanceDesc d;
    d.position = glm::dvec3(1.2 * (k - 1), 0.0, 0.0);
    d.clip = uint32_t(palette().findClip("walk"));
    d.time_seconds = 0.2 * k;
    return d;
  }
  // The stored matrices of "wave"'s frame `frame`.
  std::vector<glm::mat4> waveFrame(uint32_t frame) {
    const BakedPalette& p = palette();
    std::vector<glm::mat4> pose(p.palette_joints.size());
    for (uint32_t slot = 0; slot < pose.size(); ++slot)
      pose[slot] = decodeJoint(p, uint32_t(p.findClip("wave")), frame, slot);
    return pose;
  }
  // Three instances in a row; the middle one plays "walk" and, when `posed`, is posed with
  // the stored matrices of "wave"'s frame `frame`; when `twin`, it plays "wave" held at frame 0
  // instead (speed 0) and is not posed. Room for `capacity` live poses.
  void makeRow(CrowdManager* crowd, bool posed, bool twin, uint32_t frame = 0,
               uint32_t capacity = 2) {
    initRow(crowd, capacity);
    for (int k = 0; k < 3; ++k) {
      InstanceDesc d = rowInstance(k);
      if (k == 1 && twin)
        d.clip = uint32_t(palette().findClip("wave")), d.time_seconds = 0.0, d.speed = 0.0f;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      if (k == 1 && posed) {
        ASSERT_TRUE(crowd->setLivePose(h, waveFrame(frame)).isOk());
      }
    }
    ASSERT_TRUE(crowd->update(0.1, rowCamera()).isOk());
  }
  // The row with its middle instance holding "walk" (speed 0) half-way through a 0.2 s blend
  // towards "wave"'s frame 0: as a live pose handed over to (`twin` false), or as a crossfade
  // to the clip held at that frame (`twin` true).
  void makeHalfway(CrowdManager* crowd, bool twin) {
    initRow(crowd, 1);
    for (int k = 0; k < 3; ++k) {
      InstanceDesc d = rowInstance(k);
      d.speed = 0.0f;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      if (k != 1) continue;
      if (twin)
        ASSERT_TRUE(crowd->crossfade(h, uint32_t(palette().findClip("wave")), 0.2, 0.0).isOk());
      else
        ASSERT_TRUE(crowd->setLivePose(h, waveFrame(0), 0.2).isOk());
    }
    ASSERT_TRUE(crowd->update(0.1, rowCamera()).isOk());
  }
  // `crowd` drawn on `kind` (cleared first).
  std::vector<uint8_t> image(Renderer& r, const CrowdManager& crowd, PathKind kind) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = drawOnPath(r, kind, crowd, rowCamera(), nullptr);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }
  // On `path`: a hand-over half-way draws as the crossfade half-way (to the rounding of the
  // blend's two orders), unlike the pose alone and the clip alone.
  void expectHandOverDraws(Renderer& r, PathKind path) {
    CrowdManager halfway, crossfade, posed, playing;
    makeHalfway(&halfway, false);
    makeHalfway(&crossfade, true);
    makeRow(&posed, true, false);
    makeRow(&playing, false, false);
    const std::vector<uint8_t> handed = image(r, halfway, path);
    const std::vector<uint8_t> faded = image(r, crossfade, path);
    const std::vector<uint8_t> live = image(r, posed, path);
    const std::vector<uint8_t> clip = image(r, playing, path);
    const size_t off = differingPixels(handed, faded);
    std::printf("hand-over vs crossfade: %zu pixels differ\n", off);
    EXPECT_LE(off, 8u);
    EXPECT_GT(differingPixels(handed, live), 200u);
    EXPECT_GT(differingPixels(handed, clip), 200u);
  }
  // On `path`: the posed crowd draws its twin's image exactly and the clip's image not, and
  // another posed crowd of the character, drawn before and between, never shows.
  void expectPosesDraw(Renderer& r, PathKind path) {
    CrowdManager posed, other, twin, playing;
    // Room for 256: its first upload (all 512 frames, 504 KiB) is copied on the crowd's workers
    // (CrowdExport::copyLivePoseTexels).
    makeRow(&posed, true, false, 0, 256);
    makeRow(&other, true, false, 15);  // Another pose in another crowd of the character.
    makeRow(&twin, false, true);
    makeRow(&playing, false, false);
    for (int round = 0; round < 2; ++round) {
      const std::vector<uint8_t> another = image(r, other, path);
      const std::vector<uint8_t> live = image(r, posed, path);
      const std::vector<uint8_t> frame = image(r, twin, path);
      const std::vector<uint8_t> clip = image(r, playing, path);
      EXPECT_GT(differingPixels(live, another), 200u);
      EXPECT_EQ(differingPixels(live, frame), 0u);
      EXPECT_GT(differingPixels(live, clip), 200u);  // The pose moved the middle one.
    }
  }
  static size_t differingPixels(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    size_t n = 0;
    for (size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4)
      n += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
    return n;
  }
  static Camera rowCamera() {
    return Camera::lookAt({0.0, 1.2, 4.5}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                          100.0f);
  }
};

TEST_P(LivePoseRenderTest, APoseDrawsAsTheFrameItHolds) {
  Renderer r;
  makeRenderer(&r);
  for (PathKind path : kLivePaths) {
    SCOPED_TRACE(pathKindName(path));
    expectPosesDraw(r, path);
    expectHandOverDraws(r, path);
  }
}

// Poses set step after step, some instances at a time: the renderer uploads only the frames
// written since its last upload of the crowd, and every step draws the twin that plays the
// frames the poses hold, on the vertex-shader, GPU-driven and CPU-skinning paths (the last
// reads the frames from its copy of the palette, rewritten alike).
TEST_P(LivePoseRenderTest, PosesSetStepAfterStepDrawTheirFrames) {
  Renderer r;
  makeRenderer(&r);
  const BakedPalette& p = palette();
  const uint32_t wave = uint32_t(p.findClip("wave"));
  const BakedClip& clip = p.clips[wave];
  const auto timeOf = [&](uint32_t f) {
    return clip.frame_times_seconds.empty() ? double(f) * clip.frame_interval_seconds
                                            : clip.frame_times_seconds[f];
  };
  for (PathKind path : {PathKind::kInstanced, PathKind::kGpuDriven, PathKind::kCpu}) {
    SCOPED_TRACE(pathKindName(path));
    CrowdManager posed, twin;
    initRow(&posed, 4);
    initRow(&twin, 0);  // No live rows of its own: the posed crowd's stay in the texture.
    std::vector<InstanceHandle> hp(3), ht(3);
    for (int k = 0; k < 3; ++k) {
      InstanceDesc d = rowInstance(k);
      d.clip = wave, d.time_seconds = 0.0, d.speed = 0.0f;
      ASSERT_TRUE(posed.add(d, &hp[size_t(k)]).isOk());
      ASSERT_TRUE(twin.add(d, &ht[size_t(k)]).isOk());
    }
    // Step s poses the instances of bit mask kWho[s] with the (3 s + k)-th of the frames its
    // time samples exactly (fraction 0: the twin draws the stored matrices alone); the others
    // hold theirs.
    std::vector<uint32_t> exact;
    for (uint32_t f = 0; f < clip.frame_count; ++f) {
      const FrameSample at = sampleFrames(clip, timeOf(f));
      if (at.frame == f && at.fraction == 0.0f) exact.push_back(f);
    }
    ASSERT_GE(exact.size(), 4u);
    constexpr uint32_t kWho[] = {0x7, 0x2, 0x5, 0x4, 0x3};
    for (uint32_t step = 0; step < 5; ++step) {
      SCOPED_TRACE("step " + std::to_string(step));
      for (uint32_t k = 0; k < 3; ++k) {
        if (!(kWho[step] >> k & 1u)) continue;
        const uint32_t frame = exact[(3 * step + k) % exact.size()];
        ASSERT_TRUE(posed.setLivePose(hp[k], waveFrame(frame)).isOk());
        ASSERT_TRUE(twin.play(ht[k], wave, timeOf(frame), 0.0f).isOk());
      }
      ASSERT_TRUE(posed.update(0.1, rowCamera()).isOk());
      ASSERT_TRUE(twin.update(0.1, rowCamera()).isOk());
      const std::vector<uint8_t> live = image(r, posed, path);
      const std::vector<uint8_t> frames = image(r, twin, path);
      EXPECT_EQ(differingPixels(live, frames), 0u);
    }
  }
}

// A pose drawn 30 m from its instance (an engine's ragdoll thrown away), in view while its
// clip's sphere is out of it, is drawn on every path: culled by its own bounds
// (BakedPalette::joint_bounds), on the CPU and in GPU-driven culling alike. It draws what an
// instance playing the frame where the pose is drawn draws (to the rounding of the move).
TEST_P(LivePoseRenderTest, APoseAwayFromItsClipIsDrawnWhereItIs) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager posed, twin;
  initRow(&posed, 1);
  initRow(&twin, 0);
  InstanceDesc d = rowInstance(1);
  d.clip = uint32_t(palette().findClip("wave")), d.time_seconds = 0.0, d.speed = 0.0f;
  InstanceHandle h;
  ASSERT_TRUE(twin.add(d, &h).isOk());
  d.position.x += 30.0;
  ASSERT_TRUE(posed.add(d, &h).isOk());
  std::vector<glm::mat4> pose = waveFrame(0);
  for (glm::mat4& m : pose) m[3].x -= 30.0f;
  ASSERT_TRUE(posed.setLivePose(h, pose).isOk());
  ASSERT_TRUE(posed.update(0.1, rowCamera()).isOk());
  ASSERT_TRUE(twin.update(0.1, rowCamera()).isOk());
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));  // What image() clears to.
  std::vector<uint8_t> empty;
  ASSERT_TRUE(context_->readPixels(&empty).isOk());
  for (PathKind path : kLivePaths) {
    SCOPED_TRACE(pathKindName(path));
    const std::vector<uint8_t> live = image(r, posed, path);
    const std::vector<uint8_t> frame = image(r, twin, path);
    EXPECT_GT(differingPixels(frame, empty), 500u);  // The character is in view,
    EXPECT_LE(differingPixels(live, frame), 16u);    // and the pose draws it.
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, LivePoseRenderTest, allBackends(), backendTestName);

// The OpenGL ES profile (GLSL ES 3.00, the vertex-shader path; its texture calls through the
// profile's emulation of direct state access) draws them alike.
class LivePoseEsTest : public LivePoseRenderTest {
 protected:
  bool es() const override { return true; }
};

TEST_P(LivePoseEsTest, APoseDrawsAsTheFrameItHoldsOnEs) {
  Renderer r;
  makeRenderer(&r);
  expectPosesDraw(r, PathKind::kInstanced);
}

INSTANTIATE_TEST_SUITE_P(Backends, LivePoseEsTest, esBackends(), backendTestName);

}  // namespace
}  // namespace si
