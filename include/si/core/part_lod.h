// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Per-part LOD: at each of the character's LOD levels, every sub-mesh draws the coarsest of its
/// own levels whose error stays within that level's error (the error the crowd's LOD choice
/// accepted for the whole character), and a part that lies close to the parts that are always
/// kept (a helmet on the head, a shield on the arm) is not drawn at all once dropping it is
/// within that error. A helmet a fraction of a pixel wide then stops costing triangles while the
/// body still needs its level. The result is an ordinary mesh: each sub-mesh's chain rewritten
/// to the character's levels, dropped levels empty, so the crowd, every draw path and the CPU
/// emulation need nothing else; the character's error per level (lodErrorsByLevel) is unchanged.
///
/// Usage (after the chain and its errors, before uploading the character):
/// \code
///   si::buildLodChain(&character.mesh, {}, nullptr);
///   si::measureAnimatedLodErrors(&character, {});
///   si::PartLodReport report;
///   si::Status s = si::buildPartLods(&character, {}, &report);
///   // CrowdDesc::lod_count = character.mesh.maxLodCount(), lod_errors_units from
///   // si::lodErrorsByLevel(character.mesh, ...), as without per-part LOD.
/// \endcode

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/character.h"
#include "si/core/lod_error.h"
#include "si/core/status.h"

namespace si {

/// Options of buildPartLods().
struct PartLodDesc {
  /// Sub-meshes never dropped (bit s: sub-mesh s). Their LOD 0 surface is what a dropped part is
  /// measured against. 0 means the sub-mesh whose bind-pose LOD 0 has the largest bounding box.
  uint32_t keep_mask = 0;
  /// Whether parts outside keep_mask may be dropped; false only picks each part's own level.
  bool drop = true;
  /// The poses a dropped part's distance is measured over (as measureAnimatedLodErrors()).
  AnimatedLodErrorDesc poses;
};

/// What buildPartLods() did.
struct PartLodReport {
  struct Part {
    std::string name;
    bool kept = false;  ///< In keep_mask: never dropped.
    /// How far the part may lie from the kept parts' LOD 0 surface over the rest pose and the
    /// sampled poses (model units): the error of not drawing it. Negative when not measured
    /// (kept, drop off, or dropped by an earlier call).
    float drop_error_units = -1.0f;
    /// Per character level: the part's own level drawn there (an index into its chain before
    /// the call), or -1 where it is not drawn.
    std::vector<int> level_of;
  };
  std::vector<Part> parts;
  std::vector<float> level_errors_units;  ///< The character's error per level (lodErrorsByLevel).
  /// Triangles of all sub-meshes per character level, before and after; the longer chain sets
  /// the length of both (a mesh past its last level draws its last).
  std::vector<uint64_t> triangles_before, triangles_after;
};

/// Rewrites every sub-mesh's LOD chain so that character level l draws, of each part, the
/// coarsest of its own levels whose error is at most E(l), the character's error at l (the
/// largest error of any part there, non-decreasing: lodErrorsByLevel()). With `desc.drop`, each
/// part outside `keep_mask` first gets one more level, empty, whose error is the largest distance
/// from its LOD 0 (vertices and triangle centroids, skinned in the rest pose and desc.poses'
/// poses of the character's clips) to the kept parts' LOD 0 surface. That level counts as one
/// past the character's last, so the character's error at its existing levels is unchanged; a
/// part is dropped at the first level whose error covers its drop, and where no level does,
/// the character gains one more level (body and the rest at their last, such parts dropped)
/// when it has fewer than 8. A dropped part changes the character's surface by its drop error
/// against the kept parts' LOD 0; with the kept parts at level l the change is at most that
/// plus their error at l. A part already dropped (an empty level, from an earlier call) is not
/// measured again, so calling twice changes nothing.
/// Errors are required (measureLodErrors(), buildLodChain() or measureAnimatedLodErrors() first).
/// Fails, leaving the character untouched, with kInvalidArgument for a null character, missing
/// errors, or a keep_mask naming no sub-mesh or one past the mesh's; with SkinnedMesh::validate()'s
/// and the evaluator's status for an invalid character. `report` may be null.
Status buildPartLods(Character* character, const PartLodDesc& desc, PartLodReport* report);

}  // namespace si
