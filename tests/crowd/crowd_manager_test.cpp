// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "crowd/crowd_test_helpers.h"
#include "crowd/playback.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {
using test::defaultCrowdDesc;
using test::defaultPalette;
using test::testCamera;

TEST(CrowdManager, InitValidityMatrix) {
  CrowdManager crowd;
  EXPECT_EQ(crowd.init(CrowdDesc()).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  CrowdDesc d = defaultCrowdDesc();
  d.sub_mesh_count = 33;
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = defaultCrowdDesc();
  d.lod_count = 9;
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = defaultCrowdDesc();
  d.lod_distances_radii = {30.0f, 20.0f};
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d.lod_distances_radii = {30.0f};
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = defaultCrowdDesc();
  d.character_radius = -1.0f;
  EXPECT_EQ(crowd.init(d).code(), StatusCode::kInvalidArgument);
  d = defaultCrowdDesc();
  d.lod_hysteresis_ratio = 1.5f;
  const Status hysteresis = crowd.init(d);
  EXPECT_EQ(hysteresis.code(), StatusCode::kInvalidArgument);
  // The message names the field that is wrong, and only that one.
  EXPECT_NE(hysteresis.message().find("lod_hysteresis_ratio"), std::string::npos);
  EXPECT_EQ(hysteresis.message().find("max_distance_radii"), std::string::npos)
      << hysteresis.message();
  const CrowdDesc r = resolveDefaults(defaultCrowdDesc());
  EXPECT_EQ(r.lod_distances_radii, (std::vector<float>{20.0f, 60.0f}));
  EXPECT_EQ(r.max_distance_radii, 100.0f);
  EXPECT_GT(r.character_radius, 0.5f);
}

TEST(CrowdManager, AddValidityAndStaleHandles) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  InstanceDesc d;
  InstanceHandle a, b, untouched;
  ASSERT_TRUE(crowd.add(d, &a).isOk());
  ASSERT_TRUE(crowd.add(d, &b).isOk());
  InstanceDesc bad = d;
  bad.clip = 99;
  EXPECT_EQ(crowd.add(bad, &untouched).code(), StatusCode::kInvalidArgument);
  bad = d;
  bad.scale = 0.0f;
  EXPECT_EQ(crowd.add(bad, &untouched).code(), StatusCode::kInvalidArgument);
  bad = d;
  bad.position.x = NAN;
  EXPECT_EQ(crowd.add(bad, &untouched).code(), StatusCode::kInvalidArgument);
  bad = d;
  bad.speed = -1.0f;
  EXPECT_EQ(crowd.add(bad, &untouched).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(untouched.id, 0u);
  EXPECT_EQ(crowd.size(), 2u);

  ASSERT_TRUE(crowd.remove(a).isOk());
  EXPECT_FALSE(crowd.contains(a));
  EXPECT_EQ(crowd.remove(a).code(), StatusCode::kNotFound);
  EXPECT_EQ(crowd.setColor(a, glm::u8vec4(1)).code(), StatusCode::kNotFound);
  EXPECT_EQ(crowd.play(a, 0, 0.0, 1.0f).code(), StatusCode::kNotFound);
  InstanceHandle c;
  ASSERT_TRUE(crowd.add(d, &c).isOk());  // Reuses a's slot.
  EXPECT_FALSE(crowd.contains(a));       // The stale handle never aliases the new instance.
  EXPECT_EQ(crowd.setVariationMask(a, 0).code(), StatusCode::kNotFound);
  InstanceDesc got;
  ASSERT_TRUE(crowd.setVariationMask(c, 5).isOk());
  ASSERT_TRUE(crowd.get(c, &got).isOk());
  EXPECT_EQ(got.variation_mask, 5u);
  ASSERT_TRUE(crowd.get(b, &got).isOk());
  EXPECT_EQ(got.variation_mask, 0xFFFFFFFFu);
}

TEST(CrowdManager, RemoveKeepsOtherInstancesIntact) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  std::vector<InstanceHandle> hs;
  for (int i = 0; i < 10; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(i, 0, 0);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    hs.push_back(h);
  }
  for (int i : {0, 5, 9, 3}) ASSERT_TRUE(crowd.remove(hs[size_t(i)]).isOk());
  for (int i = 0; i < 10; ++i) {
    InstanceDesc got;
    const Status s = crowd.get(hs[size_t(i)], &got);
    if (i == 0 || i == 5 || i == 9 || i == 3) {
      EXPECT_EQ(s.code(), StatusCode::kNotFound);
    } else {
      ASSERT_TRUE(s.isOk());
      EXPECT_EQ(got.position.x, double(i));
    }
  }
}

