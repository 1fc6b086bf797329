// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// LOD chains deep enough for a character a few pixels tall: each sub-mesh's LOD 0 simplified
/// (meshoptimizer: edge collapse, then sloppy clustering where collapse stalls) into coarser
/// levels down to a few dozen triangles, each with its geometric error in model units (the
/// simplifier's relative error scaled back by the mesh's extent, or the measured surface
/// distance when that is larger). Vertices are kept, so skin weights need nothing; only index
/// ranges are added.
///
/// Usage:
/// \code
///   si::LodChainReport report;
///   si::Status s = si::buildLodChain(&character.mesh, {}, &report);  // 6 levels, >= 24 tris
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/skinned_mesh.h"
#include "si/core/status.h"

namespace si {

/// Options of buildLodChain(). Zero fields take the defaults documented on each.
struct LodChainDesc {
  /// Levels per sub-mesh, LOD 0 included, 2 to 8; 0 means 6.
  uint32_t level_count = 0;
  /// Each new level aims at this fraction of the previous level's triangles; 0 means 0.3.
  float triangle_ratio = 0.0f;
  /// The coarsest level aims at this many triangles: no level aims lower, and a sub-mesh whose
  /// last level has at most this many gets no more; 0 means 24.
  uint32_t min_triangles = 0;
  /// Keep the levels a sub-mesh already has (from a file, or procedural) and add after them;
  /// false replaces every level but LOD 0.
  bool keep_existing = true;
};

/// Returns the desc with zeros replaced by their documented defaults.
LodChainDesc resolveDefaults(const LodChainDesc& desc);

/// One level of one sub-mesh.
struct LodLevelReport {
  uint32_t sub_mesh = 0, level = 0;
  uint32_t triangles = 0;
  float error_units = 0.0f;       ///< What the level carries (SubMesh::lod_error_units).
  float simplifier_error_units = 0.0f;  ///< Generated levels: the simplifier's own estimate.
  bool generated = false;  ///< Made by this call (else kept).
  bool sloppy = false;     ///< By clustering (meshopt_simplifySloppy), not edge collapse.
};

struct LodChainReport {
  std::vector<LodLevelReport> levels;  ///< Sub-mesh by sub-mesh, level by level.
};

/// Extends (or rebuilds) every sub-mesh's LOD chain to `desc.level_count` levels: level k is
/// LOD 0 simplified to max(min_triangles, previous level x triangle_ratio) triangles; its error
/// is the larger of the simplifier's estimate and the measured bind-pose surface distance to
/// LOD 0 (surfaceDistance: the estimate alone can be several times too small), and never less
/// than the previous level's, so errors grow along the chain; a
/// sub-mesh stops early once its last level has at most min_triangles, or when the simplifier
/// cannot make a smaller one. Errors of the levels it keeps are measured when missing
/// (measureLodErrors). Fails, leaving the mesh untouched, with kInvalidArgument for a null mesh,
/// a level count outside 2..8, a ratio outside (0, 1), and SkinnedMesh::validate()'s status for
/// an invalid mesh. `report` may be null.
Status buildLodChain(SkinnedMesh* mesh, const LodChainDesc& desc, LodChainReport* report);

}  // namespace si
