// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Everything the library needs of one character type: skeleton, skinned mesh, clips, materials.

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

/// The basics of a material. The base color texture's alpha is the tint mask: where it is 1 the
/// instance's tint color multiplies the texel, where it is 0 the texel is kept.
struct Material {
  std::string name;
  glm::vec4 base_color_factor = glm::vec4(1.0f);
  int32_t base_color_image = -1;  ///< Index into Character::images, or -1 for none.
};

/// A character type that many instances share.
struct Character {
  std::string name;
  Skeleton skeleton;
  SkinnedMesh mesh;
  std::vector<Clip> clips;
  std::vector<Material> materials;
  std::vector<Image> images;

  /// Validates the skeleton, the mesh against it, every clip against it (and the root motion
  /// joint of each that extracts it: kNotFound), every image; checks
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
