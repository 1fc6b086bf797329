// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Composed layers without a GPU: the compose table maps each mask's palette slots to its masked
// indices and back (what layer_compose.glsl reads), and drawCrowd composes only rows that fit
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
#include <gtest/gtest.h>

#include "crowd/layer_compose_table.h"

namespace si::detail {
namespace {

LayerMask maskOf(std::vector<int32_t> anchors) {
  LayerMask m;
  m.slot_anchor = std::move(anchors);
  return m;
}

TEST(LayerComposeTable, MapsEachMasksSlotsToItsMaskedIndicesAndBack) {
  constexpr int32_t kOut = LayerMask::kNotInMask;
  // Six palette slots: an arm of three (anchored at slot 1), and a branch of two from the model.
  const std::vector<LayerMask> masks = {maskOf({kOut, kOut, 1, 1, 1, kOut}),
                                        maskOf({-1, kOut, kOut, kOut, kOut, -1})};
  const std::vector<int32_t> t = layerComposeTable(masks);
  // Header: slots, stride (the larger mask's three), masks, no composed morph targets.
  ASSERT_EQ(t.size(), 4u + 2 * 6 + 2 * 3);
  EXPECT_EQ(t[0], 6);
  EXPECT_EQ(t[1], 3);
  EXPECT_EQ(t[2], 2);
  EXPECT_EQ(t[3], 0);
  const std::vector<int32_t> index_of(t.begin() + 4, t.begin() + 16);
  EXPECT_EQ(index_of, (std::vector<int32_t>{-1, -1, 0, 1, 2, -1, 0, -1, -1, -1, -1, 1}));
  const std::vector<int32_t> slot_of(t.begin() + 16, t.end());
  EXPECT_EQ(slot_of, (std::vector<int32_t>{2, 3, 4, 0, 5, -1}));
  // Each masked index names the slot that maps to it.
  for (uint32_t m = 0; m < 2; ++m)
    for (int32_t k = 0; k < t[1]; ++k) {
      const int32_t slot = t[4 + 2 * 6 + m * 3 + uint32_t(k)];
      if (slot >= 0) {
        EXPECT_EQ(t[4 + m * 6 + uint32_t(slot)], k) << m << " " << k;
      }
    }
  EXPECT_EQ(layerComposeTable({}), (std::vector<int32_t>{0, 0, 0, 0}));
}

// Masks holding morph targets: the table composes the weights of every target up to the
// highest any mask holds, after each record's rows; a mask of targets only composes weights in
// one lane per record.
TEST(LayerComposeTable, ComposesTheWeightsOfTheTargetsTheMasksHold) {
  constexpr int32_t kOut = LayerMask::kNotInMask;
  LayerMask arm = maskOf({kOut, 0, 1, kOut}), face = maskOf({kOut, kOut, kOut, kOut});
  arm.morph_targets = {2};
  face.morph_targets = {0, 5};
  const std::vector<LayerMask> both = {arm, face};
  const ComposeShape shape = composeShape(layerComposeTable(both));
  EXPECT_EQ(shape.stride, 2u);
  EXPECT_EQ(shape.morph_targets, 6u);  // Targets 0 to 5.
  EXPECT_EQ(shape.lanes(), 2u);
  EXPECT_EQ(shape.recordBytes(), 2u * 48 + 2 * 16);  // Two slots' rows, six weights in two vec4s.
  const std::vector<LayerMask> faces = {face};
  const ComposeShape weights_only = composeShape(layerComposeTable(faces));
  EXPECT_EQ(weights_only.stride, 0u);
  EXPECT_EQ(weights_only.lanes(), 1u);
  EXPECT_TRUE(composedRowsFit(1u << 20, 100, weights_only));
}

TEST(LayerComposeTable, RowsPastTheStorageBlockLimitAreNotComposed) {
  const uint64_t limit = uint64_t(128) << 20;  // llvmpipe's GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
  // 48 bytes per masked slot and record.
  const ComposeShape seven{7, 0};
  EXPECT_EQ(composedRowBytes(1000, seven), 1000u * 7 * 48);
  const uint64_t fitting = limit / (48 * 7);
  EXPECT_TRUE(composedRowsFit(limit, fitting, seven));
  EXPECT_FALSE(composedRowsFit(limit, fitting + 1, seven));
  EXPECT_FALSE(composedRowsFit(limit, 10, ComposeShape{}));  // Nothing to compose.
}

}  // namespace
}  // namespace si::detail
