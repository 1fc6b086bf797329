// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd API fuzzer's reader of its input bytes: integers, and floating-point values that are
// hostile (NaN, infinities, extremes) half of the time.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace si::fuzz {

// Reads the input; past its end everything is zero.
class Input {
 public:
  Input(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool done() const { return pos_ >= size_; }
  uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  uint32_t u32() {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(u8()) << (8 * i);
    return v;
  }
  // A value that is hostile half of the time, any bit pattern otherwise.
  double f64() {
    static const double kHostile[] = {std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(),
                                      0.0,
                                      -0.0,
                                      1e-300,
                                      -1.0,
                                      1e300,
                                      -1e300,
                                      1e9,
                                      0.5,
                                      1.0,
                                      std::numeric_limits<double>::max(),
                                      1.0 / 60.0};
    const uint8_t pick = u8();
    if (pick < 128) return kHostile[pick % (sizeof(kHostile) / sizeof(kHostile[0]))];
    uint64_t bits = uint64_t(u32()) | (uint64_t(u32()) << 32);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  float f32() { return float(f64()); }

 private:
  const uint8_t* data_;
  size_t size_, pos_ = 0;
};

}  // namespace si::fuzz
