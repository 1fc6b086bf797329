// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Root motion applied by the crowd: instances that opt in move by their playback's baked
// motion, the same for any time step, across loops, speed changes, crossfades and setters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "crowd/crowd_test_helpers.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct MovingCrowd {
  CrowdManager crowd;
  Camera camera = test::testCamera({0, 30, -60}, {0, 0, 0});
  uint32_t walk = 0, turn = 0, idle = 0;

  MovingCrowd() {
    CrowdDesc d = test::defaultCrowdDesc();
    d.palette = &test::movingPalette();
    d.worker_threads = 1;
    EXPECT_TRUE(crowd.init(d).isOk());
    walk = uint32_t(test::movingPalette().findClip("walk_forward"));
    turn = uint32_t(test::movingPalette().findClip("walk_turn_left"));
    idle = uint32_t(test::movingPalette().findClip("idle"));
  }
  InstanceHandle add(uint32_t clip, bool root_motion, glm::dvec3 at = {0, 0, 0},
                     glm::quat rotation = glm::quat(1, 0, 0, 0), float scale = 1.0f,
                     float speed = 1.0f) {
    InstanceDesc d;
    d.clip = clip;
    d.position = at;
    d.rotation = rotation;
    d.scale = scale;
    d.speed = speed;
    d.root_motion = root_motion;
    InstanceHandle h;
    EXPECT_TRUE(crowd.add(d, &h).isOk());
    return h;
  }
  InstanceDesc get(InstanceHandle h) {
    InstanceDesc d;
    EXPECT_TRUE(crowd.get(h, &d).isOk());
    return d;
  }
  void run(double seconds, int steps) {
    for (int i = 0; i < steps; ++i) ASSERT_TRUE(crowd.update(seconds / steps, camera).isOk());
  }
};

// Where an instance that started at (at, rotation, scale) playing clip from 0 should be after
// `seconds` of clip time: its start placed by the baked motion.
glm::dvec3 expectedPosition(uint32_t clip, double seconds, glm::dvec3 at, glm::quat rotation,
                            float scale) {
  const GroundMotion m =
      rootMotionBetween(test::movingPalette().clips[clip], LoopMode::kLoop, 0.0, seconds);
  return at + glm::dquat(rotation) * (double(scale) * glm::dvec3(m.translation.x, 0, m.translation.y));
}

TEST(RootMotionCrowd, InstancesThatOptInTravelAndOthersStay) {
  MovingCrowd m;
  const glm::quat facing_x = glm::angleAxis(float(kPi / 2), glm::vec3(0, 1, 0));
  const InstanceHandle walker = m.add(m.walk, true, {5, 0, 5}, facing_x, 2.0f);
  const InstanceHandle still = m.add(m.walk, false, {0, 0, 0});
  const InstanceHandle idle = m.add(m.idle, true, {-5, 0, 0});  // Its clip has no motion.
  m.run(2.5, 150);
  // 2.5 s at 1.3 units/s, twice the size, facing +X.
  const InstanceDesc w = m.get(walker);
  EXPECT_NEAR(w.position.x, 5.0 + 2.0 * 1.3 * 2.5, 1e-4);
  EXPECT_NEAR(w.position.z, 5.0, 1e-4);
  EXPECT_TRUE(w.root_motion);
  EXPECT_LT(glm::length(w.position - expectedPosition(m.walk, 2.5, {5, 0, 5}, facing_x, 2.0f)), 1e-5);  // Float rotation.
  EXPECT_EQ(m.get(still).position, glm::dvec3(0.0));
  EXPECT_FALSE(m.get(still).root_motion);
  EXPECT_EQ(m.get(idle).position, glm::dvec3(-5, 0, 0));
}

// The path does not depend on the step: one 2.7 s update, 162 of 1/60 s, or uneven steps.
TEST(RootMotionCrowd, AnyTimeStepGivesTheSamePath) {
  std::vector<glm::dvec3> ends;
  std::vector<double> headings;
  for (int pattern = 0; pattern < 3; ++pattern) {
    MovingCrowd m;
    const InstanceHandle h = m.add(m.turn, true, {1, 0, 2}, glm::quat(1, 0, 0, 0), 1.0f, 1.3f);
    if (pattern == 0) m.run(2.7, 1);
    if (pattern == 1) m.run(2.7, 162);
    if (pattern == 2) {
      for (double dt : {0.001, 1.1, 0.3, 0.0, 1.299}) ASSERT_TRUE(m.crowd.update(dt, m.camera).isOk());
    }
    const InstanceDesc d = m.get(h);
    ends.push_back(d.position);
    headings.push_back(2.0 * std::atan2(double(d.rotation.y), double(d.rotation.w)));
  }
  for (int p = 1; p < 3; ++p) {
    EXPECT_LT(glm::length(ends[p] - ends[0]), 1e-6) << p;
    EXPECT_NEAR(std::remainder(headings[p] - headings[0], 2 * kPi), 0.0, 1e-5) << p;
  }
  // 2.7 s at speed 1.3: 3.51 s of the clip, pi/4 per second of it.
  EXPECT_NEAR(std::remainder(headings[0] - 3.51 * kPi / 4, 2 * kPi), 0.0, 1e-4);
  const uint32_t turn = uint32_t(test::movingPalette().findClip("walk_turn_left"));
  EXPECT_LT(glm::length(ends[0] - expectedPosition(turn, 3.51, {1, 0, 2}, glm::quat(1, 0, 0, 0),
                                                  1.0f)), 1e-6);
}

