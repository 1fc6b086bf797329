// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The benches' SSIM (examples/common/image_metrics.h) on images whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/image_metrics.h"

namespace si::examples {
namespace {

std::vector<uint8_t> noiseImage(uint32_t w, uint32_t h, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> img(size_t(w) * h * 4, 255);
  for (size_t i = 0; i < img.size(); ++i)
    if (i % 4 != 3) img[i] = uint8_t(rng() % 256);
  return img;
}

TEST(ImageMetrics, SsimIsOneForIdenticalImagesAndFallsWithStructure) {
  const uint32_t w = 64, h = 48;
  const std::vector<uint8_t> a = noiseImage(w, h, 1);
  EXPECT_DOUBLE_EQ(ssim(a, a, w, h), 1.0);
  // A constant offset keeps the structure: close to 1, below it (the luminance term).
  std::vector<uint8_t> brighter = a;
  for (size_t i = 0; i < brighter.size(); ++i)
    if (i % 4 != 3) brighter[i] = uint8_t(std::min(255, brighter[i] / 2 + 60));
  const double shifted = ssim(a, brighter, w, h);
  // Unrelated noise shares no structure: near 0.
  const double unrelated = ssim(a, noiseImage(w, h, 2), w, h);
  EXPECT_LT(unrelated, 0.1);
  EXPECT_GT(unrelated, -0.1);
  EXPECT_GT(shifted, unrelated + 0.5);
  EXPECT_LT(shifted, 1.0);
  // Symmetric, and NaN where the window does not fit or sizes disagree.
  EXPECT_NEAR(ssim(a, brighter, w, h), ssim(brighter, a, w, h), 1e-12);
  EXPECT_TRUE(std::isnan(ssim(a, a, 8, 8)));
  EXPECT_TRUE(std::isnan(ssim(a, std::vector<uint8_t>(4, 0), w, h)));
}

// A flat image against itself with one pixel changed: the window's mean SSIM falls by a small,
// local amount (only windows covering that pixel change).
TEST(ImageMetrics, OneChangedPixelMovesSsimLocally) {
  const uint32_t w = 40, h = 40;
  std::vector<uint8_t> a(size_t(w) * h * 4, 128), b = a;
  b[(size_t(20) * w + 20) * 4 + 1] = 255;
  const double s = ssim(a, b, w, h);
  EXPECT_LT(s, 1.0);
  EXPECT_GT(s, 0.8);  // 121 of the 900 windows see it.
}

// The temporal error: motion both sequences share counts none; an error that appears, moves or
// flickers between the frames counts where it changes.
TEST(ImageMetrics, ShimmerCountsTheChangesTheReferenceDoesNotMake) {
  const uint32_t w = 16, h = 8;
  // Two frames of noise within [40, 215].
  std::vector<uint8_t> b0 = noiseImage(w, h, 3), b1 = noiseImage(w, h, 4);
  for (std::vector<uint8_t>* im : {&b0, &b1})
    for (uint8_t& v : *im) v = uint8_t(40 + v * 175 / 255);
  EXPECT_EQ(shimmeringPixels(b0, b1, b0, b1, 8), 0u) << "the reference against itself";
  // A constant error (every pixel 20 darker in both frames) does not shimmer.
  std::vector<uint8_t> a0 = b0, a1 = b1;
  for (std::vector<uint8_t>* im : {&a0, &a1})
    for (uint8_t& v : *im) v = uint8_t(v - 20);
  EXPECT_EQ(shimmeringPixels(a0, a1, b0, b1, 8), 0u);
  // An error in frame 1 alone (3 pixels off by 30 in red), and one moving by a pixel.
  a0 = b0, a1 = b1;
  for (size_t p : {5u, 40u, 77u}) a1[p * 4] = uint8_t(b1[p * 4] + 30);
  EXPECT_EQ(shimmeringPixels(a0, a1, b0, b1, 8), 3u);
  EXPECT_EQ(shimmeringPixels(a0, a1, b0, b1, 40), 0u) << "within the tolerance";
  a0 = b0, a1 = b1;
  a0[10 * 4 + 1] = uint8_t(b0[10 * 4 + 1] ^ 0x80);  // The green error at pixel 10, then 11.
  a1[11 * 4 + 1] = uint8_t(b1[11 * 4 + 1] ^ 0x80);
  EXPECT_EQ(shimmeringPixels(a0, a1, b0, b1, 8), 2u);
  EXPECT_EQ(shimmeringPixels(a0, a1, b0, std::vector<uint8_t>(4), 8), SIZE_MAX);
}

}  // namespace
}  // namespace si::examples
