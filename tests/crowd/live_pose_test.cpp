// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager::setLivePose: an instance draws the engine's pose. The crowd writes it in the
// palette's format into a frame after the palette's texels, the instance's record points
// there, and jointMatrix and localPose answer with it; clearLivePose goes back to the clip.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "bake/bake_test_helpers.h"
#include "crowd/crowd_test_helpers.h"
#include "crowd/live_pose_helpers.h"
#include "crowd/morph_face_fixture.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;
using test::enginePose;
using test::liveDesc;
using test::recordOf;

// Palette joint `joint`'s matrix of the live frame at texel `frame` as the shader reads it.
glm::mat4 liveMatrix(const CrowdExport& e, const BakedPalette& p, uint32_t frame, uint32_t joint) {
  const size_t bytes = bytesPerTexel(p.format);
  const size_t at = size_t(frame - e.livePoseFirstTexel() + joint * p.layout.joint_stride_texels);
  glm::mat4 m(1.0f);
  for (uint32_t row = 0; row < 3; ++row) {
    float v[4];
    if (p.format == PaletteFormat::kMatrix3x4F16) {
      uint16_t h[4];
      std::memcpy(h, e.livePoseTexels().data() + (at + row) * bytes, sizeof(h));
      for (int c = 0; c < 4; ++c) v[c] = halfToFloat(h[c]);
    } else {
      std::memcpy(v, e.livePoseTexels().data() + (at + row) * bytes, sizeof(v));
    }
    for (int c = 0; c < 4; ++c) m[c][row] = v[c];
  }
  return m;
}

// One sub-mesh of `palette` (test::smallPalette's chain) with room for one live pose.
CrowdDesc oneLivePose(const BakedPalette& palette) {
  CrowdDesc d;
  d.palette = &palette;
  d.sub_mesh_count = 1;
  d.live_pose_capacity = 1;
  return d;
}

TEST(LivePose, TheRecordDrawsTheEnginesPoseAndTheCrowdAnswersWithIt) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(liveDesc(2)).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(2, 0, -4);
  d.rotation = glm::angleAxis(0.5f, glm::vec3(0, 1, 0));
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.3;
  InstanceHandle posed, playing;
  ASSERT_TRUE(crowd.add(d, &posed).isOk());
  ASSERT_TRUE(crowd.add(d, &playing).isOk());
  const std::vector<glm::mat4> pose = enginePose(sk, p);
  const CrowdExport e(crowd);
  const uint64_t version = e.livePoseVersion();
  ASSERT_TRUE(crowd.setLivePose(posed, pose).isOk());
  EXPECT_NE(e.livePoseVersion(), version);
  ASSERT_EQ(e.livePoseFirstTexel(), uint32_t(p.layout.textureTexelCount()));
  // Two frames for each of the 2 poses.
  ASSERT_EQ(e.livePoseTexels().size(), 4u * p.layout.frame_stride_texels * bytesPerTexel(p.format));
  const Camera camera = test::testCamera({0, 1.6, 6}, {2, 1, -4});
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  const InstanceRecord* live = recordOf(crowd, posed);
  const InstanceRecord* clip = recordOf(crowd, playing);
  ASSERT_TRUE(live != nullptr && clip != nullptr);
  // The record names one live frame, without interpolation or crossfade.
  const uint32_t frame = live->frames[0];
  ASSERT_GE(frame, e.livePoseFirstTexel());
  EXPECT_EQ((frame - e.livePoseFirstTexel()) % p.layout.frame_stride_texels, 0u);
  for (int k = 1; k < 4; ++k) EXPECT_EQ(live->frames[k], frame);
  EXPECT_EQ(live->blend[2], 0u);
  EXPECT_EQ(live->blend[3], clip->blend[3]);
  EXPECT_LT(clip->frames[0], e.livePoseFirstTexel());  // The other plays its clip.
  for (uint32_t j = 0; j < pose.size(); ++j)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(liveMatrix(e, p, frame, j)[c], pose[j][c]) << j;
  // jointMatrix answers with the pose; localPose with the clip's pose under it (the twin's).
  glm::dmat4 world = glm::mat4_cast(glm::dquat(d.rotation));
  world[3] = glm::dvec4(d.position, 1.0);
  std::vector<TransformD> local(sk.jointCount()), twin(sk.jointCount());
  ASSERT_TRUE(crowd.localPose(posed, sk, local).isOk());
  ASSERT_TRUE(crowd.localPose(playing, sk, twin).isOk());
  for (size_t j = 0; j < local.size(); ++j) {
    EXPECT_EQ(local[j].translation, twin[j].translation) << j;
    EXPECT_EQ(local[j].rotation, twin[j].rotation) << j;
  }
  for (uint32_t slot = 0; slot < pose.size(); ++slot) {
    const uint32_t j = p.palette_joints[slot];
    glm::dmat4 m;
    ASSERT_TRUE(crowd.jointMatrix(posed, j, &m).isOk());
    for (int c = 0; c < 4; ++c)
      EXPECT_LT(glm::length(m[c] - (world * glm::dmat4(pose[slot]))[c]), 1e-6) << j;
  }
  // Back to the clip: the record is the playing twin's again.
  ASSERT_TRUE(crowd.clearLivePose(posed).isOk());
  ASSERT_TRUE(crowd.clearLivePose(posed).isOk());  // Nothing to clear: fine.
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  live = recordOf(crowd, posed);
  clip = recordOf(crowd, playing);
  ASSERT_TRUE(live != nullptr && clip != nullptr);
  EXPECT_EQ(std::memcmp(live, clip, sizeof(InstanceRecord)), 0);
}

