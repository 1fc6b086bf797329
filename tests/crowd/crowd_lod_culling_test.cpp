// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager's LOD and culling: distance lines in radii with hysteresis, moving the lines,
// and the frustum and far-line culling against a brute-force reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {
using test::defaultCrowdDesc;
using test::defaultPalette;
using test::testCamera;

uint32_t lodSeenFrom(CrowdManager* crowd, InstanceHandle h, double distance) {
  EXPECT_TRUE(crowd->update(0.0, testCamera({0, 0, distance}, {0, 0, 0})).isOk());
  uint32_t lod = 99;
  EXPECT_TRUE(crowd->view().lodOf(h, &lod).isOk());
  return crowd->view().stats().visible == 1 ? lod : 99u;
}

TEST(CrowdManager, LodByDistanceInRadiiWithHysteresis) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = {20.0f, 60.0f};
  cd.lod_hysteresis_ratio = 0.1f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const auto lodAt = [&](double distance) { return lodSeenFrom(&crowd, h, distance); };
  EXPECT_EQ(lodAt(10), 0u);
  EXPECT_EQ(lodAt(21), 0u);   // Past 20 but within the 10 % margin: stays.
  EXPECT_EQ(lodAt(22.5), 1u);
  EXPECT_EQ(lodAt(19), 1u);   // Back under 20 but not under 18: stays.
  EXPECT_EQ(lodAt(17.5), 0u);
  EXPECT_EQ(lodAt(80), 2u);   // Jumps two levels at once.
  EXPECT_EQ(lodAt(10), 0u);
  EXPECT_EQ(crowd.view().stats().per_lod[0], 1u);
  EXPECT_EQ(lodAt(150), 99u);  // Beyond 100 radii: culled by distance.
  EXPECT_EQ(crowd.view().stats().visible, 0u);
  EXPECT_EQ(crowd.view().stats().culled_distance, 1u);
  // The radius scales with the instance.
  ASSERT_TRUE(crowd.setTransform(h, glm::dvec3(0), glm::quat(1, 0, 0, 0), 2.0f).isOk());
  EXPECT_EQ(lodAt(150), 2u);  // 75 radii of a twice larger character.
}

TEST(CrowdManager, SetLodDistancesMovesTheLinesAndValidates) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = {20.0f, 60.0f};
  cd.lod_hysteresis_ratio = 0.01f;
  CrowdManager crowd;
  EXPECT_EQ(crowd.setLodDistances(std::vector<float>{1.0f, 2.0f}).code(),
            StatusCode::kInvalidArgument);  // Before init().
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const auto lodAt = [&](double distance) { return lodSeenFrom(&crowd, h, distance); };
  EXPECT_EQ(lodAt(30), 1u);
  ASSERT_TRUE(crowd.setLodDistances(std::vector<float>{40.0f, 120.0f}).isOk());
  EXPECT_EQ(lodAt(30), 0u);
  EXPECT_EQ(lodAt(130), 99u);  // The far line (100) is kept.
  ASSERT_TRUE(crowd.setLodDistances(std::vector<float>{40.0f, 120.0f}, 200.0f).isOk());
  EXPECT_EQ(lodAt(130), 2u);
  EXPECT_EQ(crowd.desc().max_distance_radii, 200.0f);
  // Bad lines change nothing.
  const std::vector<std::vector<float>> bad = {
      {40.0f}, {40.0f, 30.0f}, {0.0f, 10.0f}, {10.0f, INFINITY}, {10.0f, 20.0f, 30.0f}};
  for (const std::vector<float>& lines : bad)
    EXPECT_EQ(crowd.setLodDistances(lines).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.setLodDistances(std::vector<float>{10.0f, 20.0f}, NAN).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(crowd.desc().lod_distances_radii, (std::vector<float>{40.0f, 120.0f}));
  EXPECT_EQ(lodAt(130), 2u);
}