// advance() frames (selected on the GPU or by views) move instances as update() frames do;
// play() keeps the path; setTransform() places the instance as of now; opting out stops it.
TEST(RootMotionCrowd, ChangesOfPlaybackKeepThePath) {
  MovingCrowd m;
  const InstanceHandle h = m.add(m.walk, true);
  ASSERT_TRUE(m.crowd.advance(1.0).isOk());  // A GPU-driven frame walks 1.3 units.
  EXPECT_NEAR(m.get(h).position.z, 1.3, 1e-5);
  ASSERT_TRUE(m.crowd.play(h, m.walk, 0.0, 2.0f).isOk());  // Nothing is left to apply.
  EXPECT_NEAR(m.get(h).position.z, 1.3, 1e-5);
  m.run(0.5, 30);  // Twice the speed: another 1.3.
  EXPECT_NEAR(m.get(h).position.z, 2.6, 1e-5);
  ASSERT_TRUE(m.crowd.advance(0.25).isOk());
  EXPECT_NEAR(m.get(h).position.z, 3.25, 1e-5);
  ASSERT_TRUE(m.crowd.setTransform(h, {10, 0, 0}, glm::quat(1, 0, 0, 0), 1.0f).isOk());
  m.run(0.25, 1);  // Only what follows the setTransform.
  EXPECT_NEAR(m.get(h).position.z, 0.65, 1e-5);
  EXPECT_NEAR(m.get(h).position.x, 10.0, 1e-9);
  ASSERT_TRUE(m.crowd.advance(0.25).isOk());
  ASSERT_TRUE(m.crowd.setRootMotion(h, false).isOk());
  EXPECT_NEAR(m.get(h).position.z, 1.3, 1e-5);
  m.run(1.0, 10);
  EXPECT_NEAR(m.get(h).position.z, 1.3, 1e-5);
  ASSERT_TRUE(m.crowd.setRootMotion(h, true).isOk());  // From now on.
  m.run(0.5, 5);
  EXPECT_NEAR(m.get(h).position.z, 2.6, 1e-5);
  InstanceHandle stale = h;
  ASSERT_TRUE(m.crowd.remove(h).isOk());
  EXPECT_EQ(m.crowd.setRootMotion(stale, true).code(), StatusCode::kNotFound);
}

// During a crossfade from standing to walking the instance speeds up with the weight; once the
// fade is over it walks at the clip's speed.
TEST(RootMotionCrowd, CrossfadesBlendTheMotionByWeight) {
  MovingCrowd m;
  const InstanceHandle h = m.add(m.idle, true);
  ASSERT_TRUE(m.crowd.crossfade(h, m.walk, 1.0).isOk());
  std::vector<double> z = {0.0};
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(m.crowd.update(0.1, m.camera).isOk());
    z.push_back(m.get(h).position.z);
  }
  // Step i + 1 covers [0.1 i, 0.1 (i + 1)]: 1.3 x 0.1 x the weight at its middle.
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(z[size_t(i) + 1] - z[size_t(i)], 0.13 * (0.1 * i + 0.05), 1e-5) << i;
  for (int i = 10; i < 20; ++i) EXPECT_NEAR(z[size_t(i) + 1] - z[size_t(i)], 0.13, 1e-5) << i;
}

