// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's character: the embedded one with its LOD chain, the error of each level over
// the clips' poses, optionally per-part LOD, and each level's image error; each printed.
#include <cstdint>
#include <string>

#include "crowd_bench/bench_scene.h"
#include "si/gl/impostor.h"
#include "si/gl/renderer.h"

namespace si::bench {

/// How the bench's character is made (its command-line options).
struct CharacterChoice {
  std::string lod_chain = "deep";  ///< deep: si::buildLodChain's levels; technique: the 3 embedded.
  uint32_t lod_min_triangles = 0;  ///< LodChainDesc::min_triangles; 0: the library's default.
  bool part_lod = false;           ///< si::buildPartLods (each part its own level, parts dropped).
  bool impostor = false;           ///< si::appendImpostorLevel: the last level is the impostor.
  /// --impostor-atlas: full (ImpostorDesc's defaults), small (8 azimuths, 2 elevations, 4
  /// frames) or fine (the defaults with 32 azimuths).
  std::string atlas = "full";
  uint32_t capture_supersample = 0;  ///< --impostor-capture: ImpostorDesc::capture_supersample.
  uint32_t cell_pixels = 0;          ///< --impostor-cell: ImpostorDesc::cell_pixels.
  float lod_bias = 0.0f;             ///< --impostor-bias: ImpostorDesc::lod_bias.
  /// --vertex-colors: every vertex a colour (white to mid grey by height) and texture
  /// coordinates 1, which the built-in material multiplies into the base colour.
  bool vertex_colors = false;
  /// --eight-influences: each vertex's weights split 3:1 over the same joints in two sets
  /// (SkinnedMesh::joints1/weights1): the same skinning, drawn through 8 influences.
  bool eight_influences = false;
  /// --morph-targets N: N face-like morph targets on the head, every clip animating their
  /// weights (examples/common/face_targets.h).
  uint32_t morph_targets = 0;
};

/// The embedded character with its LOD chain (deep: 6 levels down to a few dozen triangles),
/// and the error of each level (setup->lod_errors); prints triangles and error per level, and
/// with per-part LOD each part's level per character level and its drop error.
Status makeCharacter(const CharacterChoice& choice, Setup* setup);

/// Measures the image error of each LOD level (si::measureImageLodErrors), prints it beside the
/// geometric error and, with `select`, makes it what the screen-error mode selects by
/// (setup.lod_errors). Every level is measured between the impostor atlas's captured views and
/// frames (half an azimuth step, half a pose step), with an impostor level or without; with one
/// (setup.impostor), it is drawn as the impostor (setup.impostor_desc), and its image error is
/// where it takes over in setup.lod_errors (si::impostorLodErrorsUnits at `budget_pixels`, the
/// screen-error budget, or imageLodErrorsUnits with `select`). With `quick` (--quick, the
/// sanitizer smoke run): 3 heights up to 16 px (a sixteenth of the pixels), every pose and view
/// direction: with 2 poses and 4 views the hand-over differed between GPUs (docs/crowd.md).
Status imageErrors(Setup& setup, const BakedPalette& palette, bool select, bool quick,
                   float budget_pixels);

/// Builds character `id`'s impostor atlas (setup.impostor_desc) and, with `print`, prints its
/// size.
Status buildImpostor(const Setup& setup, Renderer& renderer, CharacterId id, bool print = true);
/// buildImpostor() without printing when the setup has an impostor level; nothing otherwise.
inline Status addImpostor(const Setup& setup, Renderer& renderer, CharacterId id) {
  return setup.impostor ? buildImpostor(setup, renderer, id, false) : Status::ok();
}
/// `renderer` initialized with `desc` for the bench's character (character 0, with `palette`)
/// and its impostor atlas (addImpostor).
inline Status initRenderer(const Setup& setup, const BakedPalette& palette,
                           const RendererDesc& desc, Renderer* renderer) {
  Status s = renderer->init(setup.info, desc);
  CharacterId id;
  if (s.isOk()) s = renderer->addCharacter(setup.character, palette, &id);
  if (s.isOk()) s = addImpostor(setup, *renderer, id);
  return s;
}

}  // namespace si::bench
