// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Composed layers without a GPU: the compose table maps each mask's palette slots to its masked
// indices and back (what layer_compose.glsl reads), and drawCrowd composes only rows that fit
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
#include <gtest/gtest.h>

#include "gl/resources/layer_compose_table.h"

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
  // Header: slots, stride (the larger mask's three), masks.
  ASSERT_EQ(t.size(), 3u + 2 * 6 + 2 * 3);
  EXPECT_EQ(t[0], 6);
  EXPECT_EQ(t[1], 3);
  EXPECT_EQ(t[2], 2);
  const std::vector<int32_t> index_of(t.begin() + 3, t.begin() + 15);
  EXPECT_EQ(index_of, (std::vector<int32_t>{-1, -1, 0, 1, 2, -1, 0, -1, -1, -1, -1, 1}));
  const std::vector<int32_t> slot_of(t.begin() + 15, t.end());
  EXPECT_EQ(slot_of, (std::vector<int32_t>{2, 3, 4, 0, 5, -1}));
  // Each masked index names the slot that maps to it.
  for (uint32_t m = 0; m < 2; ++m)
    for (int32_t k = 0; k < t[1]; ++k) {
      const int32_t slot = t[3 + 2 * 6 + m * 3 + uint32_t(k)];
      if (slot >= 0) {
        EXPECT_EQ(t[3 + m * 6 + uint32_t(slot)], k) << m << " " << k;
      }
    }
  EXPECT_EQ(layerComposeTable({}), (std::vector<int32_t>{0, 0, 0}));
}

TEST(LayerComposeTable, RowsPastTheStorageBlockLimitAreNotComposed) {
  const uint64_t limit = uint64_t(128) << 20;  // llvmpipe's GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
  // 48 bytes per masked slot and record.
  EXPECT_EQ(composedRowBytes(1000, 7), 1000u * 7 * 48);
  const uint64_t fitting = limit / (48 * 7);
  EXPECT_TRUE(composedRowsFit(limit, fitting, 7));
  EXPECT_FALSE(composedRowsFit(limit, fitting + 1, 7));
  EXPECT_FALSE(composedRowsFit(limit, 10, 0));  // No masked slot: nothing to compose.
}

}  // namespace
}  // namespace si::detail
