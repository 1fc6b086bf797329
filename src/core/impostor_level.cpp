// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor level: every sub-mesh padded to the mesh's levels, then one empty level.
#include "si/core/impostor_level.h"

#include "core/str_cat.h"

namespace si {

Status appendImpostorLevel(SkinnedMesh* mesh) {
  if (mesh == nullptr) return {StatusCode::kInvalidArgument, "appendImpostorLevel: mesh is null"};
  if (mesh->sub_meshes.empty())
    return {StatusCode::kInvalidArgument, "appendImpostorLevel: the mesh has no sub-meshes"};
  for (size_t s = 0; s < mesh->sub_meshes.size(); ++s)
    if (mesh->sub_meshes[s].lods.empty())
      return {StatusCode::kInvalidArgument,
              detail::strCat("appendImpostorLevel: sub-mesh ", s, " has no LOD 0")};
  const size_t levels = mesh->maxLodCount();
  if (levels >= kMaxImpostorMeshLods)
    return {StatusCode::kLimitExceeded,
            detail::strCat("appendImpostorLevel: the mesh has ", levels,
                           " levels; with the impostor's it would pass ", kMaxImpostorMeshLods)};
  for (SubMesh& sub : mesh->sub_meshes) {
    const bool errors = !sub.lod_error_units.empty();
    while (sub.lods.size() < levels) {
      sub.lods.push_back(sub.lods.back());
      if (errors) sub.lod_error_units.push_back(sub.lod_error_units.back());
    }
    sub.lods.push_back(IndexRange{});
    if (errors) sub.lod_error_units.push_back(sub.lod_error_units.back());
  }
  return Status::ok();
}

}  // namespace si
