// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Materials (glTF 2.0 specification, "Materials"): the metallic-roughness model whole (base
// colour, metallic-roughness, normal, occlusion and emissive textures with their factors,
// alphaMode and alphaCutoff, doubleSided); images converted to RGBA8 once however many
// materials use them. Index 0 is a default white material for primitives without one.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

class ImageTable {
 public:
  ImageTable(const tinygltf::Model& m, std::vector<std::string>* warnings, Character* c)
      : m_(m), warnings_(*warnings), c_(*c) {}

  // The character image of `info` (a material's texture reference), or -1 with a warning when
  // it has none usable. `what` names the reference in warnings.
  template <typename TextureInfo>
  int32_t image(const TextureInfo& info, const std::string& what) {
    const int tex = info.index;
    if (tex < 0) return -1;
    if (size_t(tex) >= m_.textures.size()) {
      warnings_.push_back(strCat(what, ": texture ", tex, " does not exist: skipped"));
      return -1;
    }
    if (info.texCoord != 0)
      warnings_.push_back(strCat(what, ": uses TEXCOORD_", info.texCoord,
                                 "; the library reads TEXCOORD_0 for it"));
    if (!info.extensions.empty())
      warnings_.push_back(strCat(what, ": texture extensions (", info.extensions.begin()->first,
                                 ") not supported: ignored"));
    const int src = m_.textures[size_t(tex)].source;
    // Not decoded (GltfImportDesc::load_images off, or parseGltf's warnings say why).
    if (src < 0 || size_t(src) >= m_.images.size() || m_.images[size_t(src)].image.empty())
      return -1;
    const auto it = image_map_.find(src);
    if (it != image_map_.end()) return it->second;
    const int32_t converted = convert(src);
    if (converted >= 0) image_map_[src] = converted;
    return converted;
  }

 private:
  int32_t convert(int src) {
    const tinygltf::Image& im = m_.images[size_t(src)];
    Image out_image;
    out_image.width = uint32_t(std::max(im.width, 0));
    out_image.height = uint32_t(std::max(im.height, 0));
    const int comps = im.component, bytes = im.bits / 8;
    const uint64_t texels = uint64_t(out_image.width) * out_image.height;
    if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
        im.image.size() != texels * uint64_t(comps) * uint64_t(bytes)) {
      if (reported_.insert(src).second)
        warnings_.push_back(strCat("image ", src, ": unexpected layout: skipped"));
      return -1;
    }
    out_image.rgba8.resize(size_t(texels) * 4);
    for (uint64_t t = 0; t < texels; ++t)
      for (int ch = 0; ch < 4; ++ch) {
        uint8_t v = ch == 3 ? 255 : 0;
        const int from = comps >= 3 ? ch : (ch < 3 ? 0 : 1);
        if (from < comps && (ch < 3 || comps == 4 || comps == 2))
          v = im.image[size_t((t * uint64_t(comps) + uint64_t(from)) * uint64_t(bytes) + uint64_t(bytes - 1))];
        out_image.rgba8[size_t(t * 4 + uint64_t(ch))] = v;
      }
    c_.images.push_back(std::move(out_image));
    return int32_t(c_.images.size() - 1);
  }

  const tinygltf::Model& m_;
  std::vector<std::string>& warnings_;
  Character& c_;
  std::map<int, int32_t> image_map_;
  std::set<int> reported_;  // Images refused, warned once.
};

glm::vec4 vec4Or(const std::vector<double>& f, glm::vec4 fallback) {
  return f.size() == 4 ? glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3])) : fallback;
}

// `v` clamped into [lo, hi] with a warning when it was outside (NaN becomes `lo`).
float clampedFactor(double v, float lo, float hi, const std::string& what,
                    std::vector<std::string>* warnings) {
  const float f = float(v);
  if (f >= lo && f <= hi) return f;
  const float c = f > hi ? hi : lo;
  warnings->push_back(strCat(what, " ", v, " is outside [", lo, ", ", hi, "]: ", c, " used"));
  return c;
}

}  // namespace

void convertMaterials(const tinygltf::Model& m, GltfImportReport* report, Character* c) {
  std::vector<std::string>& warnings = report->warnings;
  Material fallback;
  fallback.name = "default";
  c->materials.push_back(fallback);
  ImageTable images(m, &warnings, c);
  for (size_t i = 0; i < m.materials.size(); ++i) {
    const tinygltf::Material& mat = m.materials[i];
    const std::string where = strCat("material ", i, " '", mat.name, "'");
    const tinygltf::PbrMetallicRoughness& pbr = mat.pbrMetallicRoughness;
    Material out;
    out.name = mat.name;
    out.base_color_factor = vec4Or(pbr.baseColorFactor, glm::vec4(1.0f));
    for (int ch = 0; ch < 4; ++ch)
      out.base_color_factor[ch] = clampedFactor(out.base_color_factor[ch], 0.0f, 1.0f,
                                                where + " baseColorFactor", &warnings);
    out.base_color_image = images.image(pbr.baseColorTexture, where + " baseColorTexture");
    out.metallic_factor = clampedFactor(pbr.metallicFactor, 0.0f, 1.0f, where + " metallicFactor", &warnings);
    out.roughness_factor = clampedFactor(pbr.roughnessFactor, 0.0f, 1.0f, where + " roughnessFactor", &warnings);
    out.metallic_roughness_image =
        images.image(pbr.metallicRoughnessTexture, where + " metallicRoughnessTexture");
    out.normal_image = images.image(mat.normalTexture, where + " normalTexture");
    out.normal_scale = std::isfinite(mat.normalTexture.scale) ? float(mat.normalTexture.scale) : 1.0f;
    out.occlusion_image = images.image(mat.occlusionTexture, where + " occlusionTexture");
    out.occlusion_strength = clampedFactor(mat.occlusionTexture.strength, 0.0f, 1.0f,
                                           where + " occlusionTexture.strength", &warnings);
    if (mat.emissiveFactor.size() == 3)
      for (int ch = 0; ch < 3; ++ch)
        out.emissive_factor[ch] = clampedFactor(mat.emissiveFactor[size_t(ch)], 0.0f, 1.0f,
                                                where + " emissiveFactor", &warnings);
    out.emissive_image = images.image(mat.emissiveTexture, where + " emissiveTexture");
    if (mat.alphaMode == "MASK") {
      out.alpha_mode = AlphaMode::kMask;
      out.alpha_cutoff = std::isfinite(mat.alphaCutoff) && mat.alphaCutoff >= 0.0
                             ? float(mat.alphaCutoff) : 0.5f;
    } else if (mat.alphaMode == "BLEND") {
      out.alpha_mode = AlphaMode::kBlend;
      warnings.push_back(where + ": alphaMode BLEND: the crowd draws it opaque (no sorting)");
    } else if (mat.alphaMode != "OPAQUE" && !mat.alphaMode.empty()) {
      warnings.push_back(strCat(where, ": unknown alphaMode '", mat.alphaMode, "': OPAQUE used"));
    }
    out.double_sided = mat.doubleSided;
    for (const auto& [name, value] : mat.extensions) {
      (void)value;
      warnings.push_back(strCat(where, ": extension ", name, " not supported: ignored"));
    }
    c->materials.push_back(out);
  }
}

}  // namespace si::detail
