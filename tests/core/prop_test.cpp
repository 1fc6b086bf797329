// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Sockets and props (si/core/prop.h): a socket's bind frame, a prop attached as a sub-mesh
// rigidly weighted to its joint (skinned by the reference, it sits at the socket's posed frame),
// materials renumbered, mirrored frames keeping the triangles' fronts outside, and every refusal
// leaving the character untouched.
#include "si/core/prop.h"

#include <gtest/gtest.h>

#include "core/prop_fixture.h"
#include "core/test_helpers.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

using namespace test;

TEST(Socket, IsTheJointsBindFrameTimesTheOffset) {
  const Character c = embeddedCharacter();
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  const uint32_t hand = uint32_t(c.skeleton.findJoint("r_hand"));
  EXPECT_EQ(s.joint, hand);
  EXPECT_EQ(s.name, "grip");
  const glm::dmat4 expected =
      glm::inverse(glm::dmat4(c.skeleton.inverse_bind_matrices[hand])) * glm::dmat4(gripOffset());
  for (int k = 0; k < 4; ++k)
    EXPECT_LT(glm::length(glm::dvec4(s.bind_frame[k]) - expected[k]), 1e-6);
  // Refusals, `out` untouched.
  Socket kept = s;
  EXPECT_EQ(makeSocket(c.skeleton, "grip", "no_such_joint", gripOffset(), &s).code(),
            StatusCode::kNotFound);
  EXPECT_EQ(makeSocket(c.skeleton, "", "r_hand", gripOffset(), &s).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), nullptr).code(),
            StatusCode::kInvalidArgument);
  glm::mat4 bad = gripOffset();
  bad[0][3] = 0.5f;  // Not affine.
  EXPECT_EQ(makeSocket(c.skeleton, "grip", "r_hand", bad, &s).code(), StatusCode::kInvalidArgument);
  glm::mat4 singular(1.0f);
  singular[1] = glm::vec4(0.0f);
  EXPECT_EQ(makeSocket(c.skeleton, "grip", "r_hand", singular, &s).code(),
            StatusCode::kInvalidArgument);
  bad = gripOffset();
  bad[3][1] = std::nanf("");
  EXPECT_EQ(makeSocket(c.skeleton, "grip", "r_hand", bad, &s).code(), StatusCode::kNotFinite);
  Skeleton twins = c.skeleton;
  twins.joint_names[0] = "r_hand";
  EXPECT_EQ(makeSocket(twins, "grip", "r_hand", gripOffset(), &s).code(), StatusCode::kAmbiguous);
  EXPECT_EQ(s.bind_frame, kept.bind_frame);
  EXPECT_EQ(s.name, kept.name);
}

// A character with 8 influences takes a prop too: the prop's vertices get an empty second set,
// and the character stays valid.
TEST(Prop, ACharacterWithEightInfluencesTakesAProp) {
  Character c = embeddedCharacter();
  c.mesh.joints1.assign(c.mesh.vertexCount(), glm::u16vec4(0));
  c.mesh.weights1.assign(c.mesh.vertexCount(), glm::vec4(0.0f));
  ASSERT_TRUE(c.validate().isOk());
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  ASSERT_TRUE(attachProp(s, boxProp({0.02f, 0.03f, 0.3f}), &c, nullptr).isOk());
  EXPECT_EQ(c.mesh.joints1.size(), c.mesh.vertexCount());
  EXPECT_EQ(c.mesh.weights1.size(), c.mesh.vertexCount());
  EXPECT_TRUE(c.validate().isOk()) << c.validate().toString();
}

