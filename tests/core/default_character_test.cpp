// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "si/core/default_character.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

const Character& character() {
  static Character c = [] {
    Character out;
    EXPECT_TRUE(makeDefaultCharacter({}, &out).isOk());
    return out;
  }();
  return c;
}

TEST(DefaultCharacter, Validates) { EXPECT_TRUE(character().validate().isOk()); }

TEST(DefaultCharacter, HasTheDocumentedContent) {
  const Character& c = character();
  EXPECT_GE(c.skeleton.jointCount(), 20u);
  for (const char* name : {"pelvis", "spine", "neck", "head", "l_upperarm", "r_hand", "l_thigh",
                           "r_foot"})
    EXPECT_GE(c.skeleton.findJoint(name), 0) << name;
  // The body is 1.8 units tall; the bind-pose bounds include the upright spear (2.05).
  EXPECT_NEAR(c.height(), 2.05f, 0.05f);
  ASSERT_GE(c.mesh.sub_meshes.size(), 4u);
  EXPECT_EQ(c.mesh.sub_meshes[0].name, "body");
  EXPECT_EQ(c.mesh.maxLodCount(), 3u);
  // Body LODs: about 4000, 1000 and 250 triangles, each coarser than the last.
  EXPECT_NEAR(double(c.mesh.triangleCount(0, 0)), 4000.0, 600.0);
  EXPECT_NEAR(double(c.mesh.triangleCount(0, 1)), 1000.0, 250.0);
  EXPECT_NEAR(double(c.mesh.triangleCount(0, 2)), 250.0, 80.0);
  for (size_t s = 0; s < c.mesh.sub_meshes.size(); ++s) {
    for (size_t l = 1; l < 3; ++l) {
      EXPECT_LT(c.mesh.triangleCount(s, l), c.mesh.triangleCount(s, l - 1));
    }
  }

  for (const char* name : {"idle", "walk", "run"}) {
    const int32_t i = c.findClip(name);
    ASSERT_GE(i, 0) << name;
    EXPECT_EQ(c.clips[size_t(i)].loop_mode, LoopMode::kLoop) << name;
  }
  ASSERT_GE(c.findClip("wave"), 0);
  EXPECT_EQ(c.clips[size_t(c.findClip("wave"))].loop_mode, LoopMode::kOnce);
  ASSERT_EQ(c.images.size(), 1u);
  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_EQ(c.materials[0].base_color_image, 0);
}

TEST(DefaultCharacter, WeightsSumToOneAndUseUpToThreeJoints) {
  const SkinnedMesh& m = character().mesh;
  size_t blended = 0;
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    const glm::vec4 w = m.weights[v];
    EXPECT_NEAR(double(w.x) + w.y + w.z + w.w, 1.0, 1e-6) << "vertex " << v;
    EXPECT_EQ(w.w, 0.0f);
    if (w.y > 0.0f) ++blended;
  }
  EXPECT_GT(blended, m.vertexCount() / 10);  // Smooth joints, not rigid pieces.
}

TEST(DefaultCharacter, RootJointIsUnweighted) {
  const SkinnedMesh& m = character().mesh;
  const uint16_t root = uint16_t(character().skeleton.findJoint("root"));
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    for (int i = 0; i < 4; ++i) {
      if (m.weights[v][i] > 0.0f) {
        EXPECT_NE(m.joints[v][i], root);
      }
    }
  }
}

TEST(DefaultCharacter, TintMaskHasTintedAndUntintedTexels) {
  const Image& img = character().images[0];
  size_t tinted = 0, plain = 0;
  for (size_t i = 3; i < img.rgba8.size(); i += 4) (img.rgba8[i] == 255 ? tinted : plain)++;
  EXPECT_GT(tinted, 0u);
  EXPECT_GT(plain, 0u);
}

TEST(DefaultCharacter, IsDeterministic) {
  Character a, b;
  ASSERT_TRUE(makeDefaultCharacter({}, &a).isOk());
  ASSERT_TRUE(makeDefaultCharacter({}, &b).isOk());
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
  EXPECT_EQ(0, std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                           a.mesh.positions.size() * sizeof(glm::vec3)));
  EXPECT_EQ(a.mesh.indices, b.mesh.indices);
  for (size_t c = 0; c < a.clips.size(); ++c)
    for (size_t j = 0; j < a.skeleton.jointCount(); ++j) {
      const auto& qa = a.clips[c].joint_tracks[j].rotation.values;
      const auto& qb = b.clips[c].joint_tracks[j].rotation.values;
      ASSERT_EQ(qa.size(), qb.size());
      if (qa.empty()) continue;
      EXPECT_EQ(0, std::memcmp(qa.data(), qb.data(), qa.size() * sizeof(glm::quat)));
    }
}

