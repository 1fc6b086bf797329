// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A character's materials as one draw reads them: a table of metallic-roughness entries and
/// their images resized into the layers of two texture arrays, so parts with different
/// materials and textures share a draw. The **colour** layers hold sRGB images (base colour,
/// emissive), the **data** layers linear ones (normal, metallic-roughness, occlusion). Built on
/// the CPU (testable without a GPU); the GL back-end uploads it.

#include <cstdint>
#include <vector>

#include "si/core/character.h"

namespace si {

/// A MaterialEntry layer that is not there: the material has no such texture.
inline constexpr uint32_t kNoLayer = 0xFFFFu;

/// One material as the shaders read it (si::Material, its images as layers).
struct MaterialEntry {
  glm::vec4 base_color_factor = glm::vec4(1.0f);
  uint32_t layer = 0;  ///< Base colour: a colour layer (white where the material has none).
  uint32_t emissive_layer = kNoLayer;            ///< A colour layer.
  uint32_t normal_layer = kNoLayer;              ///< A data layer.
  uint32_t metallic_roughness_layer = kNoLayer;  ///< A data layer.
  uint32_t occlusion_layer = kNoLayer;           ///< A data layer.
  float metallic = 0.0f, roughness = 1.0f, normal_scale = 1.0f, occlusion_strength = 1.0f;
  glm::vec3 emissive_factor = glm::vec3(0.0f);
  /// kMask's cutoff; negative for the other modes (kBlend draws as kOpaque).
  float alpha_cutoff = -1.0f;
  bool double_sided = false;
};

/// What buildMaterialTable() produces.
struct MaterialTable {
  uint32_t width = 1, height = 1;       ///< Size of every colour layer.
  std::vector<Image> layers;            ///< Colour (sRGB): one per distinct base colour or
                                        ///< emissive image used, plus a white layer when a
                                        ///< material has no base colour image (alpha 1: tint
                                        ///< everywhere).
  uint32_t data_width = 1, data_height = 1;  ///< Size of every data layer.
  std::vector<Image> data_layers;       ///< Data (linear): one per distinct normal,
                                        ///< metallic-roughness or occlusion image used; empty
                                        ///< when no material has one.
  std::vector<MaterialEntry> materials; ///< One per Character::materials; one white entry when
                                        ///< the character has none.
  std::vector<uint16_t> vertex_materials;  ///< Per vertex (si::resolvedVertexMaterials()).
  uint32_t resized_images = 0;          ///< Images whose size differed from their layers'.
};

/// Builds the table of `character` (which must be valid). Each array's layer size is the
/// largest width and the largest height of the images in it, each capped at `max_size` (0
/// means 2048); images of another size are resized with resizeImage(). An image used both as
/// colour and as data is in both arrays; images no material uses are in neither.
/// kInvalidArgument for a null output or a character that does not validate.
Status buildMaterialTable(const Character& character, uint32_t max_size, MaterialTable* out);

/// `in` resized to `width` x `height` (each 1..16384), per axis: where the image shrinks, each
/// destination texel is the area-weighted average of the source texels it covers (a box
/// filter, exact for whole ratios); where it grows, bilinear between texel centres with the
/// edges clamped. Channels are averaged as stored (no sRGB decoding). The same size returns a
/// copy.
Image resizeImage(const Image& in, uint32_t width, uint32_t height);

}  // namespace si
