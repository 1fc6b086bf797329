// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Image comparison for the benches: the structural similarity index (SSIM) of Z. Wang, A. C.
// Bovik, H. R. Sheikh and E. P. Simoncelli, "Image quality assessment: from error visibility to
// structural similarity", IEEE Trans. Image Processing 13(4), 2004: on luma, with their 11 x 11
// Gaussian window (sigma 1.5) and constants K1 = 0.01, K2 = 0.03 for 8-bit data. And a
// temporal error: how much of an approximation's frame-to-frame change is not the reference's.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace si::examples {

namespace detail {
// Rec. 601 luma of an RGBA8 image, as doubles.
inline std::vector<double> luma(const std::vector<uint8_t>& rgba, size_t pixels) {
  std::vector<double> y(pixels);
  for (size_t i = 0; i < pixels; ++i)
    y[i] = 0.299 * rgba[i * 4] + 0.587 * rgba[i * 4 + 1] + 0.114 * rgba[i * 4 + 2];
  return y;
}
// The image filtered by the separable window, over the positions where the window fits
// (w - 10) x (h - 10).
inline std::vector<double> window(const std::vector<double>& in, uint32_t w, uint32_t h,
                                  const double* g) {
  const uint32_t ow = w - 10, oh = h - 10;
  std::vector<double> rows(size_t(ow) * h), out(size_t(ow) * oh);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int k = 0; k < 11; ++k) s += g[k] * in[size_t(y) * w + x + k];
      rows[size_t(y) * ow + x] = s;
    }
  for (uint32_t y = 0; y < oh; ++y)
    for (uint32_t x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int k = 0; k < 11; ++k) s += g[k] * rows[size_t(y + k) * ow + x];
      out[size_t(y) * ow + x] = s;
    }
  return out;
}
}  // namespace detail

/// Mean SSIM of two RGBA8 images of w x h pixels (1 for identical images, lower as structure
/// differs; may be negative). Images smaller than the 11 x 11 window, or of another size than
/// w * h * 4 bytes, give NaN.
inline double ssim(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, uint32_t w,
                   uint32_t h) {
  const size_t pixels = size_t(w) * h;
  if (w < 11 || h < 11 || a.size() != pixels * 4 || b.size() != pixels * 4) return std::nan("");
  double g[11], sum = 0.0;
  for (int k = 0; k < 11; ++k) sum += g[k] = std::exp(-double((k - 5) * (k - 5)) / (2.0 * 1.5 * 1.5));
  for (double& v : g) v /= sum;
  const std::vector<double> x = detail::luma(a, pixels), y = detail::luma(b, pixels);
  std::vector<double> xx(pixels), yy(pixels), xy(pixels);
  for (size_t i = 0; i < pixels; ++i) xx[i] = x[i] * x[i], yy[i] = y[i] * y[i], xy[i] = x[i] * y[i];
  const std::vector<double> mx = detail::window(x, w, h, g), my = detail::window(y, w, h, g);
  const std::vector<double> sxx = detail::window(xx, w, h, g), syy = detail::window(yy, w, h, g);
  const std::vector<double> sxy = detail::window(xy, w, h, g);
  const double c1 = (0.01 * 255.0) * (0.01 * 255.0), c2 = (0.03 * 255.0) * (0.03 * 255.0);
  double total = 0.0;
  for (size_t i = 0; i < mx.size(); ++i) {
    const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i];
    const double cov = sxy[i] - mx[i] * my[i];
    total += ((2.0 * mx[i] * my[i] + c1) * (2.0 * cov + c2)) /
             ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
  }
  return total / double(mx.size());
}

/// Pixels that shimmer between two consecutive frames of an approximation (`a0`, `a1`) against
/// the same frames of its reference (`b0`, `b1`), all RGBA8 of one size: those whose change from
/// frame to frame, in some channel of RGB, differs from the reference's by more than
/// `tolerance` (of 255). Motion both images share (the camera's, the animation's) counts none;
/// an error that moves or flickers counts where it does. The count, or SIZE_MAX when the sizes
/// disagree.
inline size_t shimmeringPixels(const std::vector<uint8_t>& a0, const std::vector<uint8_t>& a1,
                               const std::vector<uint8_t>& b0, const std::vector<uint8_t>& b1,
                               int tolerance) {
  if (a1.size() != a0.size() || b0.size() != a0.size() || b1.size() != a0.size()) return SIZE_MAX;
  size_t n = 0;
  for (size_t i = 0; i + 3 < a0.size(); i += 4) {
    int worst = 0;
    for (size_t c = 0; c < 3; ++c)
      worst = std::max(
          worst, std::abs((int(a1[i + c]) - int(a0[i + c])) - (int(b1[i + c]) - int(b0[i + c]))));
    n += worst > tolerance ? 1 : 0;
  }
  return n;
}

}  // namespace si::examples