// Skinned by the reference at any time, every prop vertex sits at the socket's posed frame:
// model(joint) * offset * vertex.
TEST(Prop, AttachedVerticesFollowTheSocketsPosedFrame) {
  Character c = embeddedCharacter();
  const size_t vertices = c.mesh.vertexCount(), sub_meshes = c.mesh.sub_meshes.size();
  const size_t materials = c.materials.size(), images = c.images.size();
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  const PropMesh prop = boxProp({0.02f, 0.03f, 0.3f});
  uint32_t bit = 99;
  ASSERT_TRUE(attachProp(s, prop, &c, &bit).isOk());
  EXPECT_EQ(bit, sub_meshes);
  ASSERT_EQ(c.mesh.sub_meshes.size(), sub_meshes + 1);
  EXPECT_EQ(c.mesh.sub_meshes[bit].name, "box");
  ASSERT_EQ(c.mesh.sub_meshes[bit].lods.size(), 1u);
  EXPECT_EQ(c.mesh.sub_meshes[bit].lods[0].index_count, prop.indices.size());
  EXPECT_EQ(c.mesh.vertexCount(), vertices + prop.positions.size());
  ASSERT_TRUE(c.validate().isOk());
  // Materials and images follow the character's; the prop's vertex materials renumbered.
  ASSERT_EQ(c.materials.size(), materials + 2);
  EXPECT_EQ(c.materials[materials + 1].name, "flame");
  EXPECT_EQ(c.materials[materials + 1].base_color_image, int32_t(images));
  EXPECT_EQ(c.images.size(), images + 1);
  for (size_t v = 0; v < prop.positions.size(); ++v) {
    EXPECT_EQ(c.mesh.vertex_materials[vertices + v], materials + prop.vertex_materials[v]);
    EXPECT_EQ(c.mesh.joints[vertices + v], glm::u16vec4(uint16_t(s.joint), 0, 0, 0));
    EXPECT_EQ(c.mesh.weights[vertices + v], glm::vec4(1, 0, 0, 0));
  }
  // Posed: every vertex at model(joint) * offset * vertex, its normal turned with it.
  const Clip& wave = c.clips[size_t(c.findClip("wave"))];
  ReferencePose pose;
  ASSERT_TRUE(evaluatePose(c.skeleton, wave, 0.7, &pose).isOk());
  std::vector<glm::dvec3> pos(c.mesh.vertexCount()), nrm(c.mesh.vertexCount());
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, pos, nrm, {}).isOk());
  const glm::dmat4 frame = pose.model[s.joint] * glm::dmat4(gripOffset());
  double worst = 0.0, worst_normal = 0.0;
  for (size_t v = 0; v < prop.positions.size(); ++v) {
    worst = std::max(worst, glm::length(pos[vertices + v] -
                                        glm::dvec3(frame * glm::dvec4(prop.positions[v], 1.0))));
    worst_normal =
        std::max(worst_normal,
                 glm::length(nrm[vertices + v] - glm::dmat3(frame) * glm::dvec3(prop.normals[v])));
  }
  EXPECT_LT(worst, 1e-5 * c.height());
  EXPECT_LT(worst_normal, 1e-5);
  // The character's own vertices are where they were.
  const Character before = embeddedCharacter();
  for (size_t v = 0; v < vertices; ++v) ASSERT_EQ(c.mesh.positions[v], before.mesh.positions[v]);
}

// A mirroring socket frame (negative determinant) reverses each triangle so its front, by the
// winding, faces the way its transformed normal does.
TEST(Prop, MirroredFramesKeepFrontsOutside) {
  for (float mirror : {1.0f, -1.0f}) {
    Character c = embeddedCharacter();
    const size_t first_index = c.mesh.indices.size();
    glm::mat4 offset = gripOffset();
    offset[0] *= mirror;
    Socket s;
    ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", offset, &s).isOk());
    ASSERT_TRUE(attachProp(s, boxProp({0.02f, 0.03f, 0.3f}), &c, nullptr).isOk());
    for (size_t i = first_index; i < c.mesh.indices.size(); i += 3) {
      const glm::vec3 a = c.mesh.positions[c.mesh.indices[i]],
                      b = c.mesh.positions[c.mesh.indices[i + 1]],
                      d = c.mesh.positions[c.mesh.indices[i + 2]];
      EXPECT_GT(glm::dot(glm::cross(b - a, d - a), c.mesh.normals[c.mesh.indices[i]]), 0.0f)
          << "mirror " << mirror << ", triangle " << (i - first_index) / 3;
    }
  }
}

TEST(Prop, RefusalsLeaveTheCharacterUntouched) {
  Character c = embeddedCharacter();
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  const size_t vertices = c.mesh.vertexCount(), sub_meshes = c.mesh.sub_meshes.size();
  const auto refused = [&](const PropMesh& p, const Socket& at, StatusCode code, const char* why) {
    const Status st = attachProp(at, p, &c, nullptr);
    EXPECT_EQ(st.code(), code) << why << ": " << st.message();
    EXPECT_EQ(c.mesh.vertexCount(), vertices) << why;
    EXPECT_EQ(c.mesh.sub_meshes.size(), sub_meshes) << why;
  };
  PropMesh p = boxProp({0.1f, 0.1f, 0.1f});
  p.indices.pop_back();
  refused(p, s, StatusCode::kInvalidArgument, "indices not triangles");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.indices[4] = 24;
  refused(p, s, StatusCode::kOutOfRange, "index past the vertices");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.normals.pop_back();
  refused(p, s, StatusCode::kCountMismatch, "normals");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.positions[3].y = std::numeric_limits<float>::infinity();
  refused(p, s, StatusCode::kNotFinite, "position");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.vertex_materials[2] = 2;
  refused(p, s, StatusCode::kOutOfRange, "vertex material");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.materials[1].base_color_image = 1;
  refused(p, s, StatusCode::kOutOfRange, "image");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.name.clear();
  refused(p, s, StatusCode::kInvalidArgument, "no name");
  p = boxProp({0.1f, 0.1f, 0.1f});
  p.name = c.mesh.sub_meshes[0].name;
  refused(p, s, StatusCode::kInvalidArgument, "a sub-mesh of that name");
  Socket far = s;
  far.joint = uint32_t(c.skeleton.jointCount());
  refused(boxProp({0.1f, 0.1f, 0.1f}), far, StatusCode::kOutOfRange, "joint past the skeleton");
  Socket flat = s;
  flat.bind_frame[1] = glm::vec4(0.0f);
  refused(boxProp({0.1f, 0.1f, 0.1f}), flat, StatusCode::kInvalidArgument, "singular frame");
  EXPECT_EQ(attachProp(s, boxProp({0.1f, 0.1f, 0.1f}), nullptr, nullptr).code(),
            StatusCode::kInvalidArgument);
  // Up to the variation mask's 32 bits.
  for (size_t k = sub_meshes; k < SkinnedMesh::kMaxSubMeshes; ++k) {
    p = boxProp({0.1f, 0.1f, 0.1f});
    p.name = "prop" + std::to_string(k);
    ASSERT_TRUE(attachProp(s, p, &c, nullptr).isOk()) << k;
  }
  const size_t full = c.mesh.vertexCount();
  p.name = "one too many";
  EXPECT_EQ(attachProp(s, p, &c, nullptr).code(), StatusCode::kLimitExceeded);
  EXPECT_EQ(c.mesh.vertexCount(), full);
}

