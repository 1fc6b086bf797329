// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A character's materials as one draw reads them: a table of (base colour factor, texture
/// layer) and every base colour image resized into the layers of one texture array, so parts
/// with different materials and textures share a draw. Built on the CPU (testable without a
/// GPU); the GL back-end uploads it.

#include <cstdint>
#include <vector>

#include "si/core/character.h"

namespace si {

/// One material as the shaders read it.
struct MaterialEntry {
  glm::vec4 base_color_factor = glm::vec4(1.0f);
  uint32_t layer = 0;  ///< Layer of MaterialTable::layers.
};

/// What buildMaterialTable() produces.
struct MaterialTable {
  uint32_t width = 1, height = 1;       ///< Size of every layer.
  std::vector<Image> layers;            ///< One per distinct image used, plus a white layer
                                        ///< when a material has none (alpha 1: tint everywhere).
  std::vector<MaterialEntry> materials; ///< One per Character::materials; one white entry when
                                        ///< the character has none.
  std::vector<uint16_t> vertex_materials;  ///< Per vertex (si::resolvedVertexMaterials()).
  uint32_t resized_images = 0;          ///< Images whose size differed from the layers'.
};

/// Builds the table of `character` (which must be valid). The layer size is the largest width
/// and the largest height of the images its materials use, each capped at `max_size` (0 means
/// 2048); images of another size are resized with resizeImage(). Images no material uses are
/// not uploaded. kInvalidArgument for a null output or a character that does not validate.
Status buildMaterialTable(const Character& character, uint32_t max_size, MaterialTable* out);

/// `in` resized to `width` x `height` (each 1..16384), per axis: where the image shrinks, each
/// destination texel is the area-weighted average of the source texels it covers (a box
/// filter, exact for whole ratios); where it grows, bilinear between texel centres with the
/// edges clamped. Channels are averaged as stored (no sRGB decoding). The same size returns a
/// copy.
Image resizeImage(const Image& in, uint32_t width, uint32_t height);

}  // namespace si