// identity() names one crowd from its init() on: state changes keep it, another crowd or a new
// init() gets another; the exported state names each instance's handle.
TEST(CrowdManager, IdentityNamesOneInitOfOneCrowd) {
  CrowdManager a, b;
  EXPECT_EQ(a.identity(), 0u);
  ASSERT_TRUE(a.init(defaultCrowdDesc()).isOk());
  ASSERT_TRUE(b.init(defaultCrowdDesc()).isOk());
  const uint64_t first = a.identity();
  EXPECT_NE(first, 0u);
  EXPECT_NE(b.identity(), first);
  InstanceHandle h, g;
  ASSERT_TRUE(a.add(InstanceDesc(), &h).isOk());
  ASSERT_TRUE(a.add(InstanceDesc(), &g).isOk());
  ASSERT_TRUE(a.play(h, 0, 0.2, 1.5f).isOk());
  ASSERT_TRUE(a.remove(h).isOk());
  EXPECT_EQ(a.identity(), first);
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> handles;
  CrowdExport(a).state(&state, &handles);
  ASSERT_EQ(state.size(), 1u);
  EXPECT_EQ(state[0].handle, g.id);
  ASSERT_TRUE(a.init(defaultCrowdDesc()).isOk());
  EXPECT_NE(a.identity(), first);
  EXPECT_NE(a.identity(), b.identity());
}

