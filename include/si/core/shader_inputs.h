// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The CPU side of the shipped GLSL skinning interface (si_skinning.glsl, documented in
/// docs/glsl-interface.md): the interleaved vertex stream its skinning reads and the value of
/// its `si_palette_info` uniform. Plain data, no GL: an engine that draws with its own renderer
/// (any API) uploads these as they are. si::Renderer uses the same functions.
///
/// Usage:
/// \code
///   si::VertexStream stream;
///   si::Status s = si::buildVertexStream(character.mesh, palette, &stream);
///   // Upload stream.bytes as one vertex buffer (stride stream.stride_bytes) with the
///   // attributes at the offsets below, and the mesh's indices as the index buffer.
///   const glm::uvec4 info = si::paletteShaderInfo(palette);  // -> si_palette_info
/// \endcode

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "si/core/baked_palette.h"
#include "si/core/skinned_mesh.h"
#include "si/core/status.h"

namespace si {

/// One vertex buffer of interleaved vertices, 32 bytes each (36 with wide joints; 12 more, 16
/// with wide joints, with a second set of influences; then 4 more each with tangents, a second
/// texture coordinate set, vertex colours and morph targets, in that order):
///
/// | offset | attribute (location) | format |
/// | --- | --- | --- |
/// | 0 | position (0) | 3 x float32, bind-pose model space, not quantized |
/// | 12 | normal (1) | 10:10:10:2 signed normalized (GL_INT_2_10_10_10_REV), w unused |
/// | 16 | texcoord (2) | 2 x float16 (0 when the mesh has none) |
/// | 20 | joints (3) | 4 x uint8 palette slots; 4 x uint16 when wide_joints |
/// | 24 (28) | weights (4) | 4 x unorm16 summing to exactly 65535 (si::quantizeWeights) |
/// | 32 (36) | joints 5-8 (10) | as joints; only when the mesh has `joints1` |
/// | next | weights 5-8 (11) | 4 x unorm16; the 8 weights together sum to exactly 65535 |
/// | next | tangent (7) | 10:10:10:2 signed normalized: xyz the unit tangent, w +-1; only when
/// the mesh has tangents | | next | texcoord 1 (8) | 2 x float16; only when the mesh has
/// `texcoords1` | | next | colour (9) | 4 x unorm8, linear RGBA; only when the mesh has `colors` |
/// | next | morph (12) | uint32: the vertex's run of MorphStream entries, first entry << 9 |
/// count (0 to 256); only when the mesh has morph targets |
///
/// Joints are palette slots (BakedPalette::skeleton_to_palette applied), not skeleton joints;
/// a zero weight's joint is 0. Wide joints are used when the palette stores more than 256.
struct VertexStream {
  static constexpr uint32_t kPositionOffset = 0;
  static constexpr uint32_t kNormalOffset = 12;
  static constexpr uint32_t kTexcoordOffset = 16;
  static constexpr uint32_t kJointsOffset = 20;

