// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager::jointMatrix: what the crowd says is drawn of a joint (attachments, hit tests)
// is what the instance's record draws.
#include <gtest/gtest.h>

#include "core/prop_fixture.h"
#include "crowd/crowd_test_helpers.h"
#include "si/core/reference_evaluator.h"
#include "si/core/shader_inputs.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using namespace test;

TEST(CrowdManager, JointMatrixMatchesThePalette) {
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  const Character& ch = test::defaultCharacter();
  InstanceDesc d;
  d.position = glm::dvec3(5, 0, 7);
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.3;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const uint32_t hand = uint32_t(ch.skeleton.findJoint("r_hand"));
  glm::dmat4 m;
  ASSERT_TRUE(crowd.jointMatrix(h, hand, &m).isOk());
  const glm::mat4 skin = emulateSkinningMatrix(p, d.clip, sampleFrames(p.clips[d.clip], 0.3),
                                               uint32_t(p.skeleton_to_palette[hand]));
  const glm::dvec3 bind_hand(glm::inverse(ch.skeleton.inverse_bind_matrices[hand])[3]);
  const glm::dvec3 world(m * glm::dvec4(bind_hand, 1.0));
  const glm::dvec3 expected = glm::dvec3(skin * glm::vec4(glm::vec3(bind_hand), 1.0f)) + d.position;
  EXPECT_NEAR(glm::length(world - expected), 0.0, 1e-5);
  EXPECT_EQ(crowd.jointMatrix(h, 0, &m).code(), StatusCode::kOutOfRange);  // Root not stored.
  ASSERT_TRUE(crowd.remove(h).isOk());
  EXPECT_EQ(crowd.jointMatrix(h, hand, &m).code(), StatusCode::kNotFound);
}

// An instance at a LOD past CrowdDesc::animation_lod_start is drawn at times held on the
// animation-LOD grid; jointMatrix (an attachment, a hit test) answers for the same times, so it
// matches the record, crossfade included.
TEST(CrowdManager, JointMatrixFollowsTheAnimationLodStepping) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.animation_lod_start = 1;
  cd.animation_lod_rate_hz = 10.0f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const BakedPalette& p = defaultPalette();
  const Character& ch = test::defaultCharacter();
  InstanceDesc d;
  d.position = glm::dvec3(0, 0, -70);  // Past the first LOD line, in view.
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.37;  // Off the 0.1 s grid.
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.crossfade(h, uint32_t(p.findClip("run")), 0.5).isOk());
  const Camera camera = testCamera({0, 1.6, 0}, {0, 1, -70});
  ASSERT_TRUE(crowd.update(0.12, camera).isOk());
  uint32_t lod = 0;
  ASSERT_TRUE(crowd.view().lodOf(h, &lod).isOk());
  ASSERT_GE(lod, 1u);
  ASSERT_EQ(crowd.view().records().size(), 1u);
  const uint32_t hand = uint32_t(ch.skeleton.findJoint("r_hand"));
  glm::dmat4 m;
  ASSERT_TRUE(crowd.jointMatrix(h, hand, &m).isOk());
  const glm::mat4 drawn =
      emulateRecordMatrix(p, crowd.view().records()[0], uint32_t(p.skeleton_to_palette[hand]));
  const glm::dvec4 bind_hand(glm::dvec3(glm::inverse(ch.skeleton.inverse_bind_matrices[hand])[3]),
                             1.0);
  const glm::dvec3 expected = glm::dvec3(glm::dmat4(drawn) * bind_hand) + d.position;
  EXPECT_LT(glm::length(glm::dvec3(m * bind_hand) - expected), 1e-5);
}

