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

namespace {

// The layers of one texture array: images in first-use order, resized to the largest size.
class LayerSet {
 public:
  explicit LayerSet(size_t image_count) : layer_of_image_(image_count, -1) {}
  void use(int32_t image) {
    if (image >= 0 && layer_of_image_[size_t(image)] < 0) {
      layer_of_image_[size_t(image)] = 0;
      used_.push_back(image);
    }
  }
  // Sets `width` and `height` to the largest used image's (capped), resizes the layers already
  // in `out` (the white one) to it, then appends the used images resized; counts resized images.
  void build(const std::vector<Image>& images, uint32_t cap, std::vector<Image>* out,
             uint32_t* width, uint32_t* height, uint32_t* resized) {
    for (int32_t i : used_) {
      *width = std::max(*width, std::min(cap, images[size_t(i)].width));
      *height = std::max(*height, std::min(cap, images[size_t(i)].height));
    }
    for (Image& l : *out) l = resizeImage(l, *width, *height);
    for (int32_t i : used_) {
      const Image& img = images[size_t(i)];
      layer_of_image_[size_t(i)] = int32_t(out->size());
      if (img.width != *width || img.height != *height) ++*resized;
      out->push_back(resizeImage(img, *width, *height));
    }
  }
  uint32_t layer(int32_t image) const {
    return image < 0 ? kNoLayer : uint32_t(layer_of_image_[size_t(image)]);
  }

 private:
  std::vector<int32_t> layer_of_image_;
  std::vector<int32_t> used_;
};

}  // namespace

Status buildMaterialTable(const Character& character, uint32_t max_size, MaterialTable* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "buildMaterialTable: null output"};
  Status s = character.validate();
  if (!s.isOk()) return s;
  const uint32_t cap = max_size == 0 ? 2048 : std::min<uint32_t>(max_size, 16384);
  MaterialTable t;
  LayerSet colour(character.images.size()), data(character.images.size());
  bool needs_white = character.materials.empty();
  for (const Material& m : character.materials) {
    needs_white |= m.base_color_image < 0;
    colour.use(m.base_color_image);
    colour.use(m.emissive_image);
    data.use(m.normal_image);
    data.use(m.metallic_roughness_image);
    data.use(m.occlusion_image);
  }
  if (needs_white) {
    Image white;
    white.width = white.height = 1;
    white.rgba8.assign(4, 255);
    t.layers.push_back(std::move(white));
  }
  colour.build(character.images, cap, &t.layers, &t.width, &t.height, &t.resized_images);
  data.build(character.images, cap, &t.data_layers, &t.data_width, &t.data_height,
             &t.resized_images);
  for (const Material& m : character.materials) {
    MaterialEntry e;
    e.base_color_factor = m.base_color_factor;
    e.layer = m.base_color_image < 0 ? 0 : colour.layer(m.base_color_image);
    e.emissive_layer = colour.layer(m.emissive_image);
    e.normal_layer = data.layer(m.normal_image);
    e.metallic_roughness_layer = data.layer(m.metallic_roughness_image);
    e.occlusion_layer = data.layer(m.occlusion_image);
    e.metallic = m.metallic_factor;
    e.roughness = m.roughness_factor;
    e.normal_scale = m.normal_scale;
    e.occlusion_strength = m.occlusion_strength;
    e.emissive_factor = m.emissive_factor;
    e.alpha_cutoff = m.alpha_mode == AlphaMode::kMask ? m.alpha_cutoff : -1.0f;
    e.double_sided = m.double_sided;
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
