// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Tangent frames for normal maps where a mesh has none: per-vertex tangents from the
/// triangles' texture-coordinate gradients, MikkTSpace-style (each corner weighted by its
/// angle, the tangent made orthogonal to the vertex normal, the bitangent's side as w). The
/// glTF import calls it when a material has a normal map and the file has no TANGENT
/// (GltfImportReport::generated_tangents). Plain CPU work, no GL.
///
/// It follows MikkTSpace's construction but is not bit-identical to it: vertices are not
/// split where neighbouring triangles disagree (a glTF vertex already carries one frame), so
/// where a baker split them the frame differs; tests/core/tangents_test.cpp measures the angle
/// against analytic frames.

#include <cstddef>

#include "si/core/skinned_mesh.h"
#include "si/core/status.h"

namespace si {

/// What generateTangents() did.
struct TangentReport {
  size_t vertices = 0;    ///< Tangents written (every vertex).
  size_t degenerate = 0;  ///< Vertices no triangle with a usable UV mapping touches: given a
                          ///< unit vector perpendicular to the normal, w = 1.
  size_t mirrored = 0;    ///< Vertices with w = -1 (the mapping mirrored against glTF's).
};

/// Writes `mesh->tangents` (one per vertex, xyz unit and perpendicular to the normal, w = +-1
/// with bitangent = w * cross(normal, tangent)), replacing any it had. glTF's convention: the
/// tangent points where u grows, the bitangent where v falls (up in the image: images are
/// stored top row first and texture coordinates have v growing down, so a normal map's +y is
/// up in its image). The triangles of every sub-mesh's LOD 0 make the frame; vertices only
/// coarser levels use take theirs from the levels' triangles. Fails, leaving `mesh` untouched, with kInvalidArgument for a null mesh,
/// one without texture coordinates, or normals that do not match the vertices, and with
/// kOutOfRange for an index past the vertices.
Status generateTangents(SkinnedMesh* mesh, TangentReport* report);

}  // namespace si