TEST(CrowdManager, AddRandomIsSeededAndDeterministic) {
  std::vector<glm::dvec3> positions;
  for (int i = 0; i < 200; ++i) positions.push_back(glm::dvec3(i % 20, 0, i / 20) * 2.0);
  RandomCrowdDesc r;
  r.positions = positions;
  r.seed = 42;
  r.required_mask = 1;
  r.optional_mask = 0xE;
  const auto masks = [&](uint64_t seed) {
    CrowdManager crowd;
    EXPECT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
    RandomCrowdDesc rr = r;
    rr.seed = seed;
    std::vector<InstanceHandle> hs;
    EXPECT_TRUE(crowd.addRandom(rr, &hs).isOk());
    std::vector<uint32_t> out;
    for (InstanceHandle h : hs) {
      InstanceDesc d;
      EXPECT_TRUE(crowd.get(h, &d).isOk());
      out.push_back(d.variation_mask);
    }
    return out;
  };
  const std::vector<uint32_t> a = masks(42), b = masks(42), c = masks(43);
  ASSERT_EQ(a.size(), 200u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  size_t distinct = 0;
  std::vector<bool> seen(16, false);
  for (uint32_t m : a) {
    EXPECT_EQ(m & 1u, 1u);       // The body is always worn.
    EXPECT_EQ(m & ~0xFu, 0u);    // Nothing outside the masks.
    if (!seen[m]) distinct++, seen[m] = true;
  }
  EXPECT_EQ(distinct, 8u);  // Every combination of 3 optional pieces occurs among 200.
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const uint32_t bad_clip[] = {7};
  r.clips = bad_clip;
  EXPECT_EQ(crowd.addRandom(r, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.size(), 0u);  // Nothing added on failure.
}

TEST(CrowdManager, AWeekAt60HzStillChoosesTheExactFrame) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const uint32_t walk = uint32_t(defaultPalette().findClip("walk"));
  InstanceDesc d;
  d.clip = walk;  // 1.0 s loop.
  d.time_seconds = 0.0123;
  d.position = glm::dvec3(1e6, 0, 0);  // Far away: culled, only its time matters.
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = testCamera({0, 1.5, -5}, {0, 1, 0});
  const uint64_t frames = 7ull * 24 * 3600 * 60;
  float naive = 0.0f;  // What a float clock would do.
  // update() and advance() step the one accumulator: every frame steps it, advance() (O(1)
  // here) most frames, one frame a simulated minute the whole update (36M updates took 80 s
  // under ASan).
  for (uint64_t f = 0; f < frames; ++f) {
    if (f % 3600 == 0) {
      ASSERT_TRUE(crowd.update(1.0 / 60.0, camera).isOk());
    } else {
      ASSERT_TRUE(crowd.advance(1.0 / 60.0).isOk());
    }
    naive += 1.0f / 60.0f;
  }
  // Exactly: a week is 604800 s, a whole number of 1 s loops, so the clip is back at 0.0123 s.
  EXPECT_NEAR(crowd.clockSeconds(), 604800.0, 1e-6);
  InstanceDesc got;
  ASSERT_TRUE(crowd.get(h, &got).isOk());
  EXPECT_NEAR(got.time_seconds, 0.0123, 1e-6);
  const BakedClip& clip = defaultPalette().clips[walk];
  const FrameSample s = detail::clipFrameSample(clip, got.time_seconds);
  const FrameSample expected = detail::clipFrameSample(clip, 0.0123);
  EXPECT_EQ(s.frame, expected.frame);
  EXPECT_NEAR(s.fraction, expected.fraction, 1e-4f);
  // A float clock stalls once its step exceeds twice 1/60 s: days behind by now.
  EXPECT_GT(std::fabs(double(naive) - 604800.0), 1000.0);
}

TEST(CrowdManager, OnceClipsHoldTheirLastFrameAndLoopsWrap) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  InstanceDesc d;
  d.clip = uint32_t(p.findClip("wave"));  // 2.5 s, plays once.
  InstanceHandle once, loop;
  ASSERT_TRUE(crowd.add(d, &once).isOk());
  d.clip = uint32_t(p.findClip("walk"));
  ASSERT_TRUE(crowd.add(d, &loop).isOk());
  const Camera camera = testCamera({0, 1.5, -5}, {0, 1, 0});
  ASSERT_TRUE(crowd.update(3.25, camera).isOk());
  InstanceDesc got;
  ASSERT_TRUE(crowd.get(once, &got).isOk());
  EXPECT_EQ(got.time_seconds, 2.5);
  ASSERT_TRUE(crowd.get(loop, &got).isOk());
  EXPECT_NEAR(got.time_seconds, 0.25, 1e-12);
  const FrameSample s = detail::clipFrameSample(p.clips[size_t(p.findClip("wave"))], 2.5);
  EXPECT_EQ(s.next_frame, p.clips[size_t(p.findClip("wave"))].frame_count - 1);
  EXPECT_EQ(s.fraction, 1.0f);
}

TEST(CrowdManager, RecordsAreCameraRelativeAndPreciseFarFromTheOrigin) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const glm::dvec3 far(100000.37, 2.25, -100000.81);  // 100 km from the origin.
  InstanceDesc d;
  d.position = far;
  d.scale = 2.0f;
  d.rotation = glm::angleAxis(0.5f, glm::vec3(0, 1, 0));
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const glm::dvec3 eye = far + glm::dvec3(3.1, 1.5, 4.2);
  ASSERT_TRUE(crowd.update(0.0, testCamera(eye, far)).isOk());
  ASSERT_EQ(crowd.view().stats().visible, 1u);
  const InstanceRecord& r = crowd.view().records()[0];
  const glm::dvec3 rel = far - eye;
  for (int row = 0; row < 3; ++row) EXPECT_NEAR(r.world_rows[row][3], rel[row], 1e-6);
  // Without camera-relative doubles, float positions 100 km out are off by millimetres.
  const float naive = float(far.x) - float(eye.x);
  EXPECT_GT(std::fabs(double(naive) - rel.x), 1e-4);
  // The 3x3 part is rotation * scale.
  const glm::mat3 m = glm::mat3_cast(d.rotation) * 2.0f;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) EXPECT_NEAR(r.world_rows[row][col], m[col][row], 1e-6);
}

