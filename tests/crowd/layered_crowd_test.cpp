// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Layered animation, the crowd's half: instances play an overlay clip on a joint mask over
// their clip; each drawn instance's layer record, emulated as the shader computes it, skins the
// reference's local-space layered pose within the palette's error; the weight fades in and out;
// crowds without overlays write no layer records.
#include <gtest/gtest.h>

#include <cstring>

#include "crowd/crowd_test_helpers.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/crowd/record_emulation.h"

namespace si {
namespace {

using test::defaultCharacter;
using test::defaultPalette;

struct Layered {
  CrowdManager crowd;
  LayerMask arm;
  uint32_t mask = 0, walk = 0, wave = 0;
  std::vector<InstanceHandle> handles;
};

void makeLayered(Layered* l, uint32_t count) {
  ASSERT_TRUE(l->crowd.init(test::defaultCrowdDesc()).isOk());
  ASSERT_TRUE(buildLayerMask(defaultCharacter().skeleton, defaultPalette(), "right arm",
                             {"r_clavicle"}, &l->arm).isOk());
  ASSERT_TRUE(l->crowd.addLayerMask(l->arm, &l->mask).isOk());
  l->walk = uint32_t(defaultPalette().findClip("walk"));
  l->wave = uint32_t(defaultPalette().findClip("wave"));
  for (uint32_t k = 0; k < count; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(1.5 * k, 0.0, 0.0);
    d.clip = l->walk;
    d.time_seconds = 0.1 * k;
    InstanceHandle h;
    ASSERT_TRUE(l->crowd.add(d, &h).isOk());
    l->handles.push_back(h);
  }
}

Camera viewOf(uint32_t count) {
  return test::testCamera({0.75 * count, 2.0, -8.0}, {0.75 * count, 1.0, 0.0});
}

// Skinned model-space positions of the mesh for a drawn instance, as the shader computes them.
std::vector<glm::vec3> emulatedPositions(const CrowdManager& crowd, size_t record) {
  const BakedPalette& p = defaultPalette();
  const SkinnedMesh& mesh0 = defaultCharacter().mesh;
  SkinnedMesh mesh = mesh0;
  for (glm::vec4& w : mesh.weights) w = dequantizeWeights(quantizeWeights(w));
  std::vector<glm::mat4> m(p.skeleton_to_palette.size(), glm::mat4(1.0f));
  for (size_t j = 0; j < m.size(); ++j)
    if (p.skeleton_to_palette[j] >= 0)
      m[j] = emulateLayeredRecordMatrix(p, crowd.view().records()[record],
                                        crowd.view().layerRecords()[record], crowd.layerMasks(),
                                        uint32_t(p.skeleton_to_palette[j]));
  std::vector<glm::vec3> out(mesh.positions.size());
  EXPECT_TRUE(emulateSkinning(mesh, m, out, {}).isOk());
  return out;
}

double maxDistance(const std::vector<glm::vec3>& a, const std::vector<glm::dvec3>& b) {
  double worst = 0.0;
  for (size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(glm::dvec3(a[v]) - b[v]));
  return worst;
}

TEST(LayeredCrowd, RecordsSkinTheReferenceLayeredPose) {
  Layered l;
  makeLayered(&l, 6);
  // Half the crowd waves at full weight from the start, the other half fades in over 0.5 s.
  for (uint32_t k = 0; k < 6; ++k)
    ASSERT_TRUE(l.crowd.playOverlay(l.handles[k], l.wave, l.mask, 1.0f, k % 2 ? 0.5 : 0.0, 0.2 * k).isOk());
  const Character& c = defaultCharacter();
  const Clip& walk = c.clips[size_t(c.findClip("walk"))];
  const Clip& wave = c.clips[size_t(c.findClip("wave"))];
  double worst_full = 0.0, worst_fading = 0.0;
  for (int frame = 0; frame < 5; ++frame) {
    ASSERT_TRUE(l.crowd.update(0.07, viewOf(6)).isOk());  // Off the 30 Hz frame grid.
    ASSERT_EQ(l.crowd.view().layerRecords().size(), l.crowd.view().records().size());
    ASSERT_EQ(l.crowd.view().records().size(), 6u);
    const double clock = l.crowd.clockSeconds();
    for (size_t r = 0; r < l.crowd.view().records().size(); ++r) {
      uint32_t index = 99;
      for (uint32_t i = 0; i < 6; ++i)
        if (l.crowd.view().visibleHandles()[r] == l.handles[i]) index = i;
      ASSERT_LT(index, 6u);
      const double weight = index % 2 ? std::min(1.0, clock / 0.5) : 1.0;  // 5 x 0.07 s < 0.5 s.
      EXPECT_NEAR(layerWeight(l.crowd.view().layerRecords()[r]), weight, 1e-4);
      ReferencePose pose;
      ASSERT_TRUE(evaluateLayeredPose(c.skeleton, walk, 0.1 * index + clock, wave,
                                      0.2 * index + clock, l.arm, weight, &pose).isOk());
      std::vector<glm::dvec3> reference(c.mesh.positions.size());
      ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}).isOk());
      const double e = maxDistance(emulatedPositions(l.crowd, r), reference);
      (weight == 1.0 ? worst_full : worst_fading) = std::max(weight == 1.0 ? worst_full : worst_fading, e);
    }
  }
  // At full weight, the palette's sampling of both clips through the anchor (the baker's own
  // test bounds it by three times the two clips' errors; at 30 Hz they are about 5e-3 and
  // 7e-3 units). While fading, each link of the arm blended in local space, as the reference
  // blends it: the same sampling error, no more (the dual quaternion blend of whole joints
  // this replaced measured 0.189 units here).
  std::printf("[ layered  ] full weight %.3g units, fading %.3g units\n", worst_full, worst_fading);
  EXPECT_GT(worst_full, 0.0);
  EXPECT_LT(worst_full, 0.04);
  EXPECT_GT(worst_fading, 0.0);
  EXPECT_LT(worst_fading, 0.04);
}

