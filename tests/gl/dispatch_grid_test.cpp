// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The CPU side of every compute dispatch, without a GPU: groups in rows within
// GL_MAX_COMPUTE_WORK_GROUP_COUNT, and a refusal past it.
#include <gtest/gtest.h>

#include "gl/paths/dispatch_grid.h"

namespace si::detail {
namespace {

TEST(DispatchGrid, GroupsWithinOneRowStayInOneRow) {
  DispatchGrid g;
  ASSERT_TRUE(dispatchGrid(1, 65535, 65535, &g));
  EXPECT_EQ(g.x, 1u);
  EXPECT_EQ(g.y, 1u);
  ASSERT_TRUE(dispatchGrid(65535, 65535, 65535, &g));
  EXPECT_EQ(g.x, 65535u);
  EXPECT_EQ(g.y, 1u);
  ASSERT_TRUE(dispatchGrid(0, 65535, 65535, &g));  // An empty pass is one group that returns.
  EXPECT_EQ(g.x, 1u);
  EXPECT_EQ(g.y, 1u);
}

// The cases: a LOD of 65535 x 64 + 1 vertices pre-skinned in one dispatch, and the
// GPU-driven cull pass over 4.2 M instances, each one group more than a row of GL's minimum.
TEST(DispatchGrid, PastGlsMinimumTheGroupsGoInRowsThatCoverThemAll) {
  for (uint64_t threads : {uint64_t(65535) * 64 + 1, uint64_t(4200000), uint64_t(1) << 31}) {
    SCOPED_TRACE(threads);
    const uint64_t groups = (threads + 63) / 64;
    DispatchGrid g;
    ASSERT_TRUE(dispatchGrid(groups, 65535, 65535, &g));
    EXPECT_LE(g.x, 65535u);
    EXPECT_LE(g.y, 65535u);
    EXPECT_GE(uint64_t(g.x) * g.y, groups);           // Every group is dispatched,
    EXPECT_LT(uint64_t(g.x) * (g.y - 1), groups);     // and no row is wasted.
  }
  // Zero limits count as GL's minimum.
  DispatchGrid g;
  ASSERT_TRUE(dispatchGrid(65536, 0, 0, &g));
  EXPECT_EQ(g.x, 65535u);
  EXPECT_EQ(g.y, 2u);
}

TEST(DispatchGrid, APassPastBothLimitsIsRefusedAndNothingIsWritten) {
  DispatchGrid g{7, 9};
  EXPECT_FALSE(dispatchGrid(uint64_t(65535) * 65535 + 1, 65535, 65535, &g));
  EXPECT_FALSE(dispatchGrid(7, 2, 3, &g));
  EXPECT_EQ(g.x, 7u);
  EXPECT_EQ(g.y, 9u);
  ASSERT_TRUE(dispatchGrid(6, 2, 3, &g));
  EXPECT_EQ(g.x, 2u);
  EXPECT_EQ(g.y, 3u);
}

}  // namespace
}  // namespace si::detail