// CrowdManager::socketTransform: a prop attached at a socket (si::attachProp) is drawn at the
// socket's frame times its own vertices: the record's emulated skinning of the prop's vertices
// agrees with it (crossfading, in float), and it lies within the bake's error of the reference
// pose's joint frame times the offset.
TEST(CrowdManager, SocketTransformIsWhereThePropIsDrawn) {
  Character ch = test::defaultCharacter();
  Socket grip;
  ASSERT_TRUE(makeSocket(ch.skeleton, "grip", "r_hand", gripOffset(), &grip).isOk());
  const PropMesh prop = boxProp({0.02f, 0.03f, 0.3f});
  const size_t first = ch.mesh.vertexCount();
  ASSERT_TRUE(attachProp(grip, prop, &ch, nullptr).isOk());
  CrowdManager crowd;  // The hand drives vertices already: the default palette stores it.
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  const BakedPalette& p = defaultPalette();
  InstanceDesc d;
  d.position = glm::dvec3(3, 0, -6);
  d.rotation = glm::angleAxis(0.7f, glm::vec3(0, 1, 0));
  d.clip = uint32_t(p.findClip("walk"));
  d.time_seconds = 0.41;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.crossfade(h, uint32_t(p.findClip("run")), 0.5).isOk());
  ASSERT_TRUE(crowd.update(0.2, testCamera({0, 1.6, 0}, {3, 1, -6})).isOk());
  ASSERT_EQ(crowd.view().records().size(), 1u);
  glm::dmat4 socket;
  ASSERT_TRUE(crowd.socketTransform(h, grip, &socket).isOk());
  const uint32_t slot = uint32_t(p.skeleton_to_palette[grip.joint]);
  const glm::mat4 skin = emulateRecordMatrix(p, crowd.view().records()[0], slot);
  const InstanceRecord& r = crowd.view().records()[0];
  const Camera& cam = crowd.view().camera();
  double worst = 0.0;
  for (size_t v = 0; v < prop.positions.size(); ++v) {
    const glm::vec4 posed = skin * glm::vec4(ch.mesh.positions[first + v], 1.0f);
    const glm::dvec3 drawn(glm::dot(glm::vec4(r.world_rows[0][0], r.world_rows[0][1],
                                              r.world_rows[0][2], r.world_rows[0][3]),
                                    posed),
                           glm::dot(glm::vec4(r.world_rows[1][0], r.world_rows[1][1],
                                              r.world_rows[1][2], r.world_rows[1][3]),
                                    posed),
                           glm::dot(glm::vec4(r.world_rows[2][0], r.world_rows[2][1],
                                              r.world_rows[2][2], r.world_rows[2][3]),
                                    posed));
    const glm::dvec3 said(socket * glm::dvec4(prop.positions[v], 1.0));
    worst = std::max(worst, glm::length(drawn + cam.position - said));
  }
  EXPECT_LT(worst, 1e-5 * ch.height());
  // The reference: the walk crossfading into the run is not one pose, so the instance settles
  // into the run first; the socket then sits at the reference hand's frame times the offset,
  // to the bake's error.
  ASSERT_TRUE(crowd.update(1.0, testCamera({0, 1.6, 0}, {3, 1, -6})).isOk());
  ASSERT_TRUE(crowd.socketTransform(h, grip, &socket).isOk());
  ReferencePose pose;
  const Clip& run = ch.clips[size_t(ch.findClip("run"))];
  // The run started at the crossfade (clock 0) from time 0.
  ASSERT_TRUE(evaluatePose(ch.skeleton, run, 1.2, &pose).isOk());
  const glm::dmat4 world =
      glm::translate(glm::dmat4(1.0), d.position) * glm::dmat4(glm::mat4_cast(d.rotation));
  const glm::dmat4 expected = world * pose.model[grip.joint] * glm::dmat4(gripOffset());
  double error = 0.0;
  for (size_t v = 0; v < prop.positions.size(); ++v) {
    const glm::dvec4 at(prop.positions[v], 1.0);
    error = std::max(error, glm::length(glm::dvec3(socket * at) - glm::dvec3(expected * at)));
  }
  EXPECT_LT(error, 2e-3 * ch.height()) << "socket error " << error << " units";
  RecordProperty("socket_error_fraction_of_height", std::to_string(error / ch.height()));
  // A socket on a joint the palette does not store (the root drives no vertex).
  Socket at_root;
  ASSERT_TRUE(makeSocket(ch.skeleton, "belt", "root", glm::mat4(1.0f), &at_root).isOk());
  const Status s = crowd.socketTransform(h, at_root, &socket);
  EXPECT_EQ(s.code(), StatusCode::kOutOfRange);
  EXPECT_NE(s.message().find("belt"), std::string::npos) << s.message();
  EXPECT_EQ(crowd.socketTransform(h, grip, nullptr).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(crowd.remove(h).isOk());
  EXPECT_EQ(crowd.socketTransform(h, grip, &socket).code(), StatusCode::kNotFound);
}

// A prop on a joint no other vertex is weighted to: the palette baked before cannot draw it;
// baked after attaching, the palette stores the joint and the socket is answered.
TEST(CrowdManager, ASocketJointOnlyThePropUsesIsStoredWhenBakedAfter) {
  Character ch = test::defaultCharacter();
  Socket belt;
  ASSERT_TRUE(makeSocket(ch.skeleton, "belt", "root", gripOffset(), &belt).isOk());
  ASSERT_LT(defaultPalette().skeleton_to_palette[belt.joint], 0);
  ASSERT_TRUE(attachProp(belt, boxProp({0.05f, 0.05f, 0.05f}), &ch, nullptr).isOk());
  // The palette baked before does not store it: the renderer's vertex stream is refused.
  VertexStream stream;
  EXPECT_EQ(buildVertexStream(ch.mesh, defaultPalette(), &stream).code(), StatusCode::kInvalidArgument);
  const BakedPalette p = bakeAt30Hz(ch);
  ASSERT_GE(p.skeleton_to_palette[belt.joint], 0);
  EXPECT_TRUE(buildVertexStream(ch.mesh, p, &stream).isOk());
  CrowdDesc cd = defaultCrowdDesc();
  cd.palette = &p;
  cd.sub_mesh_count = uint32_t(ch.mesh.sub_meshes.size());
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(1, 0, -4);
  d.clip = uint32_t(p.findClip("walk"));
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  glm::dmat4 m;
  ASSERT_TRUE(crowd.socketTransform(h, belt, &m).isOk());
  // The root does not move in the walk: the belt stays at the instance's origin times the offset.
  const glm::dmat4 expected =
      glm::translate(glm::dmat4(1.0), d.position) * glm::dmat4(gripOffset());
  for (int k = 0; k < 4; ++k) EXPECT_LT(glm::length(m[k] - expected[k]), 1e-5) << k;
}

}  // namespace
}  // namespace si