TEST(LayeredCrowd, TheWeightFadesInAndOut) {
  Layered l;
  makeLayered(&l, 1);
  const InstanceHandle h = l.handles[0];
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_TRUE(l.crowd.view().layerRecords().empty());  // No overlay yet: no stream.
  ASSERT_TRUE(l.crowd.playOverlay(h, l.wave, l.mask, 0.8f, 0.4).isOk());
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_NEAR(layerWeight(l.crowd.view().layerRecords()[0]), 0.2f, 1e-4);
  EXPECT_EQ(layerMask(l.crowd.view().layerRecords()[0]), l.mask);
  ASSERT_TRUE(l.crowd.update(0.4, viewOf(1)).isOk());
  EXPECT_NEAR(layerWeight(l.crowd.view().layerRecords()[0]), 0.8f, 1e-4);
  ASSERT_TRUE(l.crowd.stopOverlay(h, 0.2).isOk());
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_NEAR(layerWeight(l.crowd.view().layerRecords()[0]), 0.4f, 1e-4);
  // A new overlay continues from the weight it finds.
  ASSERT_TRUE(l.crowd.playOverlay(h, l.walk, l.mask, 1.0f, 0.6).isOk());
  ASSERT_TRUE(l.crowd.update(0.3, viewOf(1)).isOk());
  EXPECT_NEAR(layerWeight(l.crowd.view().layerRecords()[0]), 0.7f, 1e-4);
  ASSERT_TRUE(l.crowd.stopOverlay(h, 0.0).isOk());
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_EQ(layerWeight(l.crowd.view().layerRecords()[0]), 0.0f);
  // jointMatrix follows the overlay: the hand of a waving instance is where the record puts it.
  ASSERT_TRUE(l.crowd.playOverlay(h, l.wave, l.mask, 1.0f, 0.0, 0.3).isOk());
  ASSERT_TRUE(l.crowd.update(0.05, viewOf(1)).isOk());
  const uint32_t hand = uint32_t(defaultCharacter().skeleton.findJoint("r_hand"));
  glm::dmat4 world_hand;
  ASSERT_TRUE(l.crowd.jointMatrix(h, hand, &world_hand).isOk());
  const glm::mat4 drawn = emulateLayeredRecordMatrix(
      defaultPalette(), l.crowd.view().records()[0], l.crowd.view().layerRecords()[0],
      l.crowd.layerMasks(), uint32_t(defaultPalette().skeleton_to_palette[hand]));
  const glm::dvec4 p(0.27, 0.91, 0.02, 1.0);  // The hand's bind position.
  EXPECT_LT(glm::length(glm::dvec3(world_hand * p) - glm::dvec3(glm::dmat4(drawn) * p)), 1e-4);
}