// Without instances that opt in, update() leaves the exported state alone; with one it changes.
TEST(RootMotionCrowd, OnlyMovingInstancesChangeTheState) {
  MovingCrowd m;
  const InstanceHandle h = m.add(m.walk, false);
  m.run(0.1, 1);
  const uint64_t v = CrowdExport(m.crowd).stateVersion();
  m.run(0.1, 1);
  EXPECT_EQ(CrowdExport(m.crowd).stateVersion(), v);
  ASSERT_TRUE(m.crowd.setRootMotion(h, true).isOk());
  const uint64_t w = CrowdExport(m.crowd).stateVersion();
  EXPECT_NE(w, v);
  m.run(0.1, 1);
  EXPECT_NE(CrowdExport(m.crowd).stateVersion(), w);
  // addRandom opts every instance in when asked.
  const glm::dvec3 spots[] = {{3, 0, 3}, {6, 0, 6}};
  RandomCrowdDesc r;
  r.positions = spots;
  r.clips = Span<const uint32_t>(&m.walk, 1);
  r.root_motion = true;
  std::vector<InstanceHandle> added;
  ASSERT_TRUE(m.crowd.addRandom(r, &added).isOk());
  for (InstanceHandle a : added) EXPECT_TRUE(m.get(a).root_motion);
  m.run(0.5, 3);
  for (size_t i = 0; i < added.size(); ++i)
    EXPECT_NEAR(glm::length(m.get(added[i]).position - spots[i]), 0.65 * m.get(added[i]).speed, 1e-4);
}

// What the crowd says is drawn (jointMatrix: the in-place palette at the moved instance) is the
// reference's travelling pose placed where the instance started, within the bake's error.
TEST(RootMotionCrowd, JointsFollowTheReferencePathOfTheTravellingClip) {
  MovingCrowd m;
  const Character& c = test::movingCharacter();
  const glm::dvec3 start(4, 0, -3);
  const glm::quat rotation = glm::angleAxis(0.3f, glm::vec3(0, 1, 0));
  const InstanceHandle h = m.add(m.turn, true, start, rotation, 1.5f);
  Clip moving = c.clips[m.turn];
  moving.root_motion.extract = false;
  const int32_t hand = c.skeleton.findJoint("r_hand");
  ASSERT_GE(hand, 0);
  const glm::dmat4 world0 = glm::translate(glm::dmat4(1.0), start) *
                            glm::mat4_cast(glm::dquat(rotation)) *
                            glm::scale(glm::dmat4(1.0), glm::dvec3(1.5));
  double worst = 0.0;
  for (int frame = 1; frame <= 100; ++frame) {
    m.run(0.037, 1);
    const double t = 0.037 * frame;
    glm::dmat4 drawn;
    ASSERT_TRUE(m.crowd.jointMatrix(h, uint32_t(hand), &drawn).isOk());
    ReferencePose pose;
    ASSERT_TRUE(evaluatePose(c.skeleton, moving, std::fmod(t, 1.0), &pose).isOk());
    // Whole cycles so far, then this cycle's reference pose.
    const GroundMotion cycles = repeatGroundMotion(
        summarizeRootMotion(test::movingPalette().clips[m.turn]).whole_clip, uint64_t(t / 1.0));
    const glm::dmat4 reference = world0 * groundMotionMatrix(cycles) * pose.skinning[size_t(hand)];
    const glm::dvec4 bind_hand = glm::inverse(glm::dmat4(c.skeleton.inverse_bind_matrices[size_t(hand)]))[3];
    worst = std::max(worst, glm::length(glm::dvec3(drawn * bind_hand - reference * bind_hand)));
  }
  EXPECT_LT(worst, 1e-3 * 1.5 * c.height()) << worst;  // 30 Hz linear bake of the walk.
  EXPECT_GT(glm::length(m.get(h).position - start), 3.0);  // It did travel.
}

// Root motion that moves nothing the store can see (a step below the position's precision) but
// re-normalizes a rotation holding -0 into +0 changes the exported bytes: changedSince names it,
// so the GPU-driven upload does not keep the old bytes (found by the crowd API fuzzer).
TEST(RootMotionCrowd, ATurnThatOnlyFlipsAZerosSignIsAChange) {
  MovingCrowd m;
  const glm::dvec3 far(1e17, 0, 1e17);
  const InstanceHandle h = m.add(m.walk, true, far);
  ASSERT_TRUE(m.crowd.update(1.0 / 60.0, m.camera).isOk());
  ASSERT_TRUE(m.crowd.setTransform(h, far, glm::quat(1.0f, 0.0f, -0.0f, 0.0f), 1.0f).isOk());
  std::vector<GpuInstanceState> before, after;
  CrowdExport(m.crowd).state(&before, nullptr);
  const uint64_t version = CrowdExport(m.crowd).stateVersion();
  ASSERT_TRUE(m.crowd.update(1.0 / 60.0, m.camera).isOk());
  CrowdExport(m.crowd).state(&after, nullptr);
  ASSERT_EQ(std::memcmp(after[0].position, before[0].position, 24),
            0);  // The step is below its precision.
  ASSERT_TRUE(std::signbit(before[0].rotation[1]));
  ASSERT_NE(std::memcmp(&before[0], &after[0], sizeof(GpuInstanceState)), 0);
  std::vector<DenseRange> changed;
  CrowdExport(m.crowd).changedSince(version, &changed, nullptr);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].first, 0u);
}

}  // namespace
}  // namespace si
