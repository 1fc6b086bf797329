#include "si/crowd/crowd_export.h"
// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The frame builder's block path (positions and rotations loaded from the store's columns,
// rows, times and frames 8 lanes at a time, records transposed and stored 8 at a time) against
// its one-instance reference, detail::scalarRecord: every visible instance's record, byte for
// byte, with crossfades at every stage, animation-LOD stepping, clips with frame times, clips
// played once past their end and times the lanes cannot compute.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "crowd/crowd_test_helpers.h"
#include "crowd/frame_builder.h"

namespace si {
namespace {

struct Scene {
  detail::InstanceStore store;
  std::vector<detail::ClipTiming> clips;
  CrowdManager crowd;  // Empty: only its cullParams() are used.
};

// Initializes the scene's crowd with `d` and an empty store of the default palette.
void initScene(Scene& s, const CrowdDesc& d) {
  const BakedPalette& p = test::defaultPalette();
  ASSERT_TRUE(s.crowd.init(d).isOk());
  s.store.reset(&p);
  for (const BakedClip& c : p.clips) s.clips.push_back(detail::makeClipTiming(c));
  s.store.clip_timings = &s.clips;
}

// The inputs of a frame of `s` at `clock` for `camera`, its events into `events`.
detail::FrameInputs frameInputs(const Scene& s, const Camera& camera, double clock,
                                std::vector<std::vector<AnimationEvent>>* events) {
  detail::FrameInputs in;
  in.palette = &test::defaultPalette();
  in.clips = &s.clips;
  in.params = CrowdExport::cullParams(s.crowd.view(), camera);
  in.camera_position = camera.position;
  in.clock = clock;
  in.sub_mesh_count = s.crowd.desc().sub_mesh_count;
  in.chunk_events = events;
  return in;
}

// `n` instances on a grid 1.5 m apart, 100 to a row, with random rotations, scales, tints,
// clips, times and speeds; of every 8, two crossfading (begun up to their blend time ago), one
// at a start time of 9.1e15 s (a loop past 2^53 intervals: the lanes defer it to scalar code)
// and one played once from far past its end. Animation-LOD stepping from LOD 1 at 7.5 Hz.
void fill(Scene& s, uint32_t n, double clock) {
  const BakedPalette& p = test::defaultPalette();
  CrowdDesc d = test::defaultCrowdDesc();
  d.max_distance_radii = -1.0f;
  d.lod_distances_radii = {80.0f, 90.0f};
  d.animation_lod_start = 1;
  d.animation_lod_rate_hz = 7.5f;
  initScene(s, d);
  if (::testing::Test::HasFatalFailure()) return;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const uint32_t clip_count = uint32_t(p.clips.size());
  for (uint32_t k = 0; k < n; ++k) {
    InstanceDesc one;
    one.position = {double(k % 100) * 1.5 + u(rng) * 0.3, 0.0, double(k / 100) * 1.5};
    one.rotation = glm::normalize(glm::quat(float(u(rng)), float(u(rng)), float(u(rng)), 0.3f));
    one.scale = float(0.6 + u(rng));
    one.color = glm::u8vec4(uint8_t(rng()), uint8_t(rng()), uint8_t(rng()), 255);
    one.clip = uint32_t(rng() % clip_count);
    one.time_seconds = u(rng) * 4.0;
    one.speed = float(0.25 + u(rng) * 2.0);
    InstanceHandle h;
    ASSERT_TRUE(s.store.validate(one).isOk());
    ASSERT_TRUE(s.store.handles.allocate(&h).isOk());
    s.store.push(one, h, clock);
    const uint32_t other = uint32_t(rng() % clip_count);
    const double blend = 0.2 + u(rng) * 2.0;
    switch (k % 8) {
      case 1:
      case 2:
        ASSERT_TRUE(s.store.crossfade(h, other, blend, u(rng), clock - u(rng) * blend).isOk());
        break;
      case 3:
        ASSERT_TRUE(s.store.play(h, other, 9.1e15, 1.0f, clock).isOk());
        break;
      case 4:
        one.loop_mode = LoopMode::kOnce;
        ASSERT_TRUE(s.store.play(h, other, 1e6, 3.0f, clock).isOk());
        break;
      default:
        break;
    }
  }
}

struct Coverage {
  uint32_t per_lod[8] = {}, records = 0, fading = 0, stepped = 0, frame_times = 0, huge_times = 0;
};

// Builds a frame of `s` at `clock` for `camera` and checks every record against scalarRecord.
void expectBlocksEqualReference(Scene& s, const Camera& camera, double clock, uint32_t threads,
                                Coverage* cover) {
  std::vector<std::vector<AnimationEvent>> events(detail::chunkCount(s.store.size()));
  WorkerPool pool(threads);
  const ParallelFor parallel_for = [&pool](uint32_t count, const ParallelTask& task) {
    pool.run(count, task);
  };
  detail::FrameInputs in = frameInputs(s, camera, clock, &events);
  in.parallel_for = &parallel_for;
  in.simulate = true;
  detail::CrowdFrame f;
  detail::buildFrame(in, s.store, &f);
  const uint32_t groups = uint32_t(f.group_masks.size());
  for (uint32_t slot = 0; slot < f.stats.visible; ++slot) {
    uint32_t i = 0;
    ASSERT_TRUE(s.store.denseIndex(f.visible_handles[slot], &i).isOk());
    const uint32_t key =
        uint32_t(std::upper_bound(f.key_offsets.begin(), f.key_offsets.end(), slot) -
                 f.key_offsets.begin()) -
        1;
    const uint32_t lod = key / groups;
    InstanceRecord want;
    detail::scalarRecord(in, s.store, i, lod, &want);
    ASSERT_EQ(std::memcmp(&f.records[slot], &want, sizeof want), 0)
        << "record " << slot << " (instance " << i << ", LOD " << lod << ", clip "
        << s.store.playback[i].clip << ", fading " << (s.store.fade_duration[i] > 0.0) << ")";
    ++cover->records;
    ++cover->per_lod[lod];
    cover->fading += s.store.fade_duration[i] > 0.0;
    cover->stepped += lod >= in.params.animation_lod_start;
    cover->frame_times += !s.clips[s.store.playback[i].clip].uniform;
    cover->huge_times += s.store.playback[i].start_time > 1e15;
  }
}

TEST(RecordBlocks, EveryRecordEqualsTheOneInstanceReference) {
  Scene s;
  double clock = 100.0;
  fill(s, 10000, clock);
  // Above the field, every instance in view (consecutive blocks: vector loads), then at its
  // edge looking across (scattered visible instances: gathers), on 1 and 3 threads.
  const Camera above = test::testCamera({75.0, 180.0, 75.5}, {75.0, 0.0, 75.0});
  const Camera edge = test::testCamera({75.0, 2.0, -8.0}, {75.0, 0.0, 60.0});
  Coverage cover;
  for (int frame = 0; frame < 4; ++frame) {
    clock += 0.37;
    expectBlocksEqualReference(s, frame % 2 == 0 ? above : edge, clock, frame < 2 ? 1 : 3, &cover);
    if (HasFatalFailure()) return;
  }
  // The frames reached what the block path must get right besides the common case.
  EXPECT_GT(cover.records, 10000u);
  for (uint32_t lod = 0; lod < 3; ++lod) EXPECT_GT(cover.per_lod[lod], 1000u) << lod;
  EXPECT_GT(cover.fading, 1000u);
  EXPECT_GT(cover.stepped, 1000u);
  EXPECT_GT(cover.frame_times, 1000u);
  EXPECT_GT(cover.huge_times, 500u);
}

// Culling keeps a crossfading instance while either clip's bounding sphere is in view: blocks
// where no lane fades test one sphere, the others both. Clip 1's sphere is moved 60 m ahead of
// the instances, which stand 30 m behind the camera: only the 19 that fade from clip 1 to clip
// 0 are visible, in blocks with and without other fading lanes.
TEST(RecordBlocks, ACrossfadeIsKeptWhileEitherClipsSphereIsInView) {
  Scene s;
  initScene(s, test::defaultCrowdDesc());
  ASSERT_FALSE(HasFatalFailure());
  s.clips[1].sphere_center = {0.0f, 0.0f, 60.0f};
  s.clips[1].sphere_radius = 1.0f;
  const double clock = 10.0;
  std::vector<bool> fading;
  for (uint32_t k = 0; k < 40; ++k) {
    InstanceDesc one;
    one.position = {double(k % 8) - 4.0, 0.0, -30.0};
    one.clip = 1;
    InstanceHandle h;
    ASSERT_TRUE(s.store.handles.allocate(&h).isOk());
    s.store.push(one, h, clock);
    // Lanes 0-7: three fade; 8-15 and 24-31: none; 16-23 and 32-39: every one.
    const bool fades = (k >= 16 && k < 24) || k >= 32 || (k < 8 && k % 3 == 0);
    ASSERT_TRUE(fades ? s.store.crossfade(h, 0, 100.0, 0.0, clock).isOk()
                      : s.store.play(h, 0, 0.0, 1.0f, clock).isOk());
    fading.push_back(fades);
  }
  const Camera camera = test::testCamera({0.0, 2.0, 0.0}, {0.0, 0.0, 100.0});
  std::vector<std::vector<AnimationEvent>> events(1);
  const detail::FrameInputs in = frameInputs(s, camera, clock + 1.0, &events);
  detail::CrowdFrame f;
  detail::buildFrame(in, s.store, &f);
  uint32_t want = 0;
  for (bool b : fading) want += b;
  ASSERT_EQ(want, 19u);
  EXPECT_EQ(f.stats.visible, want);
  for (uint32_t slot = 0; slot < f.stats.visible; ++slot) {
    uint32_t i = 0;
    ASSERT_TRUE(s.store.denseIndex(f.visible_handles[slot], &i).isOk());
    EXPECT_TRUE(fading[i]) << i;
  }
}

}  // namespace
}  // namespace si
