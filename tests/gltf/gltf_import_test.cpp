// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// glTF import on the real sample assets in assets and on synthetic files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "gltf/gltf_writer.h"
#include "si/bake/animation_baker.h"
#include "si/core/reference_evaluator.h"
#include "si/gltf/gltf_import.h"
#include "test_assets.h"

namespace si {
namespace {

constexpr int kFloat = 5126, kUByte = 5121, kUShort = 5123;

std::string assets() { return SI_ASSETS_DIR; }

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

struct Sample {
  const char* path;
  uint32_t skin_joints;
  std::vector<std::pair<const char*, float>> clips;  // Name (empty: unnamed) and duration.
  bool rest_is_bind;
};

const Sample kSamples[] = {
    {"RiggedSimple/glTF/RiggedSimple.gltf", 2, {{"", 2.0833f}}, false},
    {"RiggedSimple/glTF-Binary/RiggedSimple.glb", 2, {{"", 2.0833f}}, false},
    {"RiggedFigure/glTF-Binary/RiggedFigure.glb", 19, {{"", 1.25f}}, false},
    {"CesiumMan/glTF/CesiumMan.gltf", 19, {{"", 2.0f}}, false},
    {"CesiumMan/glTF-Binary/CesiumMan.glb", 19, {{"", 2.0f}}, false},
    {"Fox/glTF-Binary/Fox.glb", 24, {{"Survey", 3.4167f}, {"Walk", 0.7083f}, {"Run", 1.1583f}}, true},
    {"SimpleSkin/glTF/SimpleSkin.gltf", 2, {{"", 5.5f}}, true},
    {"SimpleSkin/glTF-Embedded/SimpleSkin.gltf", 2, {{"", 5.5f}}, true},
};

class SampleAsset : public ::testing::TestWithParam<Sample> {};

TEST_P(SampleAsset, LoadsValidatesEvaluatesAndBakes) {
  const Sample& sample = GetParam();
  const std::string path = assets() + "/" + sample.path;
  ASSERT_TRUE(test::assetExists(path));
  Character c;
  GltfImportReport r;
  const Status s = importGltfFile(path, {}, &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  EXPECT_TRUE(c.validate().isOk());
  EXPECT_EQ(r.skin_joints, sample.skin_joints);
  EXPECT_GE(c.skeleton.jointCount(), sample.skin_joints);
  ASSERT_EQ(c.clips.size(), sample.clips.size());
  for (size_t i = 0; i < c.clips.size(); ++i) {
    if (sample.clips[i].first[0] != '\0') {
      EXPECT_EQ(c.clips[i].name, sample.clips[i].first);
    }
    EXPECT_NEAR(c.clips[i].duration_seconds, sample.clips[i].second, 1e-3f);
  }
  // Skinned positions at several times are finite and stay near the mesh.
  const Aabb bind = c.bindPoseBounds();
  const double reach = 4.0 * glm::length(bind.extent()) + 1.0;
  std::vector<glm::dvec3> p(c.mesh.vertexCount());
  for (const Clip& clip : c.clips) {
    for (int k = 0; k <= 6; ++k) {
      ReferencePose pose;
      ASSERT_TRUE(evaluatePose(c.skeleton, clip, clip.duration_seconds * k / 6.0, &pose).isOk());
      ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, p, {}, {}).isOk());
      for (const glm::dvec3& v : p) {
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
        ASSERT_LT(glm::length(v - glm::dvec3(bind.center())), reach) << clip.name;
      }
    }
  }
  if (sample.rest_is_bind) {  // The file's bind pose is its rest pose: rest skinning is exact.
    ReferencePose rest;
    ASSERT_TRUE(evaluateRestPose(c.skeleton, &rest).isOk());
    ASSERT_TRUE(skinVertices(c.mesh, rest.skinning, p, {}, {}).isOk());
    double e = 0.0;
    for (size_t v = 0; v < p.size(); ++v)
      e = std::max(e, glm::length(p[v] - glm::dvec3(c.mesh.positions[v])));
    EXPECT_LT(e, 1e-6 * (1.0 + glm::length(bind.extent())));
  }
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  BakedPalette palette;
  const Status b = bakePalette(c, d, &palette, nullptr);
  EXPECT_TRUE(b.isOk()) << b.toString();
}

INSTANTIATE_TEST_SUITE_P(Assets, SampleAsset, ::testing::ValuesIn(kSamples),
                         [](const auto& param_info) {
                           std::string n = param_info.param.path;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

TEST(GltfImport, FoxHasItsTextureAndClips) {
  const std::string path = assets() + "/Fox/glTF/Fox.gltf";
  ASSERT_TRUE(test::assetExists(path));
  Character c;
  ASSERT_TRUE(importGltfFile(path, {}, &c, nullptr).isOk());
  ASSERT_GE(c.images.size(), 1u);
  EXPECT_GT(c.images[0].width, 0u);
  ASSERT_GE(c.materials.size(), 2u);  // The default plus the file's.
  EXPECT_GE(c.materials[c.mesh.sub_meshes[0].material].base_color_image, 0);
  GltfImportDesc no_images;
  no_images.load_images = false;
  Character plain;
  ASSERT_TRUE(importGltfFile(path, no_images, &plain, nullptr).isOk());
  EXPECT_TRUE(plain.images.empty());
}

TEST(GltfImport, GeneratesLodsWithMeshoptimizer) {
  const std::string path = assets() + "/CesiumMan/glTF-Binary/CesiumMan.glb";
  ASSERT_TRUE(test::assetExists(path));
  GltfImportDesc d;
  d.generate_lods = 2;
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importGltfFile(path, d, &c, &r).isOk());
  EXPECT_EQ(r.generated_lods, 2u);
  ASSERT_EQ(c.mesh.sub_meshes[0].lods.size(), 3u);
  EXPECT_LT(c.mesh.triangleCount(0, 1), c.mesh.triangleCount(0, 0));
  EXPECT_LT(c.mesh.triangleCount(0, 2), c.mesh.triangleCount(0, 1));
  EXPECT_TRUE(c.validate().isOk());
}

TEST(GltfImport, EveryTruncationAndManyByteFlipsGiveAnErrorOrAValidResult) {
  const std::string path = assets() + "/RiggedSimple/glTF-Binary/RiggedSimple.glb";
  ASSERT_TRUE(test::assetExists(path));
  const std::vector<uint8_t> bytes = readFile(path);
  ASSERT_GT(bytes.size(), 100u);
  size_t errors = 0;
  for (size_t n = 0; n < bytes.size(); n += 1 + n / 64) {
    Character c;
    const Status s = importGltfMemory(Span<const uint8_t>(bytes.data(), n), "", {}, &c, nullptr);
    if (s.isOk()) {
      EXPECT_TRUE(c.validate().isOk());
    } else {
      ++errors;
    }
  }
  EXPECT_GT(errors, 0u);
  for (size_t i = 0; i < bytes.size(); i += 7) {
    std::vector<uint8_t> bad = bytes;
    bad[i] ^= uint8_t(0x5A);
    Character c;
    const Status s = importGltfMemory(bad, "", {}, &c, nullptr);
    if (s.isOk()) {
      ASSERT_TRUE(c.validate().isOk()) << "byte " << i;
    }
  }
}

TEST(GltfImport, ExternalUrisMayNotLeaveTheAssetFolder) {
  const std::string json =
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"../../etc/passwd"}]})";
  Character c;
  const Status s = importGltfMemory(
      Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "/tmp/a",
      {}, &c, nullptr);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt) << s.toString();
  EXPECT_EQ(importGltfFile("/nonexistent/x.gltf", {}, &c, nullptr).code(), StatusCode::kIo);
  EXPECT_EQ(importGltfMemory({}, "", {}, nullptr, nullptr).code(), StatusCode::kInvalidArgument);
}