// What GPU-driven culling reads: nothing while no overlay plays; then every instance in dense
// order, playing or not, and playing or stopping one moves the state version.
TEST(LayeredCrowd, ExportsTheOverlaysForTheGpu) {
  Layered l;
  makeLayered(&l, 3);
  std::vector<GpuOverlayState> out(5);
  CrowdExport(l.crowd).overlays(&out);
  EXPECT_TRUE(out.empty());
  const uint64_t before = CrowdExport(l.crowd).stateVersion();
  ASSERT_TRUE(l.crowd.advance(0.25).isOk());
  ASSERT_TRUE(l.crowd.playOverlay(l.handles[1], l.wave, l.mask, 0.75f, 0.5, 0.2, 1.5f).isOk());
  EXPECT_NE(CrowdExport(l.crowd).stateVersion(), before);
  CrowdExport(l.crowd).overlays(&out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].active, 0u);
  EXPECT_EQ(out[2].active, 0u);
  const GpuOverlayState& o = out[1];
  EXPECT_EQ(o.active, 1u);
  EXPECT_EQ(o.clip, l.wave);
  EXPECT_EQ(o.mask, l.mask);
  EXPECT_DOUBLE_EQ(o.start_clock, 0.25);
  EXPECT_DOUBLE_EQ(o.start_time, 0.2);
  EXPECT_FLOAT_EQ(o.speed, 1.5f);
  EXPECT_FLOAT_EQ(o.weight_from, 0.0f);
  EXPECT_FLOAT_EQ(o.weight_to, 0.75f);
  EXPECT_DOUBLE_EQ(o.fade_start, 0.25);
  EXPECT_DOUBLE_EQ(o.fade_duration, 0.5);
  EXPECT_EQ(o.loop, uint32_t(defaultPalette().clips[l.wave].loop_mode));
  const uint64_t playing = CrowdExport(l.crowd).stateVersion();
  ASSERT_TRUE(l.crowd.stopOverlay(l.handles[1], 0.0).isOk());
  EXPECT_NE(CrowdExport(l.crowd).stateVersion(), playing);
  CrowdExport(l.crowd).overlays(&out);
  ASSERT_EQ(out.size(), 3u);  // Stopped overlays stay, at weight 0.
  EXPECT_FLOAT_EQ(out[1].weight_to, 0.0f);
}

// Motion vectors of overlays: the previous update's layer records are kept beside the previous
// records, and the batcher lays each slot's out as build() lays its record (an instance added
// since gets its current one, as buildPrevious does).
TEST(LayeredCrowd, KeepsThePreviousLayerRecords) {
  Layered l;
  CrowdDesc cd = test::defaultCrowdDesc();
  cd.previous_records = true;
  ASSERT_TRUE(l.crowd.init(cd).isOk());
  ASSERT_TRUE(buildLayerMask(defaultCharacter().skeleton, defaultPalette(), "right arm",
                             {"r_clavicle"}, &l.arm).isOk());
  ASSERT_TRUE(l.crowd.addLayerMask(l.arm, &l.mask).isOk());
  l.wave = uint32_t(defaultPalette().findClip("wave"));
  const auto addOne = [&](uint32_t k) {
    InstanceDesc d;
    d.position = glm::dvec3(1.5 * k, 0.0, 0.0);
    d.time_seconds = 0.1 * k;
    InstanceHandle h;
    ASSERT_TRUE(l.crowd.add(d, &h).isOk());
    ASSERT_TRUE(l.crowd.playOverlay(h, l.wave, l.mask, 1.0f, 0.0, 0.2 * k).isOk());
    l.handles.push_back(h);
  };
  for (uint32_t k = 0; k < 5; ++k) addOne(k);
  const Camera camera = viewOf(6);
  ASSERT_TRUE(l.crowd.update(0.0, camera).isOk());
  EXPECT_TRUE(
      l.crowd.view().previousLayerRecords().empty());  // The first update had no previous one.
  const std::vector<LayerRecord> first(l.crowd.view().layerRecords().begin(),
                                       l.crowd.view().layerRecords().end());
  ASSERT_EQ(first.size(), 5u);
  addOne(5);
  ASSERT_TRUE(l.crowd.update(0.1, camera).isOk());
  ASSERT_EQ(l.crowd.view().previousLayerRecords().size(), first.size());
  for (size_t i = 0; i < first.size(); ++i)
    EXPECT_EQ(
        std::memcmp(&l.crowd.view().previousLayerRecords()[i], &first[i], sizeof(LayerRecord)), 0);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init({16384, 256, 0}).isOk());
  std::vector<uint8_t> records(batcher.recordBufferBound(l.crowd.view()));
  std::vector<uint8_t> previous(batcher.layerBufferBound(l.crowd.view())), current(previous.size());
  std::vector<DrawBatch> draws;
  ASSERT_TRUE(batcher.build(l.crowd.view(), records, &draws).isOk());
  ASSERT_TRUE(batcher.buildLayers(l.crowd.view(), current).isOk());
  ASSERT_TRUE(batcher.buildPreviousLayers(l.crowd.view(), previous).isOk());
  size_t kept = 0, fallbacks = 0;
  for (const DrawBatch& d : draws)
    for (uint32_t k = 0; k < d.instance_count; ++k) {
      InstanceRecord rec;
      std::memcpy(&rec, records.data() + d.byte_offset + k * kInstanceRecordSize, sizeof rec);
      // The slot's record is records()[i] for the i whose record it is.
      size_t i = 0;
      while (i < l.crowd.view().records().size() &&
             std::memcmp(&l.crowd.view().records()[i], &rec, sizeof rec) != 0)
        ++i;
      ASSERT_LT(i, l.crowd.view().records().size());
      const uint32_t p = l.crowd.view().previousRecordIndices()[i];
      const uint8_t* slot = previous.data() + d.layer_byte_offset + k * kLayerRecordSize;
      const void* expected =
          p == kNoPreviousRecord
              ? static_cast<const void*>(&l.crowd.view().layerRecords()[i])
              : static_cast<const void*>(&l.crowd.view().previousLayerRecords()[p]);
      EXPECT_EQ(std::memcmp(slot, expected, kLayerRecordSize), 0) << i;
      (p == kNoPreviousRecord ? fallbacks : kept) += 1;
    }
  EXPECT_GT(kept, 0u);
  EXPECT_GT(fallbacks, 0u);  // The instance added between the updates.
  // Refused: a crowd without previous records.
  Layered plain;
  makeLayered(&plain, 2);
  ASSERT_TRUE(plain.crowd.playOverlay(plain.handles[0], plain.wave, plain.mask, 1.0f, 0.0).isOk());
  ASSERT_TRUE(plain.crowd.update(0.0, viewOf(2)).isOk());
  std::vector<uint8_t> out(batcher.layerBufferBound(plain.crowd.view()));
  EXPECT_EQ(batcher.buildPreviousLayers(plain.crowd.view(), out).code(),
            StatusCode::kInvalidArgument);
}

