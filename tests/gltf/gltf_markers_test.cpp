// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Animation markers from a glTF file: the animation's extras ({"markers": [{"time", "name"}]})
// become Clip::markers, which the baker copies into the palette; malformed entries are skipped
// with a warning each; other extras are left alone.
#include <gtest/gtest.h>

#include "gltf/import_json.h"
#include "gltf/parts_asset.h"
#include "si/bake/animation_baker.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

// The generated asset (one 1 s animation "sway") with `extras` on its animation.
std::string withExtras(const std::string& extras) {
  std::string json = test::partsAsset({{"Body", 2}}, 1);
  const std::string key = "\"name\":\"sway\",";
  const size_t at = json.find(key);
  EXPECT_NE(at, std::string::npos);
  return json.insert(at + key.size(), "\"extras\":" + extras + ",");
}

using test::importJson;

size_t warningsMentioning(const GltfImportReport& r, const std::string& text) {
  size_t n = 0;
  for (const std::string& w : r.warnings) n += w.find(text) != std::string::npos;
  return n;
}

TEST(GltfMarkers, ExtrasMarkersReachTheClipAndThePalette) {
  Character c;
  GltfImportReport r;
  const Status s = importJson(
      withExtras(R"({"author":"x","markers":[{"time":0.25,"name":"left"},{"time":1,"name":"end"}]})"),
      &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.clips.size(), 1u);
  const std::vector<AnimationMarker> expected = {{0.25, "left"}, {1.0, "end"}};
  EXPECT_EQ(c.clips[0].markers, expected);
  EXPECT_EQ(warningsMentioning(r, "markers"), 0u);
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  BakedPalette p;
  ASSERT_TRUE(bakePalette(c, d, &p, nullptr).isOk());
  EXPECT_EQ(p.clips[0].markers, expected);
}

TEST(GltfMarkers, MalformedEntriesAreSkippedWithAWarningEach) {
  Character c;
  GltfImportReport r;
  const Status s = importJson(withExtras(R"({"markers":[
      {"time":0.5,"name":"kept"}, {"time":"soon","name":"a"}, {"name":"b"}, {"time":0.1},
      {"time":0.2,"name":""}, {"time":2.5,"name":"late"}, {"time":-1,"name":"early"}, 7]})"),
      &c, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  ASSERT_EQ(c.clips.size(), 1u);
  const std::vector<AnimationMarker> expected = {{0.5, "kept"}};
  EXPECT_EQ(c.clips[0].markers, expected);
  EXPECT_EQ(warningsMentioning(r, "extras.markers["), 7u);
  EXPECT_EQ(warningsMentioning(r, "extras.markers[5]: time 2.5 s is outside"), 1u);
  // Not an array: one warning, nothing imported; extras without markers: nothing said.
  Character c2;
  GltfImportReport r2;
  ASSERT_TRUE(importJson(withExtras(R"({"markers":{"time":0.5}})"), &c2, &r2).isOk());
  EXPECT_TRUE(c2.clips[0].markers.empty());
  EXPECT_EQ(warningsMentioning(r2, "extras.markers is not an array"), 1u);
  Character c3;
  GltfImportReport r3;
  ASSERT_TRUE(importJson(withExtras(R"({"tool":"exporter 1.2"})"), &c3, &r3).isOk());
  EXPECT_TRUE(c3.clips[0].markers.empty());
  EXPECT_EQ(warningsMentioning(r3, "markers"), 0u);
}

}  // namespace
}  // namespace si