TEST(CrowdManager, RecordBytesMatchTheStd140Layout) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  InstanceDesc d;
  d.position = glm::dvec3(1, 0, 5);
  d.color = glm::u8vec4(10, 20, 30, 255);
  d.custom_layer = 40;
  d.clip = uint32_t(p.findClip("idle"));
  d.time_seconds = 0.5;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.update(0.0, testCamera({0, 1, 0}, {1, 1, 5})).isOk());
  ASSERT_EQ(crowd.view().records().size(), 1u);
  uint8_t bytes[80];
  std::memcpy(bytes, &crowd.view().records()[0], 80);
  const auto f32 = [&](size_t o) { float v; std::memcpy(&v, bytes + o, 4); return v; };
  const auto u32 = [&](size_t o) { uint32_t v; std::memcpy(&v, bytes + o, 4); return v; };
  // vec4 world_rows[3] at 0, 16, 32: identity rotation, translation (1, -1, 5) in w.
  EXPECT_EQ(f32(0), 1.0f);
  EXPECT_EQ(f32(12), 1.0f);
  EXPECT_EQ(f32(20), 1.0f);
  EXPECT_EQ(f32(28), -1.0f);
  EXPECT_EQ(f32(40), 1.0f);
  EXPECT_EQ(f32(44), 5.0f);
  // uvec4 frames at 48: frame texel = clip first texel + frame * frame stride.
  const BakedClip& idle = p.clips[d.clip];
  const FrameSample s = sampleFrames(idle, 0.5);
  EXPECT_EQ(u32(48), idle.first_texel + s.frame * p.layout.frame_stride_texels);
  EXPECT_EQ(u32(52), idle.first_texel + s.next_frame * p.layout.frame_stride_texels);
  EXPECT_EQ(u32(56), u32(48));  // No crossfade: B repeats A.
  // uvec4 blend at 64: fraction bits, fraction B, weight 0, appearance (tint RGB8 with R in
  // the low byte, custom layer select in the high byte).
  EXPECT_EQ(f32(64), s.fraction);
  EXPECT_EQ(f32(72), 0.0f);
  EXPECT_EQ(u32(76), 10u | (20u << 8) | (30u << 16) | (40u << 24));
}

TEST(CrowdManager, TintAndCustomLayerShareTheAppearanceWord) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(0, 0, 5);
  d.color = glm::u8vec4(1, 2, 3, 128);  // A tint with alpha: refused, nothing added.
  InstanceHandle h;
  const Status refused = crowd.add(d, &h);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("custom_layer"), std::string::npos) << refused.message();
  EXPECT_EQ(crowd.size(), 0u);
  d.color = glm::u8vec4(1, 2, 3, 255);
  d.custom_layer = 7;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = testCamera({0, 1, 0}, {0, 1, 5});
  const auto word = [&] {
    EXPECT_TRUE(crowd.update(0.0, camera).isOk());
    return crowd.view().records().empty() ? 0u : crowd.view().records()[0].blend[3];
  };
  EXPECT_EQ(word(), packAppearance(1, 2, 3, 7));
  EXPECT_EQ(crowd.setColor(h, glm::u8vec4(9, 8, 7, 0)).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(word(), packAppearance(1, 2, 3, 7));  // The refused tint changed nothing.
  ASSERT_TRUE(crowd.setColor(h, glm::u8vec4(9, 8, 7, 255)).isOk());
  EXPECT_EQ(word(), packAppearance(9, 8, 7, 7));  // The layer stays.
  ASSERT_TRUE(crowd.setCustomLayer(h, 200).isOk());
  EXPECT_EQ(word(), packAppearance(9, 8, 7, 200));  // The tint stays.
  InstanceDesc got;
  ASSERT_TRUE(crowd.get(h, &got).isOk());
  EXPECT_EQ(got.color, glm::u8vec4(9, 8, 7, 255));
  EXPECT_EQ(got.custom_layer, 200);
  EXPECT_EQ(crowd.setCustomLayer(InstanceHandle{}, 1).code(), StatusCode::kNotFound);
}