// Brute-force reference: an instance is truly visible when a skinned vertex of its current
// pose (emulated from the palette, double-transformed) lies inside the frustum.
TEST(CrowdManager, CullingMatchesABruteForceReference) {
  const Character& ch = test::defaultCharacter();
  const BakedPalette& p = defaultPalette();
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(defaultCrowdDesc()).isOk());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-40.0, 40.0), unit(0.0, 1.0);
  std::vector<InstanceHandle> hs;
  for (int i = 0; i < 300; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(pos(rng), pos(rng) * 0.1, pos(rng));
    d.rotation = glm::angleAxis(float(unit(rng) * 6.28), glm::vec3(0, 1, 0));
    d.scale = float(0.5 + unit(rng));
    d.clip = uint32_t(unit(rng) * p.clips.size()) % uint32_t(p.clips.size());
    d.time_seconds = unit(rng) * 3.0;
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    hs.push_back(h);
  }
  std::vector<glm::mat4> mats(ch.skeleton.jointCount());
  std::vector<glm::vec3> skinned(ch.mesh.vertexCount());
  size_t false_positives = 0, truly_visible = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const glm::dvec3 eye(pos(rng), 1.7, pos(rng));
    const Camera cam = testCamera(eye, glm::dvec3(pos(rng), 0.0, pos(rng)));
    ASSERT_TRUE(crowd.update(0.1, cam).isOk());
    std::vector<bool> marked(hs.size(), false);
    for (InstanceHandle h : crowd.view().visibleHandles())
      for (size_t i = 0; i < hs.size(); ++i)
        if (hs[i] == h) marked[i] = true;
    const glm::dmat4 vp(cam.viewProjection());
    for (size_t i = 0; i < hs.size(); ++i) {
      InstanceDesc d;
      ASSERT_TRUE(crowd.get(hs[i], &d).isOk());
      ASSERT_TRUE(emulateSkinningMatrices(p, d.clip, sampleFrames(p.clips[d.clip], d.time_seconds),
                                          mats).isOk());
      ASSERT_TRUE(emulateSkinning(ch.mesh, mats, skinned, {}).isOk());
      const glm::dmat3 rs = glm::dmat3(glm::mat3_cast(d.rotation)) * double(d.scale);
      bool inside = false;
      for (const glm::vec3& v : skinned) {
        const glm::dvec3 rel = d.position - eye + rs * glm::dvec3(v);
        const glm::dvec4 c = vp * glm::dvec4(rel, 1.0);
        if (std::fabs(c.x) <= c.w && std::fabs(c.y) <= c.w && std::fabs(c.z) <= c.w) {
          inside = true;
          break;
        }
      }
      const double dist_radii = glm::length(d.position - eye) /
                                (crowd.desc().character_radius * d.scale);
      if (dist_radii > crowd.desc().max_distance_radii) continue;  // Distance-culled by design.
      if (inside) {
        ++truly_visible;
        EXPECT_TRUE(marked[i]) << "false negative: instance " << i << " trial " << trial;
      } else if (marked[i]) {
        ++false_positives;  // Allowed: the bounding sphere is conservative.
      }
    }
  }
  EXPECT_GT(truly_visible, 50u);  // The scenes do exercise culling.
  EXPECT_LT(false_positives, truly_visible);
  std::printf("[ culling  ] %zu truly visible, %zu conservative extras over 4 cameras\n",
              truly_visible, false_positives);
}

// The culling pass skips a block of 64 instances whose every lane lies beyond the far line
// (cull::anyNearLane): a block with a single nearer lane, first, last or in the padded last block,
// still selects it.
TEST(CrowdManager, ABlockBeyondTheFarLineButForOneLaneSelectsThatLane) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.character_radius = 1.0f;
  cd.max_distance_radii = 100.0f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const uint32_t nearer[] = {0, 127, 137};  // Lane 0 of block 0, 63 of block 1, 9 of block 2.
  std::vector<InstanceHandle> want;
  for (uint32_t i = 0; i < 138; ++i) {
    const bool near = std::find(std::begin(nearer), std::end(nearer), i) != std::end(nearer);
    InstanceDesc d;
    d.position = glm::dvec3(double(i % 8) * 0.5, 0.0, near ? -5.0 : -500.0);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    if (near) want.push_back(h);
  }
  ASSERT_TRUE(crowd.update(0.0, testCamera({0, 1, 10}, {0, 0, -100})).isOk());
  EXPECT_EQ(crowd.view().stats().culled_distance, 135u);
  const std::vector<InstanceHandle> seen(crowd.view().visibleHandles().begin(),
                                         crowd.view().visibleHandles().end());
  EXPECT_EQ(seen, want);
}

}  // namespace
}  // namespace si

namespace si {
namespace {

// CrowdDesc::impostor_lod: only the last level; its instances join sub-mesh 0's bucket once,
// whatever parts they wear; nearer instances keep one bucket entry per worn part.
TEST(CrowdManager, ImpostorLevelBucketsEachInstanceOnceInSubMeshZero) {
  CrowdDesc cd = defaultCrowdDesc();
  cd.lod_count = 3;
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = {20.0f, 60.0f};
  cd.max_distance_radii = -1.0f;
  CrowdManager crowd;
  for (uint32_t bad : {1u, 3u}) {
    cd.impostor_lod = bad;
    const Status s = crowd.init(cd);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("impostor_lod"), std::string::npos) << s.message();
  }
  cd.impostor_lod = 2;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const uint32_t subs = cd.sub_mesh_count;
  ASSERT_GE(subs, 3u);
  const uint32_t masks[4] = {0x1u, 0x6u, 0x7u, 0x4u};  // Two of them without sub-mesh 0.
  for (int k = 0; k < 4; ++k)
    for (double z : {-5.0, -200.0}) {  // LOD 0, and the impostor level.
      InstanceDesc d;
      d.position = glm::dvec3(k * 0.5, 0.0, z);
      d.variation_mask = masks[k];
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
    }
  ASSERT_TRUE(crowd.update(0.0, testCamera({0, 1, 10}, {0, 0, -100})).isOk());
  ASSERT_EQ(crowd.view().stats().per_lod[0], 4u);
  ASSERT_EQ(crowd.view().stats().per_lod[2], 4u);
  const std::vector<uint32_t>& offsets = crowd.view().bucketOffsets();
  const auto entries = [&](uint32_t lod, uint32_t sub) {
    const uint32_t b = lod * subs + sub;
    return offsets[b + 1] - offsets[b];
  };
  EXPECT_EQ(entries(2, 0), 4u);  // Every impostor, once.
  for (uint32_t s = 1; s < subs; ++s) EXPECT_EQ(entries(2, s), 0u) << s;
  EXPECT_EQ(entries(0, 0), 2u);  // Nearer: per worn part.
  EXPECT_EQ(entries(0, 1), 2u);
  EXPECT_EQ(entries(0, 2), 3u);
  EXPECT_EQ(crowd.view().stats().bucket_entries, 4u + 7u);
}

}  // namespace
}  // namespace si
