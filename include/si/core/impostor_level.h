// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The impostor level of a mesh: one LOD level past the last that draws none of the mesh, where
/// the renderer draws the character's animated impostor instead (si::Renderer::buildImpostor,
/// CrowdDesc::impostor_lod). Appending it keeps every existing level as it is.
///
/// \code
///   si::appendImpostorLevel(&character.mesh);              // level L = maxLodCount() - 1
///   crowd_desc.lod_count = uint32_t(character.mesh.maxLodCount());
///   crowd_desc.impostor_lod = crowd_desc.lod_count - 1;
/// \endcode

#include "si/core/skinned_mesh.h"
#include "si/core/status.h"

namespace si {

/// Most LOD levels a mesh may have with its impostor level (the crowd's limit, CrowdDesc).
inline constexpr size_t kMaxImpostorMeshLods = 8;

/// Pads every sub-mesh of `mesh` to maxLodCount() levels (its last range and error repeated: a
/// sub-mesh past its last level draws that level anyway) and appends one empty level to each:
/// the impostor level, index maxLodCount() - 1 afterwards. Its lod_error_units entry (where the
/// sub-mesh has errors) repeats the last level's: the impostor's own error is measured in image
/// space (si::measureImageLodErrors) and given to the crowd in CrowdDesc::lod_errors_units.
/// kInvalidArgument for a null mesh or one without sub-meshes or LOD 0; kLimitExceeded when it
/// already has kMaxImpostorMeshLods levels. Nothing is changed on failure.
Status appendImpostorLevel(SkinnedMesh* mesh);

}  // namespace si