// ---- Synthetic files -----------------------------------------------------------------------

// Two joints (root and a child 1 up), a triangle, and the given extras. `joints_u16` switches
// the joint component type; `second_set` adds JOINTS_1/WEIGHTS_1; `sparse` stores the positions
// as a zero accessor with sparse values.
std::string syntheticAsset(bool joints_u16, bool second_set, bool sparse, bool two_skins,
                           const std::string& interpolation, float child_scale_x = 1.0f,
                           bool animated = true) {
  test::GltfWriter w;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  int pos_acc;
  if (sparse) {
    const std::vector<uint16_t> idx = {1, 2};
    const std::vector<float> vals = {1, 0, 0, 0, 1, 0};
    const int iv = w.view(idx.data(), idx.size() * 2), vv = w.view(vals.data(), vals.size() * 4);
    pos_acc = w.rawAccessor(-1, kFloat, "VEC3", 3,
                            ",\"sparse\":{\"count\":2,\"indices\":{\"bufferView\":" +
                                std::to_string(iv) + ",\"componentType\":5123},\"values\":{"
                                "\"bufferView\":" + std::to_string(vv) + "}}");
  } else {
    pos_acc = w.accessor(pos, kFloat, "VEC3", 3);
  }
  int joints_acc, weights_acc;
  if (joints_u16) {
    joints_acc = w.accessor(std::vector<uint16_t>{0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kUShort, "VEC4", 3);
  } else {
    joints_acc = w.accessor(std::vector<uint8_t>{0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, kUByte, "VEC4", 3);
  }
  // Normalized u16 weights: vertex 0 half and half, others rigid.
  weights_acc = w.accessor(std::vector<uint16_t>{32768, 32767, 0, 0, 65535, 0, 0, 0, 65535, 0, 0, 0},
                           kUShort, "VEC4", 3, ",\"normalized\":true");
  std::string attributes = "\"POSITION\":" + std::to_string(pos_acc) + ",\"JOINTS_0\":" +
                           std::to_string(joints_acc) + ",\"WEIGHTS_0\":" + std::to_string(weights_acc);
  if (second_set) {
    const int j1 = w.accessor(std::vector<uint8_t>{1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, kUByte, "VEC4", 3);
    const int w1 = w.accessor(std::vector<float>{0.1f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, kFloat, "VEC4", 3);
    attributes += ",\"JOINTS_1\":" + std::to_string(j1) + ",\"WEIGHTS_1\":" + std::to_string(w1);
  }
  const int idx = w.accessor(std::vector<uint8_t>{0, 1, 2, 0}, kUByte, "SCALAR", 3);
  w.meshes = "{\"name\":\"tri\",\"primitives\":[{\"attributes\":{" + attributes +
             "},\"indices\":" + std::to_string(idx) + "}]}";
  w.nodes = "{\"name\":\"root\",\"children\":[1,2]},"
            "{\"name\":\"child\",\"translation\":[0,1,0],\"scale\":[" +
            std::to_string(child_scale_x) + ",1,1]},"
            "{\"name\":\"body\",\"mesh\":0,\"skin\":0}";
  w.skins = "{\"name\":\"main\",\"joints\":[0,1]}";
  if (two_skins) w.skins += ",{\"name\":\"other\",\"joints\":[1]}";
  // A rotation channel on the child with the chosen interpolation.
  const bool cubic = interpolation == "CUBICSPLINE";
  const int in = w.accessor(std::vector<float>{0.0f, 0.5f, 1.0f}, kFloat, "SCALAR", 3);
  std::vector<float> out;
  const float keys[3][4] = {{0, 0, 0, 1}, {0, 0, 0.38268343f, 0.92387953f}, {0, 0, 0.70710678f, 0.70710678f}};
  for (const auto& k : keys) {
    if (cubic) out.insert(out.end(), {0, 0, 0, 0});
    out.insert(out.end(), k, k + 4);
    if (cubic) out.insert(out.end(), {0, 0, 0, 0});
  }
  const int o = w.accessor(out, kFloat, "VEC4", out.size() / 4);
  w.animations = "{\"name\":\"bend\",\"samplers\":[{\"input\":" + std::to_string(in) +
                 ",\"output\":" + std::to_string(o) + ",\"interpolation\":\"" + interpolation +
                 "\"}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":1,\"path\":\"rotation\"}},"
                 "{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"rotation\"}}]}";
  if (!animated) w.animations.clear();
  return w.json();
}

Status importString(const std::string& json, const GltfImportDesc& d, Character* c,
                    GltfImportReport* r = nullptr) {
  return importGltfMemory(Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()),
                                              json.size()), "", d, c, r);
}

TEST(GltfSynthetic, StepAndCubicSplineChannels) {
  for (const char* interp : {"STEP", "CUBICSPLINE", "LINEAR"}) {
    Character c;
    GltfImportReport r;
    const Status s = importString(syntheticAsset(false, false, false, false, interp), {}, &c, &r);
    ASSERT_TRUE(s.isOk()) << interp << ": " << s.toString();
    ASSERT_EQ(c.clips.size(), 1u);
    const int32_t child = c.skeleton.findJoint("child");
    const QuatTrack& t = c.clips[0].joint_tracks[size_t(child)].rotation;
    EXPECT_EQ(t.values.size(), std::string(interp) == "CUBICSPLINE" ? 9u : 3u) << interp;
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], 0.4, &pose).isOk());
    const double angle = 2.0 * std::acos(std::min(1.0, std::fabs(pose.local[size_t(child)].rotation.w)));
    if (std::string(interp) == "STEP") {
      EXPECT_NEAR(angle, 0.0, 1e-6);  // Holds key 0.
    } else if (std::string(interp) == "LINEAR") {
      EXPECT_NEAR(angle, 0.8 * 0.7853982, 1e-5);
    }
    // The channel on the mesh node (outside the skeleton) was skipped with a warning.
    bool warned = false;
    for (const std::string& w : r.warnings) warned |= w.find("outside the skeleton") != std::string::npos;
    EXPECT_TRUE(warned);
  }
}