TEST(CrowdManager, CrossfadeWeightsAndEndOfBlend) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  InstanceDesc d;
  d.position = glm::dvec3(0, 0, 5);
  d.clip = uint32_t(p.findClip("walk"));
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = testCamera({0, 1, 0}, {0, 1, 5});
  const uint32_t run = uint32_t(p.findClip("run"));
  EXPECT_EQ(crowd.crossfade(h, run, 0.0).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(crowd.crossfade(h, run, 0.5).isOk());
  const auto weight = [&] {
    float w;
    std::memcpy(&w, &crowd.view().records()[0].blend[2], 4);
    return w;
  };
  ASSERT_TRUE(crowd.update(0.125, camera).isOk());
  EXPECT_NEAR(weight(), 0.25f, 1e-6f);
  // A carries the old clip (walk), B the new one (run).
  const uint32_t walk_first = p.clips[size_t(p.findClip("walk"))].first_texel;
  const uint32_t run_first = p.clips[run].first_texel;
  EXPECT_GE(crowd.view().records()[0].frames[0], walk_first);
  EXPECT_LT(crowd.view().records()[0].frames[0], run_first > walk_first ? run_first : UINT32_MAX);
  EXPECT_GE(crowd.view().records()[0].frames[2], run_first);
  ASSERT_TRUE(crowd.update(0.25, camera).isOk());
  EXPECT_NEAR(weight(), 0.75f, 1e-6f);
  ASSERT_TRUE(crowd.update(0.125, camera).isOk());  // Exactly the end of the blend.
  EXPECT_EQ(weight(), 0.0f);                         // Over: only the new clip remains...
  EXPECT_GE(crowd.view().records()[0].frames[0], run_first);  // ...and it is in A.
  EXPECT_EQ(crowd.view().records()[0].frames[0], crowd.view().records()[0].frames[2]);
  InstanceDesc got;
  ASSERT_TRUE(crowd.get(h, &got).isOk());
  EXPECT_EQ(got.clip, run);
  EXPECT_NEAR(got.time_seconds, 0.5, 1e-12);  // The new clip played during the blend.
}

// A crossfade ends by the clock, not by a pass over the crowd: after advance() steps past its
// end, a view selects the new clip alone, exactly as update() at the same clock does (the GPU's
// culling pass reads the end the same way).
TEST(CrowdManager, ACrossfadeEndsByTheClockWhateverSteppedIt) {
  const BakedPalette& p = defaultPalette();
  const Camera camera = testCamera({0, 1, 0}, {0, 1, 5});
  const uint32_t run = uint32_t(p.findClip("run"));
  InstanceRecord drawn[2];
  for (int by_advance = 0; by_advance < 2; ++by_advance) {
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
    InstanceDesc d;
    d.position = glm::dvec3(0, 0, 5);
    d.clip = uint32_t(p.findClip("walk"));
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    ASSERT_TRUE(crowd.crossfade(h, run, 0.5).isOk());
    CrowdView view;
    ASSERT_TRUE(view.init(crowd).isOk());
    if (by_advance) {
      ASSERT_TRUE(crowd.advance(0.625).isOk());
    } else {
      ASSERT_TRUE(crowd.update(0.625, camera).isOk());
    }
    ASSERT_TRUE(view.select(camera).isOk());
    ASSERT_EQ(view.records().size(), 1u);
    drawn[by_advance] = view.records()[0];
    EXPECT_EQ(drawn[by_advance].blend[2], 0u) << by_advance;  // Weight 0: no clip B.
    EXPECT_EQ(drawn[by_advance].frames[0], drawn[by_advance].frames[2]) << by_advance;
    EXPECT_GE(drawn[by_advance].frames[0], p.clips[run].first_texel) << by_advance;
  }
  EXPECT_EQ(std::memcmp(&drawn[0], &drawn[1], sizeof(InstanceRecord)), 0);
}

// Updates the crowd with the camera on +Z at `distance` looking at the origin (where the one
// instance `h` stands, so it is never frustum-culled) and returns its LOD, or 99 when culled.

}  // namespace
}  // namespace si
