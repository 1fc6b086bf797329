// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Meshes moved by their nodes rather than a skin (issue "Any animated glTF becomes a crowd"):
// a file animated by its nodes imports as a character whose nodes are rigid joints, and a mesh
// a skinned file hangs on a joint follows it. Checked against the node graph evaluated here,
// independently of the library, in double precision: the reference within 1e-6 of the height,
// the default bake within 1e-4.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "gltf/node_animated_asset.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using namespace test;

Status importString(const std::string& json, Character* c, GltfImportReport* r) {
  return importGltfMemory(
      Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "", {}, c,
      r);
}

TEST(GltfNodeAnimation, AFileAnimatedByItsNodesImportsAsRigidJoints) {
  Character c;
  GltfImportReport r;
  const Status s = importString(nodeAnimatedFile(), &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_EQ(r.skin_joints, 0u);
  EXPECT_EQ(r.skinned_primitives, 0u);
  EXPECT_EQ(r.rigid_primitives, 3u);
  // The nodes are the joints, parents first; each vertex is wholly its node's.
  ASSERT_EQ(c.skeleton.jointCount(), 4u);
  const int32_t rig = c.skeleton.findJoint("rig"), base = c.skeleton.findJoint("base"),
                arm = c.skeleton.findJoint("arm"), fixed = c.skeleton.findJoint("static");
  ASSERT_TRUE(rig >= 0 && base >= 0 && arm >= 0 && fixed >= 0);
  EXPECT_EQ(c.skeleton.parents[size_t(base)], rig);
  EXPECT_EQ(c.skeleton.parents[size_t(arm)], base);
  EXPECT_EQ(c.skeleton.parents[size_t(fixed)], rig);
  ASSERT_EQ(c.mesh.vertexCount(), 9u);
  const int32_t owner[3] = {base, arm, fixed};
  // Bound where the nodes rest (the clip's first key is the rest here): the bind pose is the
  // scene, which the bounds, the LOD errors and the impostors measure.
  const std::vector<glm::dvec3> rest = expectedPositions(0.0);
  for (size_t v = 0; v < 9; ++v) {
    EXPECT_EQ(c.mesh.joints[v].x, uint16_t(owner[v / 3])) << v;
    EXPECT_EQ(c.mesh.weights[v], glm::vec4(1, 0, 0, 0)) << v;
    EXPECT_LE(glm::distance(glm::dvec3(c.mesh.positions[v]), rest[v]), 1e-6) << v;
  }
  // The mirrored plate keeps its front outside: its winding agrees with its normal.
  const std::vector<uint32_t>& idx = c.mesh.indices;
  ASSERT_EQ(idx.size(), 9u);
  for (size_t k = 0; k < idx.size(); k += 3) {
    const glm::vec3 a = c.mesh.positions[idx[k]], b = c.mesh.positions[idx[k + 1]],
                    d = c.mesh.positions[idx[k + 2]];
    EXPECT_GT(glm::dot(glm::cross(b - a, d - a), c.mesh.normals[idx[k]]), 0.0f) << k;
  }
  // Posed by the library's reference and by the node graph evaluated here.
  ASSERT_EQ(c.clips.size(), 1u);
  EXPECT_FLOAT_EQ(c.clips[0].duration_seconds, 1.0f);
  double height = 0.0;
  for (const glm::dvec3& p : expectedPositions(1.0)) height = std::max(height, p.y);
  ASSERT_GT(height, 2.0);
  for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], t, &pose).isOk());
    std::vector<glm::dvec3> posed(c.mesh.vertexCount());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, posed, {}, {}).isOk());
    const std::vector<glm::dvec3> want = expectedPositions(t);
    for (size_t v = 0; v < want.size(); ++v)
      EXPECT_LE(glm::distance(posed[v], want[v]), 1e-6 * height) << "t " << t << " vertex " << v;
  }
  // The default bake: within 1e-4 of the height of the reference.
  BakedPalette p;
  BakeReport report;
  const Status baked = bakePalette(c, BakeDesc(), &p, &report);
  ASSERT_TRUE(baked.isOk()) << baked.toString();
  EXPECT_TRUE(report.clips.at(0).tolerance_met);
  EXPECT_LE(report.max_error_ratio, 1e-4);
}