// A skinned asset without animation imports with its rest pose as one clip, which bakes into a
// one-frame palette that poses every vertex where the reference puts it; without the option it
// has no clips and the baker says how to give it one.
TEST(GltfSynthetic, AssetWithoutAnimationBakesItsRestPose) {
  const std::string json = syntheticAsset(false, false, false, false, "LINEAR", 1.5f, false);
  Character c;
  GltfImportReport r;
  const Status s = importString(json, {}, &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.clips.size(), 1u);
  EXPECT_EQ(c.clips[0].name, "rest_pose");
  EXPECT_EQ(c.clips[0].duration_seconds, 0.0f);
  EXPECT_TRUE(r.added_rest_pose_clip);
  bool warned = false;
  for (const std::string& w : r.warnings) warned |= w.find("rest_pose") != std::string::npos;
  EXPECT_TRUE(warned);
  // The rest pose: every joint at its rest transform.
  ReferencePose pose;
  ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], 0.0, &pose).isOk());
  for (size_t j = 0; j < c.skeleton.jointCount(); ++j) {
    EXPECT_EQ(pose.local[j].translation, glm::dvec3(c.skeleton.rest_pose[j].translation)) << j;
    EXPECT_EQ(pose.local[j].scale, glm::dvec3(c.skeleton.rest_pose[j].scale)) << j;
  }
  BakedPalette p;
  BakeReport report;
  BakeDesc d;
  const Status baked = bakePalette(c, d, &p, &report);
  ASSERT_TRUE(baked.isOk()) << baked.toString();
  ASSERT_EQ(p.clips.size(), 1u);
  EXPECT_EQ(p.clips[0].name, "rest_pose");
  EXPECT_LE(p.clips[0].frame_count, 2u);
  ASSERT_FALSE(report.clips.empty());
  EXPECT_TRUE(report.clips[0].tolerance_met);
  EXPECT_LE(report.max_error_ratio, 1e-4);
  EXPECT_GT(report.clips[0].samples, 0u);
  // Without the option: no clips, and baking says what to do.
  GltfImportDesc none;
  none.rest_pose_clip_when_none = false;
  Character bare;
  GltfImportReport bare_report;
  ASSERT_TRUE(importString(json, none, &bare, &bare_report).isOk());
  EXPECT_TRUE(bare.clips.empty());
  EXPECT_FALSE(bare_report.added_rest_pose_clip);
  const Status refused = bakePalette(bare, d, &p, nullptr);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("makeRestPoseClip"), std::string::npos) << refused.message();
}

