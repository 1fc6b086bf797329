// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Live poses in motion vectors: an instance posed with one baked frame, then another, draws
// the motion of a twin that plays the first frame, then the second, on both skinning paths of
// drawCrowd and of the GPU-driven path (each live pose keeps two frames, so the previous
// record still reads the previous pose, from the crowd's previous records or from what the
// GPU-driven path drew).
// Instantiated with motion_vectors_render_test.cpp's MotionVectorTest.
#include "render/motion_vector_fixture.h"

namespace si {
namespace test {

TEST_P(MotionVectorTest, LivePosesMoveAsTheFramesTheyHold) {
  const BakedPalette& p = palette();
  const uint32_t wave = uint32_t(p.findClip("wave"));
  const BakedClip& clip = p.clips[wave];
  const auto frameOf = [&](uint32_t f) {
    std::vector<glm::mat4> m(p.palette_joints.size());
    for (uint32_t slot = 0; slot < m.size(); ++slot) m[slot] = decodeJoint(p, wave, f, slot);
    return m;
  };
  const auto timeOf = [&](uint32_t f) {
    return clip.frame_times_seconds.empty() ? double(f) * clip.frame_interval_seconds
                                            : clip.frame_times_seconds[f];
  };
  const uint32_t first = 2, second = std::min<uint32_t>(8, clip.frame_count - 1);
  CrowdDesc cd;
  cd.palette = &p;
  cd.sub_mesh_count = 4;
  cd.lod_count = 1;
  cd.previous_records = true;
  cd.live_pose_capacity = 1;
  InstanceDesc d;
  d.position = glm::dvec3(0.0, 0.0, 0.6);  // Near: a twentieth of the image or more.
  d.clip = wave;
  d.time_seconds = timeOf(first);
  d.speed = 0.0f;
  d.color = glm::u8vec4(tintOf(0), 255);
  const Camera still = camera(0);  // The camera stands still: the motion is the pose's own.
  struct Case {
    const char* name;
    SkinningPath skinning;
    bool gpu_driven;
  };
  for (const Case& k : {Case{"vertex shader", SkinningPath::kVertexShader, false},
                        Case{"compute", SkinningPath::kCompute, false},
                        Case{"GPU-driven", SkinningPath::kVertexShader, true},
                        Case{"GPU-driven, compute", SkinningPath::kCompute, true}}) {
    SCOPED_TRACE(k.name);
    Renderer r;
    makeMotionRenderer(&r, k.skinning);
    InstanceBatcher batcher;
    ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
    // The GPU-driven path keeps what it drew: each step is drawn (the CPU paths read the
    // crowd's previous records and draw the last step only).
    const auto draw = [&](const CrowdManager& crowd) {
      target_.clear(glm::vec4(0.0f));
      const DrawMode mode =
          k.skinning == SkinningPath::kCompute ? DrawMode::kComputeSkinned : DrawMode::kSkinned;
      return k.gpu_driven ? r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), still, nullptr, mode)
                          : r.drawCrowd(CharacterId{}, crowd.view(), batcher, still, nullptr, mode);
    };
    CrowdManager live, twin;
    ASSERT_TRUE(live.init(cd).isOk());
    ASSERT_TRUE(twin.init(cd).isOk());
    InstanceHandle posed, playing;
    ASSERT_TRUE(live.add(d, &posed).isOk());
    ASSERT_TRUE(twin.add(d, &playing).isOk());
    ASSERT_TRUE(live.setLivePose(posed, frameOf(first)).isOk());
    ASSERT_TRUE(live.update(1.0 / 30.0, still).isOk());
    ASSERT_TRUE(twin.update(1.0 / 30.0, still).isOk());
    ASSERT_TRUE(draw(twin).isOk());
    ASSERT_TRUE(draw(live).isOk());
    ASSERT_TRUE(live.setLivePose(posed, frameOf(second)).isOk());
    ASSERT_TRUE(twin.play(playing, wave, timeOf(second), 0.0f).isOk());
    ASSERT_TRUE(live.update(1.0 / 30.0, still).isOk());
    ASSERT_TRUE(twin.update(1.0 / 30.0, still).isOk());
    Status s = draw(twin);
    ASSERT_TRUE(s.isOk()) << s.toString();
    const std::vector<glm::vec2> expected = motions();
    const std::vector<float> expected_depth = depths();
    const std::vector<uint8_t> expected_color = colors();
    float largest = 0.0f;
    for (const glm::vec2& m : expected) largest = std::max(largest, glm::length(m));
    EXPECT_GT(largest, 0.01f);  // The wave moved the arm some pixels.
    s = draw(live);
    ASSERT_TRUE(s.isOk()) << s.toString();
    expectMotion(motions(), depths(), expected, expected_depth, expected_color);
    r.shutdown();
  }
}

}  // namespace test
}  // namespace si
