// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Materials (glTF 2.0 specification, "Materials"): base colour factor and texture; images
// converted to RGBA8. Index 0 is a default white material for primitives without one.
#include <algorithm>
#include <map>

#include "gltf/gltf_convert.h"

namespace si::detail {

void convertMaterials(const tinygltf::Model& m, GltfImportReport* report, Character* c) {
  std::vector<std::string>& warnings = report->warnings;
  // ---- Materials (index 0 is a default white one for primitives without a material).
  c->materials.push_back(Material{"default", glm::vec4(1.0f), -1});
  std::map<int, int32_t> image_map;
  for (size_t i = 0; i < m.materials.size(); ++i) {
    const tinygltf::Material& mat = m.materials[i];
    Material out_mat;
    out_mat.name = mat.name;
    const auto& f = mat.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4) out_mat.base_color_factor = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
    const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
    if (tex >= 0 && size_t(tex) < m.textures.size()) {
      const int src = m.textures[size_t(tex)].source;
      if (src >= 0 && size_t(src) < m.images.size() && !m.images[size_t(src)].image.empty()) {
        if (!image_map.count(src)) {
          const tinygltf::Image& im = m.images[size_t(src)];
          Image out_image;
          out_image.width = uint32_t(std::max(im.width, 0));
          out_image.height = uint32_t(std::max(im.height, 0));
          const int comps = im.component, bytes = im.bits / 8;
          const uint64_t texels = uint64_t(out_image.width) * out_image.height;
          if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
              im.image.size() != texels * uint64_t(comps) * uint64_t(bytes)) {
            warnings.push_back(strCat("image ", src, ": unexpected layout: skipped"));
          } else {
            out_image.rgba8.resize(size_t(texels) * 4);
            for (uint64_t t = 0; t < texels; ++t)
              for (int ch = 0; ch < 4; ++ch) {
                uint8_t v = ch == 3 ? 255 : 0;
                const int from = comps >= 3 ? ch : (ch < 3 ? 0 : 1);
                if (from < comps && (ch < 3 || comps == 4 || comps == 2))
                  v = im.image[size_t((t * uint64_t(comps) + uint64_t(from)) * uint64_t(bytes) + uint64_t(bytes - 1))];
                out_image.rgba8[size_t(t * 4 + uint64_t(ch))] = v;
              }
            image_map[src] = int32_t(c->images.size());
            c->images.push_back(std::move(out_image));
          }
        }
        if (image_map.count(src)) out_mat.base_color_image = image_map[src];
      }
    }
    c->materials.push_back(out_mat);
  }
}

}  // namespace si::detail