  std::vector<uint8_t> bytes;   ///< vertex_count * stride_bytes bytes.
  uint32_t vertex_count = 0;
  uint32_t stride_bytes = 0;    ///< 32, or 36 with wide joints; 4 more for each optional word.
  bool wide_joints = false;     ///< Joints as 4 x uint16.
  uint32_t weights_offset = 0;  ///< 24, or 28 with wide joints.
  /// After the fixed words and the second set when the mesh has tangents; 0 without. Without
  /// tangents the renderer feeds attribute 7 the normal's word, whose w is 0: "no tangent frame".
  uint32_t tangent_offset = 0;
  /// The second texture coordinate set's word when the mesh has `texcoords1`; 0 without.
  uint32_t texcoord1_offset = 0;
  /// The colour's word when the mesh has `colors`; 0 without.
  uint32_t color_offset = 0;
  /// Influences 5 to 8 (joints, then weights) when the mesh has `joints1`; 0 without.
  uint32_t joints1_offset = 0;
  uint32_t weights1_offset = 0;
  /// The morph word (the vertex's run of MorphStream entries) when the mesh has morph targets;
  /// 0 without.
  uint32_t morph_offset = 0;
};

/// Most MorphStream entries a mesh may have: the morph word's 23 bits of first entry.
inline constexpr uint32_t kMaxMorphEntries = (1u << 23) - 1u;

/// A mesh's morph targets as the shaders read them (SI_MORPH_TARGETS, docs/glsl-interface.md):
/// a 2D RGBA32UI texture of entries, grouped by vertex (the vertex stream's morph word names a
/// vertex's run), each run ordered by effect, largest first. Entry e starts at texel
/// e * texels_per_entry: (word, position delta x, y, z as float bits), then with normal deltas
/// (x, y, z, 0), then with tangent deltas (x, y, z, 0). The word holds the target in bits 0 to
/// 15 and, in bits 16 to 31 as a float's upper bits (rounded up), the entry's tail: how far the
/// entries from it to the end of the run can move the vertex at most, in model units (each
/// entry's |position delta| times the largest |weight| the palette gives its target, summed).
/// A LOD level stops its run at the first entry whose tail is within the level's cut
/// (morphLodCuts()). Texels are numbered row by row, as the palette's.
struct MorphStream {
  std::vector<uint32_t> texels;  ///< width * height texels of 4 words.
  uint32_t width = 0;            ///< A power of two.
  uint32_t width_log2 = 0;
  uint32_t height = 0;
  uint32_t texels_per_entry = 0;  ///< 1 (positions), 2 (and normals) or 3 (and tangents).
  uint32_t entry_count = 0;
};

/// Builds the morph stream of `mesh` (which has morph targets) for `palette` (baked with them:
/// layout.morph_target_count equal to the mesh's count, kInvalidArgument otherwise), its texture
/// at most `max_texture_size` texels a side (0: 16384). Fails, leaving `out` untouched, with
/// kInvalidArgument for a null `out` or a mesh without targets, the codes of
/// SkinnedMesh::validate(), and kLimitExceeded past kMaxMorphEntries entries or the texture
/// size.
Status buildMorphStream(const SkinnedMesh& mesh, const BakedPalette& palette,
                        uint32_t max_texture_size, MorphStream* out);

/// LOD levels a character may have (CrowdDesc::lod_count), each with its morph cut.
inline constexpr size_t kMorphLodCuts = 8;

/// The include's `si_morph_cuts` (SiPaletteInfo's last two members with SI_MORPH_TARGETS, the
/// levels in order): per LOD level, how far the morph targets it leaves out may move a vertex,
/// in model units: `share` times the level's geometric error (lodErrorsByLevel(); levels past
/// the mesh's take its coarsest; all 0, every target kept, where a sub-mesh's errors are not
/// measured). LOD 0's error is 0, so it keeps every target; at a coarser
/// level the error on screen grows by at most `share` of the level's (si::RendererDesc::
/// morph_lod_share). kInvalidArgument for a null `out` or a share outside [0, 1]; fails as
/// lodErrorsByLevel() does. Nothing is written on failure.
Status morphLodCuts(const SkinnedMesh& mesh, float share, std::array<float, kMorphLodCuts>* out);

/// The value of the include's `si_morph_info` (SiPaletteInfo's second member with
/// SI_MORPH_TARGETS): x log2 of the morph texture's width, y texels per entry, z where a frame's
/// morph weights start in the palette (PaletteLayout::morph_first_texel), w the target count.
glm::uvec4 morphShaderInfo(const BakedPalette& palette, const MorphStream& stream);

/// Builds the vertex stream of `mesh` for `palette` (the palette baked for the mesh's
/// skeleton). Fails, leaving `out` untouched, with kInvalidArgument when `out` is null, when
/// the mesh is invalid for a skeleton of the palette's joint count (see
/// SkinnedMesh::validate()), or naming the first vertex weighted to a joint the palette does not
/// store.
Status buildVertexStream(const SkinnedMesh& mesh, const BakedPalette& palette, VertexStream* out);

/// The value of the include's `uniform uvec4 si_palette_info`: x log2 of the palette texture's
/// width, y joint stride in texels, z 0 for the 3x4 matrix formats and 1 for quaternion +
/// translation, w 0.
glm::uvec4 paletteShaderInfo(const BakedPalette& palette);

/// A unit normal packed as GL_INT_2_10_10_10_REV (x, y, z signed normalized to 511; w 0), as
/// the vertex stream stores it.
uint32_t packNormal10(const glm::vec3& normal);
/// A tangent packed as the vertex stream stores it: xyz as packNormal10(), w's sign in the
/// 2-bit field (1 or -1).
uint32_t packTangent10(const glm::vec4& tangent);
/// A colour packed as the vertex stream stores it: 4 x unorm8 (R in the low byte), each
/// channel clamped to [0, 1] and rounded to the nearest of 255 steps.
uint32_t packColor8(const glm::vec4& color);

}  // namespace si