TEST(LayeredCrowd, RefusesBadMasksAndArguments) {
  Layered l;
  makeLayered(&l, 1);
  const InstanceHandle h = l.handles[0];
  LayerMask bad = l.arm;
  bad.slot_anchor.pop_back();
  EXPECT_EQ(l.crowd.addLayerMask(bad, nullptr).code(), StatusCode::kInvalidArgument);
  for (uint32_t k = 1; k < CrowdManager::kMaxLayerMasks; ++k)
    ASSERT_TRUE(l.crowd.addLayerMask(l.arm, nullptr).isOk());
  EXPECT_EQ(l.crowd.addLayerMask(l.arm, nullptr).code(), StatusCode::kLimitExceeded);
  EXPECT_EQ(l.crowd.layerMasks().size(), CrowdManager::kMaxLayerMasks);
  const uint32_t clips = uint32_t(defaultPalette().clips.size());
  EXPECT_EQ(l.crowd.playOverlay(h, clips, 0, 1.0f, 0.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(l.crowd.playOverlay(h, l.wave, 99, 1.0f, 0.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(l.crowd.playOverlay(h, l.wave, 0, 1.5f, 0.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(l.crowd.playOverlay(h, l.wave, 0, 1.0f, -1.0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(l.crowd.playOverlay(h, l.wave, 0, 1.0f, 0.0, std::nan("")).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(l.crowd.stopOverlay(h, std::nan("")).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(l.crowd.stopOverlay(h, 0.1).isOk());  // None plays: nothing to do.
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_TRUE(l.crowd.view().layerRecords().empty());  // Refused calls started nothing.
  // A removed instance's overlay goes with it.
  ASSERT_TRUE(l.crowd.playOverlay(h, l.wave, 0, 1.0f, 0.0).isOk());
  ASSERT_TRUE(l.crowd.remove(h).isOk());
  EXPECT_EQ(l.crowd.playOverlay(h, l.wave, 0, 1.0f, 0.0).code(), StatusCode::kNotFound);
  InstanceDesc d;
  InstanceHandle other;
  ASSERT_TRUE(l.crowd.add(d, &other).isOk());
  ASSERT_TRUE(l.crowd.update(0.1, viewOf(1)).isOk());
  EXPECT_TRUE(l.crowd.view().layerRecords().empty());
}

}  // namespace
}  // namespace si