// Texture coordinates or tangents only one side has: the prop without texture coordinates
// gets zeros; a character with tangents gives a prop without them tangents perpendicular to the
// normals (unit, w = 1); a prop's tangents are dropped where the character has none.
TEST(Prop, AttributesOnlyOneSideHasAreFilled) {
  Character c = embeddedCharacter();
  ASSERT_FALSE(c.mesh.texcoords.empty());
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  PropMesh p = boxProp({0.1f, 0.1f, 0.1f});
  p.texcoords.clear();
  const bool had_tangents = !c.mesh.tangents.empty();
  const size_t first = c.mesh.vertexCount();
  ASSERT_TRUE(attachProp(s, p, &c, nullptr).isOk());
  EXPECT_EQ(c.mesh.texcoords.size(), c.mesh.vertexCount());
  EXPECT_EQ(c.mesh.texcoords[first], glm::vec2(0.0f));
  if (had_tangents) {
    ASSERT_EQ(c.mesh.tangents.size(), c.mesh.vertexCount());
    for (size_t v = first; v < c.mesh.vertexCount(); ++v) {
      EXPECT_NEAR(glm::length(glm::vec3(c.mesh.tangents[v])), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(glm::vec3(c.mesh.tangents[v]), c.mesh.normals[v]), 0.0f, 1e-5f);
    }
  } else {
    EXPECT_TRUE(c.mesh.tangents.empty());
  }
}

// Colours and texture coordinates 1 the prop has and the character not: the character's
// vertices get white and 0, the prop's keep theirs; a prop without them on a character with
// them gets white and 0. A colour outside [0, 1] is refused by name.
TEST(Prop, ColoursAndSecondTextureCoordinatesOnlyOneSideHasAreFilled) {
  Character c = embeddedCharacter();
  ASSERT_TRUE(c.mesh.colors.empty() && c.mesh.texcoords1.empty());
  Socket s;
  ASSERT_TRUE(makeSocket(c.skeleton, "grip", "r_hand", gripOffset(), &s).isOk());
  PropMesh p = boxProp({0.1f, 0.1f, 0.1f});
  p.colors.assign(p.positions.size(), glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
  p.texcoords1.assign(p.positions.size(), glm::vec2(0.5f, 2.0f));
  const size_t first = c.mesh.vertexCount();
  ASSERT_TRUE(attachProp(s, p, &c, nullptr).isOk());
  ASSERT_EQ(c.mesh.colors.size(), c.mesh.vertexCount());
  ASSERT_EQ(c.mesh.texcoords1.size(), c.mesh.vertexCount());
  EXPECT_EQ(c.mesh.colors[0], glm::vec4(1.0f));
  EXPECT_EQ(c.mesh.texcoords1[0], glm::vec2(0.0f));
  EXPECT_EQ(c.mesh.colors[first], p.colors[0]);
  EXPECT_EQ(c.mesh.texcoords1[first], p.texcoords1[0]);
  EXPECT_TRUE(c.mesh.validate(c.skeleton.jointCount()).isOk());

  const size_t second = c.mesh.vertexCount();
  PropMesh plain = boxProp({0.1f, 0.1f, 0.1f});
  plain.name = "plain";
  ASSERT_TRUE(attachProp(s, plain, &c, nullptr).isOk());
  EXPECT_EQ(c.mesh.colors[second], glm::vec4(1.0f));
  EXPECT_EQ(c.mesh.texcoords1[second], glm::vec2(0.0f));

  p.name = "bright";
  p.colors[1].r = 1.5f;
  const Status refused = attachProp(s, p, &c, nullptr);
  EXPECT_EQ(refused.code(), StatusCode::kOutOfRange);
  EXPECT_NE(refused.message().find("colour"), std::string::npos) << refused.message();
}

}  // namespace
}  // namespace si