TEST(GltfSynthetic, ComponentTypesSecondWeightSetAndSparse) {
  Character c;
  GltfImportReport r;
  ASSERT_TRUE(importString(syntheticAsset(true, true, true, false, "LINEAR"), {}, &c, &r).isOk());
  EXPECT_EQ(c.mesh.positions[1], glm::vec3(1, 0, 0));  // From the sparse values.
  EXPECT_EQ(c.mesh.positions[0], glm::vec3(0, 0, 0));  // Not in the sparse set: zero.
  // Vertex 0: 0.5 / 0.5 from set 0 plus 0.1 on joint 1 from set 1: renormalized.
  EXPECT_GT(r.vertices_renormalized, 0u);
  EXPECT_NEAR(c.mesh.weights[0].x + c.mesh.weights[0].y + c.mesh.weights[0].z, 1.0f, 1e-6f);
  EXPECT_TRUE(c.validate().isOk());
}

TEST(GltfSynthetic, NegativeScaleAndSeveralSkins) {
  Character c;
  ASSERT_TRUE(importString(syntheticAsset(false, false, false, false, "LINEAR", -1.0f), {}, &c).isOk());
  EXPECT_EQ(c.skeleton.rest_pose[size_t(c.skeleton.findJoint("child"))].scale.x, -1.0f);
  BakedPalette p;
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  EXPECT_TRUE(bakePalette(c, d, &p, nullptr).isOk());  // Matrix formats take the mirror.
  d.format = PaletteFormat::kQuatTranslationF32;
  EXPECT_EQ(bakePalette(c, d, &p, nullptr).code(), StatusCode::kUnsupported);

  const std::string two = syntheticAsset(false, false, false, true, "LINEAR");
  EXPECT_EQ(importString(two, {}, &c).code(), StatusCode::kAmbiguous);
  GltfImportDesc by_name;
  by_name.skin_name = "main";
  EXPECT_TRUE(importString(two, by_name, &c).isOk());
  GltfImportDesc by_index;
  by_index.skin_index = 5;
  EXPECT_EQ(importString(two, by_index, &c).code(), StatusCode::kNotFound);
  by_name.skin_name = "nope";
  EXPECT_EQ(importString(two, by_name, &c).code(), StatusCode::kNotFound);
}

TEST(GltfSynthetic, OutOfRangeDataIsAnErrorNamingIt) {
  std::string json = syntheticAsset(false, false, false, false, "LINEAR");
  // Point the index accessor past its view: "count":3 of the index accessor becomes 300.
  const std::string key = "\"componentType\":5121,\"type\":\"SCALAR\",\"count\":3";
  const size_t at = json.find(key);
  ASSERT_NE(at, std::string::npos);
  std::string bad = json;
  bad.replace(at, key.size(), "\"componentType\":5121,\"type\":\"SCALAR\",\"count\":300");
  Character c;
  const Status s = importString(bad, {}, &c);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("accessor"), std::string::npos) << s.message();
  EXPECT_TRUE(importString(json, {}, &c).isOk());  // The unmodified file loads.
}

}  // namespace
}  // namespace si
