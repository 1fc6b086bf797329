// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The SPIR-V reader on what is not a well-formed module: refused by name with nothing written,
// and never read past the end (every prefix of a real module, and modules with words flipped at
// random, read under the sanitizers).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "vk/spirv_modules.h"
#include "vk/spirv_reflect.h"

namespace si::vk::detail {
namespace {

std::vector<uint32_t> realModule() {
  const SpirvModule* m = findSpirvModule("skinned.frag");
  if (m == nullptr) return {};
  return std::vector<uint32_t>(m->words, m->words + m->word_count);
}

TEST(SpirvReflect, WhatIsNotAModuleIsRefusedByName) {
  SpirvReflection out;
  out.descriptors.push_back({});
  const std::vector<uint32_t> not_spirv = {1, 2, 3, 4, 5, 6};
  Status s = reflectSpirv(not_spirv, "SiDefaultUniforms", &out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("magic"), std::string::npos) << s.toString();
  EXPECT_EQ(out.descriptors.size(), 1u) << "nothing written on failure";
  std::vector<uint32_t> words = realModule();
  ASSERT_GT(words.size(), 40u);
  // An instruction whose word count runs past the end.
  words[5] = (0xFFFFu << 16) | (words[5] & 0xFFFFu);
  s = reflectSpirv(words, "SiDefaultUniforms", &out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("word 5 runs past"), std::string::npos) << s.toString();
  // An OpVariable (opcode 59) of one word: shorter than its operands.
  words = realModule();
  words.push_back((1u << 16) | 59u);
  s = reflectSpirv(words, "SiDefaultUniforms", &out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("shorter than its operands"), std::string::npos) << s.toString();
  EXPECT_EQ(reflectSpirv(realModule(), "SiDefaultUniforms", nullptr).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(out.descriptors.size(), 1u);
}

TEST(SpirvReflect, PrefixesAndFlippedWordsAreReadOrRefusedNeverOverrun) {
  const std::vector<uint32_t> words = realModule();
  ASSERT_FALSE(words.empty());
  SpirvReflection whole;
  ASSERT_TRUE(reflectSpirv(words, "SiDefaultUniforms", &whole).isOk());
  ASSERT_FALSE(whole.descriptors.empty());
  for (size_t n = 0; n < words.size(); n += 7) {
    SpirvReflection r;
    const Status s = reflectSpirv(Span<const uint32_t>(words.data(), n), "SiDefaultUniforms", &r);
    EXPECT_TRUE(s.isOk() || s.code() == StatusCode::kInvalidArgument) << n;
  }
  std::mt19937 random(7);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint32_t> bad = words;
    for (int k = 0; k < 4; ++k) bad[5 + random() % (bad.size() - 5)] = uint32_t(random());
    SpirvReflection r;
    const Status s = reflectSpirv(bad, "SiDefaultUniforms", &r);
    EXPECT_TRUE(s.isOk() || s.code() == StatusCode::kInvalidArgument) << trial;
  }
}

}  // namespace
}  // namespace si::vk::detail
