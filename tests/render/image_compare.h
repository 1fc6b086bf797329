// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The render tests' image comparison: colour images (RGBA8, kSize x kSize) pixel by pixel with a
// tolerance, depth images texel by texel, motion images by agreement; and a y-flipped copy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <glm/glm.hpp>

namespace si::test {

// The render tests' image side, in pixels.
inline constexpr uint32_t kSize = 256;
// Image comparison: a pixel differs when a channel is off by more than kPixelTolerance; an image
// matches when at most kMaxDifferingShare of its pixels differ.
inline constexpr int kPixelTolerance = 8;
inline constexpr double kMaxDifferingShare = 0.005;

struct Diff {
  double share = 0.0;
  int max_channel = 0;
};

inline Diff compare(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                    std::vector<uint8_t>* diff_image) {
  Diff d;
  if (a.size() != b.size()) return {1.0, 255};
  size_t differing = 0;
  if (diff_image) diff_image->assign(a.size(), 255);
  for (size_t p = 0; p < a.size(); p += 4) {
    int m = 0;
    for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[p + c]) - int(b[p + c])));
    d.max_channel = std::max(d.max_channel, m);
    if (m > kPixelTolerance) {
      ++differing;
      if (diff_image) (*diff_image)[p] = 255, (*diff_image)[p + 1] = 0, (*diff_image)[p + 2] = 0;
    } else if (diff_image) {
      for (int c = 0; c < 3; ++c) (*diff_image)[p + c] = uint8_t(a[p + c] / 3);
    }
  }
  d.share = double(differing) / double(a.size() / 4);
  return d;
}

// Texels of two depth images more than 1e-6 apart.
inline size_t differingDepths(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) n += std::abs(a[i] - b[i]) > 1e-6f;
  return n;
}

// Two motion images (MotionTarget::readMotion) of one size agree: at least 99.5 % of their
// texels within 1e-4 texture units.
inline void expectMotionAgrees(const std::vector<glm::vec2>& a, const std::vector<glm::vec2>& b) {
  ASSERT_EQ(a.size(), b.size());
  size_t agree = 0;
  for (size_t i = 0; i < a.size(); ++i) agree += glm::length(a[i] - b[i]) < 1e-4f;
  EXPECT_GE(double(agree), 0.995 * double(a.size()));
}

// The longest motion of a motion image (MotionTarget::readMotion, kSize x kSize), in pixels.
inline float largestMotionPixels(const std::vector<glm::vec2>& motion) {
  float worst = 0.0f;
  for (const glm::vec2& v : motion) worst = std::max(worst, glm::length(v) * float(kSize));
  return worst;
}

// `image` (RGBA8, kSize x kSize) upside down.
inline std::vector<uint8_t> flipped(const std::vector<uint8_t>& image) {
  std::vector<uint8_t> out(image.size());
  const size_t row = size_t(kSize) * 4;
  for (uint32_t y = 0; y < kSize; ++y)
    std::memcpy(&out[size_t(kSize - 1 - y) * row], &image[size_t(y) * row], row);
  return out;
}

}  // namespace si::test
