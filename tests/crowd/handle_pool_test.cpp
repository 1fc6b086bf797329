// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include "si/crowd/handle_pool.h"

namespace si {
namespace {

TEST(HandlePool, AllocateReleaseAndStaleHandles) {
  HandlePool pool;
  InstanceHandle a, b;
  ASSERT_TRUE(pool.allocate(&a).isOk());
  ASSERT_TRUE(pool.allocate(&b).isOk());
  EXPECT_NE(a, b);
  EXPECT_EQ(pool.aliveCount(), 2u);
  EXPECT_EQ(pool.state(a), HandleState::kAlive);
  ASSERT_TRUE(pool.release(a).isOk());
  EXPECT_EQ(pool.state(a), HandleState::kStale);
  EXPECT_EQ(pool.release(a).code(), StatusCode::kNotFound);  // Double release.

  InstanceHandle c;
  ASSERT_TRUE(pool.allocate(&c).isOk());  // Reuses a's slot with a new generation.
  uint32_t slot_a = 99, slot_c = 0;
  EXPECT_EQ(pool.slot(a, &slot_a).code(), StatusCode::kNotFound);
  EXPECT_EQ(slot_a, 99u);  // Untouched.
  ASSERT_TRUE(pool.slot(c, &slot_c).isOk());
  EXPECT_EQ(pool.slotCount(), 2u);
  EXPECT_NE(a, c);  // Same slot, different handle: the stale one never aliases.
  EXPECT_EQ(pool.state(a), HandleState::kStale);
  EXPECT_EQ(pool.handleAt(slot_c), c);
}

TEST(HandlePool, InvalidHandles) {
  HandlePool pool;
  EXPECT_EQ(pool.state(InstanceHandle{}), HandleState::kInvalid);
  EXPECT_EQ(pool.state(InstanceHandle{(1u << 20) | 5u}), HandleState::kInvalid);
  EXPECT_EQ(pool.release(InstanceHandle{}).code(), StatusCode::kNotFound);
  EXPECT_EQ(pool.allocate(nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(pool.handleAt(3), InstanceHandle{});
}

TEST(HandlePool, GenerationSurvivesManyReuses) {
  HandlePool pool;
  InstanceHandle first, h;
  ASSERT_TRUE(pool.allocate(&first).isOk());
  ASSERT_TRUE(pool.release(first).isOk());
  for (int i = 0; i < 4000; ++i) {
    ASSERT_TRUE(pool.allocate(&h).isOk());
    ASSERT_NE(h, first) << "reuse " << i;
    ASSERT_TRUE(pool.release(h).isOk());
  }
  EXPECT_EQ(pool.slotCount(), 1u);
}

}  // namespace
}  // namespace si
