// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The material table and texture array layers of a character (si/core/material_table.h).
#include "si/core/material_table.h"

#include <algorithm>
#include <cmath>

namespace si {
namespace {

// Resampling weights of one axis: for each destination texel, (source texel, weight) pairs.
using Taps = std::vector<std::vector<std::pair<uint32_t, float>>>;

Taps axisTaps(uint32_t from, uint32_t to) {
  Taps taps(to);
  const double scale = double(from) / double(to);
  for (uint32_t d = 0; d < to; ++d) {
    if (scale >= 1.0) {  // Shrinking (or the same size): the box [d, d + 1) * scale.
      const double x0 = d * scale, x1 = (d + 1) * scale;
      for (uint32_t s = uint32_t(std::floor(x0)); s < from && double(s) < x1; ++s) {
        const double w = std::min(x1, double(s + 1)) - std::max(x0, double(s));
        if (w > 0.0) taps[d].push_back({s, float(w / scale)});
      }
    } else {  // Growing: bilinear between the centres, clamped at the edges.
      const double x = (d + 0.5) * scale - 0.5;
      const double f = x - std::floor(x);
      const int64_t s0 = int64_t(std::floor(x));
      const auto clampS = [&](int64_t s) { return uint32_t(std::clamp<int64_t>(s, 0, from - 1)); };
      taps[d].push_back({clampS(s0), float(1.0 - f)});
      taps[d].push_back({clampS(s0 + 1), float(f)});
    }
  }
  return taps;
}

}  // namespace

Image resizeImage(const Image& in, uint32_t width, uint32_t height) {
  if (in.width == width && in.height == height) return in;
  const Taps tx = axisTaps(in.width, width), ty = axisTaps(in.height, height);
  // Rows first (to width x in.height, in float), then columns.
  std::vector<float> rows(size_t(width) * in.height * 4, 0.0f);
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (const auto& [s, w] : tx[x])
        for (int c = 0; c < 4; ++c)
          rows[(size_t(y) * width + x) * 4 + c] += w * in.rgba8[(size_t(y) * in.width + s) * 4 + c];
  Image out;
  out.width = width;
  out.height = height;
  out.rgba8.resize(size_t(width) * height * 4);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c) {
        float v = 0.0f;
        for (const auto& [s, w] : ty[y]) v += w * rows[(size_t(s) * width + x) * 4 + c];
        out.rgba8[(size_t(y) * width + x) * 4 + c] =
            uint8_t(std::clamp(std::lround(v), 0l, 255l));
      }
  return out;
}

Status buildMaterialTable(const Character& character, uint32_t max_size, MaterialTable* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "buildMaterialTable: null output"};
  Status s = character.validate();
  if (!s.isOk()) return s;
  const uint32_t cap = max_size == 0 ? 2048 : std::min<uint32_t>(max_size, 16384);
  MaterialTable t;
  std::vector<int32_t> layer_of_image(character.images.size(), -1);
  std::vector<int32_t> used;  // Images in first-use order.
  bool needs_white = character.materials.empty();
  for (const Material& m : character.materials) {
    if (m.base_color_image < 0) {
      needs_white = true;
    } else if (layer_of_image[size_t(m.base_color_image)] < 0) {
      layer_of_image[size_t(m.base_color_image)] = 0;
      used.push_back(m.base_color_image);
    }
  }
  for (int32_t i : used) {
    t.width = std::max(t.width, std::min(cap, character.images[size_t(i)].width));
    t.height = std::max(t.height, std::min(cap, character.images[size_t(i)].height));
  }
  if (needs_white) {
    Image white;
    white.width = t.width;
    white.height = t.height;
    white.rgba8.assign(size_t(t.width) * t.height * 4, 255);
    t.layers.push_back(std::move(white));
  }
  for (int32_t i : used) {
    const Image& img = character.images[size_t(i)];
    layer_of_image[size_t(i)] = int32_t(t.layers.size());
    if (img.width != t.width || img.height != t.height) ++t.resized_images;
    t.layers.push_back(resizeImage(img, t.width, t.height));
  }
  for (const Material& m : character.materials) {
    MaterialEntry e;
    e.base_color_factor = m.base_color_factor;
    e.layer = m.base_color_image < 0 ? 0 : uint32_t(layer_of_image[size_t(m.base_color_image)]);
    t.materials.push_back(e);
  }
  if (t.materials.empty()) t.materials.push_back(MaterialEntry{});
  t.vertex_materials = resolvedVertexMaterials(character.mesh);
  // Sub-mesh materials are only checked against a non-empty material list: clamp for the GPU.
  for (uint16_t& m : t.vertex_materials)
    m = uint16_t(std::min<size_t>(m, t.materials.size() - 1));
  *out = std::move(t);
  return Status::ok();
}

}  // namespace si