// Motion vectors: a pose set in a new step goes to the slot's other frame, so the previous
// record still names the frame holding the previous pose; one set again in the same step, or
// none set, keeps the frame (a held pose does not move).
TEST(LivePose, ThePreviousRecordReadsThePreviousPose) {
  const Skeleton& sk = defaultCharacter().skeleton;
  const BakedPalette& p = defaultPalette();
  CrowdDesc cd = liveDesc(1);
  cd.previous_records = true;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = test::testCamera({0, 1.6, 6}, {0, 1, 0});
  const CrowdExport e(crowd);
  std::vector<glm::mat4> a = enginePose(sk, p), b = a;
  for (glm::mat4& m : b) m[3][1] += 0.25f;  // Lifted.
  // The frame `rec` names holds `pose` (its first joint's translation).
  const auto holds = [&](const InstanceRecord& rec, const std::vector<glm::mat4>& pose) {
    return liveMatrix(e, p, rec.frames[0], 0)[3] == pose[0][3];
  };
  ASSERT_TRUE(crowd.setLivePose(h, a).isOk());
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  ASSERT_TRUE(crowd.setLivePose(h, b).isOk());
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  const CrowdView& v = crowd.view();
  ASSERT_EQ(v.records().size(), 1u);
  ASSERT_NE(v.previousRecordIndices()[0], kNoPreviousRecord);
  const InstanceRecord now = v.records()[0];
  const InstanceRecord then = v.previousRecords()[v.previousRecordIndices()[0]];
  EXPECT_NE(now.frames[0], then.frames[0]);
  EXPECT_TRUE(holds(now, b));
  EXPECT_TRUE(holds(then, a));
  // Set twice in one step: the second write replaces the first in the same frame.
  ASSERT_TRUE(crowd.advance(0.1).isOk());
  ASSERT_TRUE(crowd.setLivePose(h, a).isOk());
  ASSERT_TRUE(crowd.setLivePose(h, a).isOk());
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  EXPECT_TRUE(holds(v.records()[0], a));
  EXPECT_TRUE(holds(v.previousRecords()[v.previousRecordIndices()[0]], b));
  // Held: no new pose, both records name the same frame.
  ASSERT_TRUE(crowd.update(0.1, camera).isOk());
  EXPECT_EQ(v.records()[0].frames[0], v.previousRecords()[v.previousRecordIndices()[0]].frames[0]);
}

// `crowd` initialized with room for `capacity` live poses, holding two default instances.
void initTwo(uint32_t capacity, CrowdManager* crowd, InstanceHandle* a, InstanceHandle* b) {
  ASSERT_TRUE(crowd->init(liveDesc(capacity)).isOk());
  ASSERT_TRUE(crowd->add(InstanceDesc(), a).isOk());
  ASSERT_TRUE(crowd->add(InstanceDesc(), b).isOk());
}