// A skinned file with a sword on the hand joint (a node with a mesh and no skin): the sword is a
// rigid part bound wholly to its own joint under the hand, and follows the hand.
TEST(GltfNodeAnimation, AMeshOnAJointOfASkinnedFileFollowsIt) {
  GltfWriter w;
  const int pos = w.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kGltfFloat, "VEC3", 3);
  const int joints =
      w.accessor(std::vector<uint8_t>{0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kGltfUByte, "VEC4", 3);
  const int weights =
      w.accessor(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kGltfFloat, "VEC4", 3);
  w.meshes =
      "{\"name\":\"body\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(pos) +
      ",\"JOINTS_0\":" + std::to_string(joints) + ",\"WEIGHTS_0\":" + std::to_string(weights) +
      "}}]}," + triangleMesh(&w, "sword", kStick, {0, 0, 1, 0, 0, 1, 0, 0, 1});
  w.nodes =
      "{\"name\":\"root\",\"children\":[1,2]},"
      "{\"name\":\"hand\",\"translation\":[0,1,0],\"children\":[3]},"
      "{\"name\":\"body\",\"mesh\":0,\"skin\":0},"
      "{\"name\":\"sword\",\"mesh\":1,\"translation\":[0,0.5,0]}";
  w.skins = "{\"name\":\"main\",\"joints\":[0,1]}";
  const float r = float(std::sqrt(0.5));
  w.animations = oneChannelAnimation(&w, "swing", 1, "rotation", {0, 0, 0, 1, 0, 0, r, r});
  Character c;
  GltfImportReport report;
  const Status s = importString(w.json(), &c, &report);
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_EQ(report.skinned_primitives, 1u);
  EXPECT_EQ(report.rigid_primitives, 1u);
  const int32_t hand = c.skeleton.findJoint("hand"), sword = c.skeleton.findJoint("sword");
  ASSERT_GE(sword, 0);
  EXPECT_EQ(c.skeleton.parents[size_t(sword)], hand);
  ASSERT_EQ(c.mesh.vertexCount(), 6u);
  for (size_t v = 3; v < 6; ++v) {
    EXPECT_EQ(c.mesh.joints[v].x, uint16_t(sword));
    EXPECT_EQ(c.mesh.weights[v], glm::vec4(1, 0, 0, 0));
  }
  // Half way: the hand turned 45 degrees about Z; the sword 0.5 above it, turned with it.
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips.at(0), 0.5, &pose).isOk());
  std::vector<glm::dvec3> posed(6);
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, posed, {}, {}).isOk());
  const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1, 0)) *
                        glm::rotate(glm::dmat4(1.0), 0.25 * kPi, glm::dvec3(0, 0, 1)) *
                        glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0.5, 0));
  for (size_t v = 0; v < 3; ++v) {
    const glm::dvec3 want(at * glm::dvec4(kStick[3 * v], kStick[3 * v + 1], kStick[3 * v + 2], 1));
    EXPECT_LE(glm::distance(posed[3 + v], want), 1e-6 * 2.0) << v;
  }
}

// A part that rests at zero scale and scales up (a pop-in) has no rest matrix to undo: it is
// bound in its own space, with a warning, and still posed where its node puts it.
TEST(GltfNodeAnimation, APartRestingAtZeroScaleIsBoundInItsOwnSpace) {
  GltfWriter w;
  w.meshes = triangleMesh(&w, "plate", kPlate, {0, 1, 0, 0, 1, 0, 0, 1, 0});
  w.nodes = "{\"name\":\"pop\",\"mesh\":0,\"translation\":[1,0,0],\"scale\":[0,0,0]}";
  w.animations = oneChannelAnimation(&w, "grow", 0, "scale", {0, 0, 0, 2, 2, 2});
  Character c;
  GltfImportReport r;
  const Status s = importString(w.json(), &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  bool warned = false;
  for (const std::string& m : r.warnings)
    warned |= m.find("rests at zero scale") != std::string::npos;
  EXPECT_TRUE(warned);
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips.at(0), 0.5, &pose).isOk());
  std::vector<glm::dvec3> posed(3);
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, posed, {}, {}).isOk());
  for (size_t v = 0; v < 3; ++v) {  // Scaled by 1 at half way, moved by 1 in x.
    const glm::dvec3 want(1.0 + kPlate[3 * v], kPlate[3 * v + 1], kPlate[3 * v + 2]);
    EXPECT_LE(glm::distance(posed[v], want), 1e-6) << v;
  }
}

// A file with nodes but no mesh at all, skinned or not, is refused by name.
TEST(GltfNodeAnimation, AFileWithoutAMeshIsRefusedByName) {
  GltfWriter w;
  w.nodes = "{\"name\":\"empty\"}";
  w.meshes = triangleMesh(&w, "unused", kPlate, {0, 1, 0, 0, 1, 0, 0, 1, 0});
  Character c;
  GltfImportReport r;
  const Status s = importString(w.json(), &c, &r);
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
  EXPECT_NE(s.message().find("no skin and no node with a mesh"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace si
