// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Sockets and props: a rigid mesh from another asset (a sword, a torch, a flag) held at a named
/// place on a character's skeleton. A socket is a joint plus an offset; attachProp() appends the
/// prop to the character as a sub-mesh of its own, every vertex weighted 1 to the socket's
/// joint and placed where the socket sits in the bind pose. The prop is then a part like any
/// other: an instance shows it or not with its variation mask (InstanceDesc::variation_mask,
/// CrowdManager::setVariationMask), one prop of a hand per bit, and every path draws it in the
/// exact pose drawn for the body (frame interpolation, crossfade, overlays, animation-LOD
/// stepping, motion vectors, depth-only), in the same draw as the character's other parts.
/// CrowdManager::socketTransform gives the same frame on the CPU (spawning effects, physics).
///
/// Usage:
/// \code
///   si::Socket grip;
///   si::makeSocket(character.skeleton, "right grip", "r_hand", offset, &grip);
///   uint32_t torch_bit = 0;
///   si::attachProp(grip, torch_mesh, &character, &torch_bit);  // Before baking the palette.
///   si::buildLodChain(&character.mesh, {}, nullptr);           // Coarser levels for the prop.
///   // ... bake, add to a renderer; instances holding the torch set bit `torch_bit`.
/// \endcode
///
/// Attach before baking: the palette stores the joints vertices are weighted to, so a joint
/// that only the prop uses (a grip joint) must be weighted when the palette is baked; a renderer
/// refuses a mesh whose joints its palette does not store.

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/character.h"
#include "si/core/status.h"

namespace si {

/// A named frame on a skeleton: joint `joint` and where the socket sits relative to it.
struct Socket {
  std::string name;
  uint32_t joint = 0;  ///< Skeleton joint the socket follows.
  /// The socket's frame in model space in the bind pose: the joint's bind matrix (the inverse
  /// of its inverse bind matrix) times the offset makeSocket() was given. An animated pose maps
  /// it with the joint's skinning matrix: world = instance * skinning(joint) * bind_frame.
  glm::mat4 bind_frame = glm::mat4(1.0f);
};

/// The socket named `name` on the joint named `joint_name`, at `offset` in the joint's own
/// frame (affine: last row 0 0 0 1; translations in model units, the joint's axes). Fails with
/// kInvalidArgument for a null `out`, an empty name, an offset that is not affine or not
/// invertible; kNotFinite for a non-finite offset; kNotFound for an unknown joint,
/// kAmbiguous when several joints have that name. Nothing is written on failure.
Status makeSocket(const Skeleton& skeleton, const std::string& name, const std::string& joint_name,
                  const glm::mat4& offset, Socket* out);

/// A rigid triangle mesh with its materials, in its own frame (the socket's frame once
/// attached). Per-vertex arrays: `positions` defines the count; `normals` must match it;
/// `texcoords`, `texcoords1`, `colors`, `tangents` and `vertex_materials` are empty or match it.
struct PropMesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;    ///< Unit length.
  std::vector<glm::vec4> tangents;   ///< Optional; xyz unit, w = +-1.
  std::vector<glm::vec2> texcoords;  ///< Optional.
  std::vector<glm::vec2> texcoords1;  ///< Optional: SkinnedMesh::texcoords1.
  std::vector<glm::vec4> colors;      ///< Optional: SkinnedMesh::colors (linear, in [0, 1]).
  /// Optional: each vertex's material, an index into `materials`. Empty: material 0.
  std::vector<uint16_t> vertex_materials;
  std::vector<uint32_t> indices;  ///< Triangle list.
  /// Empty: the prop is plain white (attachProp adds one material named after it).
  std::vector<Material> materials;
  std::vector<Image> images;  ///< Base colour images the materials name.

  /// Checks the rules above, naming the array and element: a name, at least one triangle
  /// (kInvalidArgument), counts (kCountMismatch), finite attributes (kNotFinite), colours in
  /// [0, 1], indices below the vertex count, vertex materials below the material count, image
  /// indices below the image count (kOutOfRange), each image valid (Image::validate).
  Status validate() const;
};

/// Appends `prop` to `character` at `socket` as a new sub-mesh named after the prop (LOD 0
/// only: si::buildLodChain, keeping existing levels, adds coarser ones; at coarser LODs of the
/// character the prop draws its last level) and gives its index, the prop's bit in the
/// variation mask, in `sub_mesh` (may be null). Vertices are placed by the socket's
/// bind_frame (normals by its inverse transpose; a mirroring frame reverses the triangles'
/// winding so their fronts stay outside) and weighted 1 to the socket's joint. The prop's
/// materials and images follow the character's (vertex materials renumbered). Texture
/// coordinates (either set) that only one side has are zero on the other side's vertices, and
/// colours that only one side has are white (1, 1, 1, 1) on the other's; tangents follow
/// the character: kept (transformed, their sign flipped by a mirroring frame) when it has
/// them, with vertices of a prop without tangents given one perpendicular to their normal, and
/// dropped when it has none.
/// Fails, leaving `character` untouched, with kInvalidArgument for a null character, a prop
/// that fails validate() (its status), a socket frame that is not finite or invertible, or a
/// sub-mesh of the prop's name already there; kOutOfRange for a socket joint past the
/// skeleton; kLimitExceeded when the mesh has SkinnedMesh::kMaxSubMeshes sub-meshes already or
/// its vertex count or materials would pass 32 or 16 bits.
Status attachProp(const Socket& socket, const PropMesh& prop, Character* character,
                  uint32_t* sub_mesh);

}  // namespace si