TEST(LivePose, FramesAreTakenAndFreed) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  CrowdManager crowd;
  InstanceHandle a, b;
  ASSERT_NO_FATAL_FAILURE(initTwo(1, &crowd, &a, &b));
  ASSERT_TRUE(crowd.setLivePose(a, pose).isOk());
  ASSERT_TRUE(crowd.setLivePose(a, pose).isOk());  // Its own frame again.
  Status s = crowd.setLivePose(b, pose);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.message();
  EXPECT_NE(s.message().find("all 1 live poses are taken"), std::string::npos) << s.message();
  ASSERT_TRUE(crowd.remove(a).isOk());  // Frees its frame.
  ASSERT_TRUE(crowd.setLivePose(b, pose).isOk());
  ASSERT_TRUE(crowd.clearLivePose(b).isOk());
  InstanceHandle c;
  ASSERT_TRUE(crowd.add(InstanceDesc(), &c).isOk());
  ASSERT_TRUE(crowd.setLivePose(c, pose).isOk());
  // The records of the posed instance after the removal moved it to another dense index.
  ASSERT_TRUE(crowd.update(0.0, test::testCamera({0, 1.6, 6}, {0, 1, 0})).isOk());
  const InstanceRecord* rec = recordOf(crowd, c);
  ASSERT_NE(rec, nullptr);
  EXPECT_EQ(rec->frames[0], CrowdExport(crowd).livePoseFirstTexel());
  EXPECT_LT(recordOf(crowd, b)->frames[0], CrowdExport(crowd).livePoseFirstTexel());
}

TEST(LivePose, BadPosesAndCapacitiesAreRefusedByName) {
  const BakedPalette& p = defaultPalette();
  std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  CrowdManager none;
  ASSERT_TRUE(none.init(test::defaultCrowdDesc()).isOk());
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(none.add(d, &h).isOk());
  Status s = none.setLivePose(h, pose);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("live_pose_capacity is 0"), std::string::npos) << s.message();
  EXPECT_TRUE(CrowdExport(none).livePoseTexels().empty());

  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(liveDesc(1)).isOk());
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  EXPECT_EQ(crowd.setLivePose(h, Span<const glm::mat4>(pose.data(), pose.size() - 1)).code(),
            StatusCode::kCountMismatch);
  std::vector<glm::mat4> bad = pose;
  bad[3][1][2] = std::nanf("");
  EXPECT_EQ(crowd.setLivePose(h, bad).code(), StatusCode::kNotFinite);
  bad = pose;
  bad[2][0][3] = 0.5f;  // A projective last row the palette cannot hold.
  s = crowd.setLivePose(h, bad);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("matrix 2's last row"), std::string::npos) << s.message();
  ASSERT_TRUE(crowd.remove(h).isOk());
  EXPECT_EQ(crowd.setLivePose(h, pose).code(), StatusCode::kNotFound);
  EXPECT_EQ(crowd.clearLivePose(h).code(), StatusCode::kNotFound);

  CrowdManager big;
  s = big.init(liveDesc(CrowdDesc::kMaxLivePoses + 1));
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("live_pose_capacity"), std::string::npos) << s.message();
  // A quaternion palette holds rigid joints only: refused.
  const BakedPalette quat = test::smallPalette(PaletteFormat::kQuatTranslationF32);
  CrowdManager q;
  s = q.init(oneLivePose(quat));
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
  EXPECT_NE(s.message().find("quat_translation_f32"), std::string::npos) << s.message();
}

