// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include <gtest/gtest.h>

#include "si/gltf/asset_path.h"

namespace si {
namespace {

TEST(ResolveAssetUri, RelativePaths) {
  std::string p;
  ASSERT_TRUE(resolveAssetUri("/assets/fox", "Fox.bin", &p).isOk());
  EXPECT_EQ(p, "/assets/fox/Fox.bin");
  ASSERT_TRUE(resolveAssetUri("/assets/fox/", "./tex/../Texture%20A.png", &p).isOk());
  EXPECT_EQ(p, "/assets/fox/Texture A.png");
  ASSERT_TRUE(resolveAssetUri("", "a/b.bin", &p).isOk());
  EXPECT_EQ(p, "a/b.bin");
}

TEST(ResolveAssetUri, RejectsEscapesAndExpansion) {
  const char* bad[] = {"",          "../secret.bin", "a/../../x.bin", "/etc/passwd",
                       "%2e%2e/x",  "C:/x.bin",      "file:///x",     "http://h/x.bin",
                       "data:application/octet-stream;base64,AA==",   "a\\b.bin",
                       "a%00b",     "a%zzb",         "bad%2",         ".",
                       "$HOME/x.bin is fine?"};
  for (const char* uri : bad) {
    std::string p = "untouched";
    const Status s = resolveAssetUri("/assets", uri, &p);
    if (std::string(uri) == "$HOME/x.bin is fine?") {
      // No expansion happens: the literal name is kept.
      ASSERT_TRUE(s.isOk());
      EXPECT_EQ(p, "/assets/$HOME/x.bin is fine?");
      continue;
    }
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << uri;
    EXPECT_EQ(p, "untouched") << uri;
  }
}

}  // namespace
}  // namespace si
