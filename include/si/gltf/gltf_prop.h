// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A prop (si/core/prop.h) from any glTF 2.0 file: every triangle primitive of the scene's
/// nodes, placed by their node transforms, with its materials and base colour images, as one
/// rigid mesh to attach at a socket. Meshes of skinned nodes are taken in their bind pose (the
/// positions as stored; glTF ignores a skinned node's own transform), so a character's file
/// works too.
///
/// Usage:
/// \code
///   si::PropMesh torch;
///   si::GltfImportReport report;
///   si::Status s = si::importGltfPropFile("props/torch.glb", {}, &torch, &report);
///   if (s.isOk()) s = si::attachProp(grip, torch, &character, &torch_bit);
/// \endcode

#include <string>

#include "si/core/prop.h"
#include "si/core/span.h"
#include "si/gltf/gltf_import.h"

namespace si {

/// Options of the prop import.
struct GltfPropDesc {
  /// The prop's name (its sub-mesh's once attached); empty: the first mesh's name (or "prop").
  std::string name;
  /// Decode base colour images (as GltfImportDesc::load_images).
  bool load_images = true;
  /// Multiplies every position: a file authored in other units (0.01 for centimetres).
  float scale = 1.0f;
};

/// Imports the triangle primitives of the default scene's nodes (every root node when the file
/// has no scene) into `out`, each transformed by its node's world matrix (normals by its
/// inverse transpose; a mirroring matrix reverses the triangles' winding), its material (index
/// 0 a default white, then the file's) and images. Lines, points and primitives without
/// vertices are skipped with a warning in `report` (may be null), as are morph targets.
/// Fails with `out` untouched: kInvalidArgument for a null `out` or a scale that is not finite
/// and positive; kIo, kCorrupt (naming the accessor, node or primitive; a node hierarchy with a
/// cycle), kLimitExceeded as importGltfFile(); kUnsupported for a file without a triangle.
/// The result passes PropMesh::validate().
Status importGltfPropFile(const std::string& path, const GltfPropDesc& desc, PropMesh* out,
                          GltfImportReport* report);

/// The same from memory: a .glb or .gltf JSON; `base_dir` resolves external URIs (empty: they
/// are refused).
Status importGltfPropMemory(Span<const uint8_t> bytes, const std::string& base_dir,
                            const GltfPropDesc& desc, PropMesh* out, GltfImportReport* report);

}  // namespace si