// A refused pose changes nothing, though it is checked as it is stored: not a pose set
// earlier in the same step (written over the frame the records will name), not the last
// step's (the next pose goes to its other frame), and an instance on its clip takes no slot.
TEST(LivePose, ARefusedPoseLeavesWhatWasHeld) {
  const BakedPalette& p = defaultPalette();
  const std::vector<glm::mat4> pose = enginePose(defaultCharacter().skeleton, p);
  CrowdManager crowd;
  InstanceHandle a, b;
  ASSERT_NO_FATAL_FAILURE(initTwo(2, &crowd, &a, &b));
  std::vector<glm::mat4> bad = pose;
  bad.back()[3][0] = std::nanf("");  // The last matrix: all the others stored first.
  const auto joints = [&] {
    std::vector<glm::dmat4> out(p.skeleton_to_palette.size());
    for (uint32_t j = 0; j < out.size(); ++j)
      if (!crowd.jointMatrix(a, j, &out[j]).isOk()) out[j] = glm::dmat4(0.0);
    return out;
  };
  const CrowdExport e(crowd);
  const auto texels = [&] {
    return std::vector<uint8_t>(e.livePoseTexels().begin(), e.livePoseTexels().end());
  };
  ASSERT_TRUE(crowd.setLivePose(a, pose).isOk());
  const std::vector<glm::dmat4> held = joints();
  std::vector<uint8_t> held_texels = texels();
  uint64_t version = e.livePoseVersion();
  EXPECT_EQ(crowd.setLivePose(a, bad).code(), StatusCode::kNotFinite);  // The same step.
  EXPECT_EQ(texels(), held_texels);
  EXPECT_EQ(e.livePoseVersion(), version);
  ASSERT_TRUE(crowd.update(0.0, test::testCamera({0, 1.6, 6}, {0, 1, 0})).isOk());
  const uint32_t named = recordOf(crowd, a)->frames[0];
  ASSERT_TRUE(crowd.advance(1.0 / 60.0).isOk());
  EXPECT_EQ(crowd.setLivePose(a, bad).code(), StatusCode::kNotFinite);  // A new step.
  EXPECT_EQ(joints(), held);
  EXPECT_EQ(e.livePoseVersion(), version);
  ASSERT_TRUE(crowd.update(0.0, test::testCamera({0, 1.6, 6}, {0, 1, 0})).isOk());
  EXPECT_EQ(recordOf(crowd, a)->frames[0], named);
  std::vector<glm::mat4> moved = pose;
  moved[0][3][1] += 0.25f;
  ASSERT_TRUE(crowd.setLivePose(a, moved).isOk());  // Then a good one goes to the other frame.
  EXPECT_NE(joints(), held);
  ASSERT_TRUE(crowd.update(0.0, test::testCamera({0, 1.6, 6}, {0, 1, 0})).isOk());
  EXPECT_NE(recordOf(crowd, a)->frames[0], named);

  EXPECT_EQ(crowd.setLivePose(b, bad).code(), StatusCode::kNotFinite);  // From its clip.
  EXPECT_EQ(e.livePoseCount(), 1u);
  ASSERT_TRUE(crowd.update(0.0, test::testCamera({0, 1.6, 6}, {0, 1, 0})).isOk());
  EXPECT_LT(recordOf(crowd, b)->frames[0], e.livePoseFirstTexel());
  EXPECT_TRUE(crowd.setLivePose(b, pose).isOk());  // Its slot was given back.
  EXPECT_EQ(e.livePoseCount(), 2u);
  InstanceHandle c;  // Every frame taken: named first, the matrices unread.
  ASSERT_TRUE(crowd.add(InstanceDesc(), &c).isOk());
  EXPECT_EQ(crowd.setLivePose(c, bad).code(), StatusCode::kLimitExceeded);
}

TEST(LivePose, AHalfPaletteHoldsThePoseInHalves) {
  const BakedPalette half = test::smallPalette(PaletteFormat::kMatrix3x4F16);
  CrowdManager crowd;
  const Status init = crowd.init(oneLivePose(half));
  ASSERT_TRUE(init.isOk()) << init.message();
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  std::vector<glm::mat4> pose(half.palette_joints.size(), glm::mat4(1.0f));
  pose[0][3] = glm::vec4(0.1f, 1.0f / 3.0f, -2.7f, 1.0f);
  ASSERT_TRUE(crowd.setLivePose(h, pose).isOk());
  const CrowdExport e(crowd);
  const glm::mat4 m = liveMatrix(e, half, e.livePoseFirstTexel(), 0);
  EXPECT_EQ(m[3][1], halfToFloat(floatToHalf(1.0f / 3.0f)));
  EXPECT_NE(m[3][1], 1.0f / 3.0f);
  pose[0][3][0] = 70000.0f;  // Past the largest half.
  const Status s = crowd.setLivePose(h, pose);
  EXPECT_EQ(s.code(), StatusCode::kNotFinite);
  EXPECT_NE(s.message().find("matrix3x4_f16"), std::string::npos) << s.message();
}

// The live frame holds the morph weights of the clip's frame when the pose was set (the clip
// plays on underneath): a posed face keeps its expression.
TEST(LivePose, TheFrameKeepsTheClipsMorphWeights) {
  const test::Face& f = test::face();
  const BakedPalette& p = f.palette;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(test::liveDesc(p, f.character, 1)).isOk());
  InstanceDesc d;
  d.clip = f.walk;
  d.time_seconds = 0.5;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.setLivePose(h, enginePose(f.character.skeleton, p)).isOk());
  const CrowdExport e(crowd);
  const size_t bytes = bytesPerTexel(p.format);
  const FrameSample s = sampleFrames(p.clips[f.walk], 0.5);
  const uint8_t* baked =
      p.texel_bytes.data() + (size_t(p.layout.morphTexel(f.walk, s.frame, 0))) * bytes;
  const uint8_t* live = e.livePoseTexels().data() + size_t(p.layout.morph_first_texel) * bytes;
  EXPECT_EQ(std::memcmp(live, baked, bytes), 0);  // Three targets: one texel.
  float w[4];
  std::memcpy(w, live, sizeof(w));
  EXPECT_GT(w[1], 0.0f);  // A weight the clip gives, not an empty texel.
}

}  // namespace
}  // namespace si
