// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "si/core/log.h"
#include "si/core/status.h"

namespace si {
namespace {

TEST(Status, DefaultIsOk) {
  Status s;
  EXPECT_TRUE(s.isOk());
  EXPECT_EQ(s.code(), StatusCode::kOk);
  EXPECT_EQ(s.toString(), "Ok");
}

TEST(Status, ErrorCarriesCodeAndMessage) {
  Status s(StatusCode::kNotSorted, "clip 'run': joint 3 key times not increasing at key 2");
  EXPECT_FALSE(s.isOk());
  EXPECT_EQ(s.code(), StatusCode::kNotSorted);
  EXPECT_EQ(s.toString(), "NotSorted: clip 'run': joint 3 key times not increasing at key 2");
}

TEST(Status, OkCodeDropsMessage) {
  Status s(StatusCode::kOk, "ignored");
  EXPECT_TRUE(s.isOk());
  EXPECT_TRUE(s.message().empty());
}

struct Captured {
  std::vector<std::pair<LogLevel, std::string>> messages;
};

TEST(Log, SilentByDefaultAndRoutesToCallback) {
  logMessage(LogLevel::kWarning, "nobody listens");  // Must not crash or print.
  Captured captured;
  setLogCallback(
      [](LogLevel level, const char* message, void* user) {
        static_cast<Captured*>(user)->messages.emplace_back(level, message);
      },
      &captured);
  logMessage(LogLevel::kWarning, "skipped channel");
  logMessage(LogLevel::kDefault, "default level");
  setLogCallback(nullptr, nullptr);
  logMessage(LogLevel::kError, "after removal");
  ASSERT_EQ(captured.messages.size(), 2u);
  EXPECT_EQ(captured.messages[0].first, LogLevel::kWarning);
  EXPECT_EQ(captured.messages[0].second, "skipped channel");
  EXPECT_EQ(captured.messages[1].first, LogLevel::kInfo);
}

}  // namespace
}  // namespace si
