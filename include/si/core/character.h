// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Everything the library needs of one character type: skeleton, skinned mesh, clips, materials.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "si/core/bounds.h"
#include "si/core/clip.h"
#include "si/core/skeleton.h"
#include "si/core/skinned_mesh.h"

namespace si {

/// An RGBA8 image, rows top to bottom, 4 bytes per texel.
struct Image {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba8;

  /// Width and height in 1..16384 (kOutOfRange) and rgba8 holding width * height * 4 bytes
  /// (kCountMismatch).
  Status validate() const;
};

/// How a material's base colour alpha is read (glTF 2.0 `alphaMode`).
enum class AlphaMode : uint8_t {
  /// Alpha is not coverage: the base colour texture's alpha is the tint mask (1 takes the
  /// instance's tint colour, 0 keeps the texel).
  kOpaque = 0,
  /// Alpha is coverage: a fragment whose base colour alpha (texture times factor) is below
  /// Material::alpha_cutoff is discarded, in colour, depth-only and impostor capture draws;
  /// the tint applies everywhere.
  kMask,
  /// glTF's blended transparency. The crowd draws opaque (it sorts nothing): kept so the
  /// import can say so, drawn as kOpaque.
  kBlend,
};

/// A glTF 2.0 metallic-roughness material: what the built-in material (docs/rendering.md,
/// "Materials") shades with and what a host material reads through SiSurface. Image indices
/// point into Character::images (-1: none). The member defaults describe a rough dielectric
/// (metallic 0, roughness 1, no textures); the glTF import takes the file's values with
/// glTF's own defaults (metallic 1, roughness 1).
struct Material {
  std::string name;
  glm::vec4 base_color_factor = glm::vec4(1.0f);  ///< Linear RGBA.
  int32_t base_color_image = -1;  ///< sRGB colour; its alpha as alpha_mode says.
  float metallic_factor = 0.0f;   ///< 0..1.
  float roughness_factor = 1.0f;  ///< 0..1 (perceptual roughness).
  /// Linear: green roughness, blue metallic (multiplying the factors).
  int32_t metallic_roughness_image = -1;
  /// Linear tangent-space normal (rgb * 2 - 1), scaled in x and y by normal_scale. Needs the
  /// mesh's tangents (si::generateTangents makes them where a file has none).
  int32_t normal_image = -1;
  float normal_scale = 1.0f;      ///< Finite.
  int32_t occlusion_image = -1;   ///< Linear, red channel.
  float occlusion_strength = 1.0f;  ///< 0..1: 1 + strength * (red - 1).
  glm::vec3 emissive_factor = glm::vec3(0.0f);  ///< Linear, >= 0.
  int32_t emissive_image = -1;    ///< sRGB colour, multiplying emissive_factor.
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;      ///< kMask: >= 0.
  /// Back faces drawn (their normal flipped) instead of culled.
  bool double_sided = false;
};

/// Every image index of `m`, in a fixed order (base colour, metallic-roughness, normal,
/// occlusion, emissive); -1 where it has none.
std::array<int32_t, 5> materialImages(const Material& m);

/// A character type that many instances share.
struct Character {
  std::string name;
  Skeleton skeleton;
  SkinnedMesh mesh;
  std::vector<Clip> clips;
  std::vector<Material> materials;
  std::vector<Image> images;

  /// Validates the skeleton, the mesh against it, every clip against both (its morph tracks
  /// within the mesh's morph targets; the root motion joint of each that extracts it:
  /// kNotFound), every image; checks
  /// that sub-mesh material indices are below materials.size() (when there are materials) and
  /// image indices below images.size() (kOutOfRange). Reports the first failure.
  Status validate() const;

  /// Index of the first clip named `name`, or -1.
  int32_t findClip(const std::string& name) const;

  /// Bounds of the bind-pose mesh (all vertices).
  Aabb bindPoseBounds() const;
  /// The character's height: the largest extent of the bind-pose bounds, the unit in which
  /// accuracy is reported as a fraction.
  float height() const;
};

}  // namespace si