TEST(DefaultCharacter, LodCountOption) {
  Character c;
  DefaultCharacterDesc d;
  d.lod_count = 1;
  ASSERT_TRUE(makeDefaultCharacter(d, &c).isOk());
  EXPECT_EQ(c.mesh.maxLodCount(), 1u);
  d.lod_count = 4;
  Character untouched;
  EXPECT_EQ(makeDefaultCharacter(d, &untouched).code(), StatusCode::kOutOfRange);
  EXPECT_TRUE(untouched.mesh.positions.empty());
  EXPECT_EQ(makeDefaultCharacter(d, nullptr).code(), StatusCode::kInvalidArgument);
}

TEST(DefaultCharacter, RestPoseReproducesTheMesh) {
  const Character& c = character();
  ReferencePose pose;
  ASSERT_TRUE(evaluateRestPose(c.skeleton, &pose).isOk());
  std::vector<glm::dvec3> p(c.mesh.vertexCount());
  ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, p, {}, {}).isOk());
  double max_error = 0.0;
  for (size_t v = 0; v < p.size(); ++v)
    max_error = std::max(max_error, glm::length(p[v] - glm::dvec3(c.mesh.positions[v])));
  EXPECT_LT(max_error, 1e-6);
}

TEST(DefaultCharacter, ClipsStayFiniteAndPlausibleAndLoopsAreSeamless) {
  const Character& c = character();
  std::vector<glm::dvec3> p(c.mesh.vertexCount()), n(c.mesh.vertexCount());
  for (const Clip& clip : c.clips) {
    for (int k = 0; k <= 20; ++k) {
      const double t = clip.duration_seconds * k / 20.0;
      ReferencePose pose;
      ASSERT_TRUE(evaluatePose(c.skeleton, clip, t, &pose).isOk());
      ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, p, n, {}).isOk());
      for (size_t v = 0; v < p.size(); ++v) {
        ASSERT_TRUE(std::isfinite(p[v].x) && std::isfinite(p[v].y) && std::isfinite(p[v].z));
        ASSERT_LT(glm::length(p[v] - glm::dvec3(0, 1, 0)), 2.5)
            << clip.name << " t=" << t << " vertex " << v;
        ASSERT_NEAR(glm::length(n[v]), 1.0, 1e-9);
      }
    }
    if (clip.loop_mode != LoopMode::kLoop) continue;
    // A seamless loop: the pose just before the end equals the pose at the start.
    ReferencePose start, end;
    ASSERT_TRUE(evaluatePose(c.skeleton, clip, 0.0, &start).isOk());
    ASSERT_TRUE(evaluatePose(c.skeleton, clip, clip.duration_seconds - 1e-9, &end).isOk());
    for (size_t j = 0; j < start.model.size(); ++j)
      EXPECT_NEAR(glm::length(glm::dvec3(start.model[j][3] - end.model[j][3])), 0.0, 1e-6)
          << clip.name << " joint " << j;
  }
}

TEST(DefaultCharacter, ClipsMoveTheLimbs) {
  // Each clip must actually animate: the right hand moves by centimetres over the clip.
  const Character& c = character();
  const size_t hand = size_t(c.skeleton.findJoint("r_hand"));
  for (const Clip& clip : c.clips) {
    ReferencePose a, b;
    ASSERT_TRUE(evaluatePose(c.skeleton, clip, 0.0, &a).isOk());
    double moved = 0.0;
    for (int k = 1; k <= 10; ++k) {
      ASSERT_TRUE(evaluatePose(c.skeleton, clip, clip.duration_seconds * k / 10.0, &b).isOk());
      moved = std::max(moved, glm::length(glm::dvec3(b.model[hand][3] - a.model[hand][3])));
    }
    EXPECT_GT(moved, 0.01) << clip.name;
  }
}

}  // namespace
}  // namespace si
