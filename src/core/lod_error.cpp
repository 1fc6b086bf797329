// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// LOD geometric error: point-to-triangle distances (C. Ericson, "Real-Time Collision
// Detection", 2005, 5.1.5) over a uniform grid of the surface's triangles.
#include "si/core/lod_error.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {

// Squared distance from p to triangle abc.
float distanceSquared(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                      const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  glm::vec3 q;
  if (d1 <= 0.0f && d2 <= 0.0f) {
    q = a;
  } else {
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    const float vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d3 >= 0.0f && d4 <= d3) {
      q = b;
    } else if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
      q = a + ab * (d1 / (d1 - d3));
    } else if (d6 >= 0.0f && d5 <= d6) {
      q = c;
    } else if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
      q = a + ac * (d2 / (d2 - d6));
    } else if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
      q = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    } else {
      const float denom = 1.0f / (va + vb + vc);
      q = a + ab * (vb * denom) + ac * (vc * denom);
    }
  }
  const glm::vec3 d = p - q;
  return glm::dot(d, d);
}

// Triangles bucketed in a uniform grid by their bounding boxes.
class TriangleGrid {
 public:
  TriangleGrid(Span<const glm::vec3> positions, Span<const uint32_t> triangles)
      : positions_(positions), triangles_(triangles) {
    const size_t count = triangles.size() / 3;
    lo_ = glm::vec3(std::numeric_limits<float>::max());
    glm::vec3 hi(-std::numeric_limits<float>::max());
    for (uint32_t i : triangles) {
      lo_ = glm::min(lo_, positions[i]);
      hi = glm::max(hi, positions[i]);
    }
    const float longest = std::max(std::max(hi.x - lo_.x, hi.y - lo_.y), hi.z - lo_.z);
    const glm::vec3 extent = glm::max(hi - lo_, glm::vec3(std::max(longest, 1e-6f) * 1e-3f));
    // About one triangle per cell of the box's volume (thin and flat boxes included).
    cell_ = std::cbrt(extent.x * extent.y * extent.z / float(std::max<size_t>(count, 1)));
    cell_ = std::max(cell_, longest / 256.0f);  // At most 256 cells along an axis.
    for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, int(std::ceil(extent[k] / cell_)));
    cells_.assign(size_t(dims_[0]) * dims_[1] * dims_[2], {});
    for (size_t t = 0; t < count; ++t) {
      const glm::vec3 &a = positions[triangles[t * 3]], &b = positions[triangles[t * 3 + 1]],
                      &c = positions[triangles[t * 3 + 2]];
      const glm::ivec3 from = cellOf(glm::min(glm::min(a, b), c));
      const glm::ivec3 to = cellOf(glm::max(glm::max(a, b), c));
      for (int z = from.z; z <= to.z; ++z)
        for (int y = from.y; y <= to.y; ++y)
          for (int x = from.x; x <= to.x; ++x) cells_[index(x, y, z)].push_back(uint32_t(t));
    }
  }

  // Squared distance from p to the nearest triangle: shells of cells around p's cell, until
  // the next shell cannot hold anything nearer, or one within `enough` is found (the caller
  // only needs to know the distance is not above it).
  float nearestSquared(const glm::vec3& p, float enough) const {
    const glm::ivec3 home = cellOf(p);
    // Distance from p to the grid's box (p may lie outside it).
    const glm::vec3 hi = lo_ + glm::vec3(dims_[0], dims_[1], dims_[2]) * cell_;
    const glm::vec3 outside = glm::max(glm::max(lo_ - p, p - hi), glm::vec3(0.0f));
    const float base = glm::length(outside);
    float best = std::numeric_limits<float>::max();
    const int max_shell = std::max(std::max(dims_[0], dims_[1]), dims_[2]);
    for (int shell = 0; shell <= max_shell; ++shell) {
      // Everything in this shell lies at least this far from p: beyond the box's distance,
      // and beyond shell - 1 whole cells along one axis.
      const float reach = std::max(base, float(std::max(shell - 1, 0)) * cell_);
      if (best <= enough || (best < std::numeric_limits<float>::max() && reach * reach > best))
        break;
      for (int z = home.z - shell; z <= home.z + shell; ++z)
        for (int y = home.y - shell; y <= home.y + shell; ++y)
          for (int x = home.x - shell; x <= home.x + shell; ++x) {
            if (std::max(std::max(std::abs(x - home.x), std::abs(y - home.y)),
                         std::abs(z - home.z)) != shell)
              continue;  // Only the shell's surface.
            if (x < 0 || y < 0 || z < 0 || x >= dims_[0] || y >= dims_[1] || z >= dims_[2])
              continue;
            for (uint32_t t : cells_[index(x, y, z)])
              best = std::min(best, distanceSquared(p, positions_[triangles_[t * 3]],
                                                    positions_[triangles_[t * 3 + 1]],
                                                    positions_[triangles_[t * 3 + 2]]));
          }
    }
    return best;
  }

 private:
  glm::ivec3 cellOf(const glm::vec3& p) const {
    glm::ivec3 c;
    for (int k = 0; k < 3; ++k)
      c[k] = std::clamp(int(std::floor((p[k] - lo_[k]) / cell_)), 0, dims_[k] - 1);
    return c;
  }
  size_t index(int x, int y, int z) const { return (size_t(z) * dims_[1] + y) * dims_[0] + x; }

  Span<const glm::vec3> positions_;
  Span<const uint32_t> triangles_;
  glm::vec3 lo_;
  float cell_ = 1.0f;
  int dims_[3] = {1, 1, 1};
  std::vector<std::vector<uint32_t>> cells_;
};

Status checkTriangles(Span<const glm::vec3> positions, Span<const uint32_t> triangles) {
  if (triangles.empty() || triangles.size() % 3 != 0)
    return {StatusCode::kInvalidArgument, "LOD error: a surface needs whole triangles"};
  for (uint32_t i : triangles)
    if (i >= positions.size())
      return {StatusCode::kInvalidArgument,
              strCat("LOD error: index ", i, " is not below ", positions.size(), " positions")};
  return Status::ok();
}

// The vertices and triangle centroids of a triangle list.
std::vector<glm::vec3> samplePoints(Span<const glm::vec3> positions, Span<const uint32_t> tris) {
  std::vector<glm::vec3> points;
  points.reserve(tris.size() + tris.size() / 3);
  for (uint32_t i : tris) points.push_back(positions[i]);
  for (size_t t = 0; t + 2 < tris.size(); t += 3)
    points.push_back((positions[tris[t]] + positions[tris[t + 1]] + positions[tris[t + 2]]) / 3.0f);
  std::sort(points.begin(), points.end(), [](const glm::vec3& a, const glm::vec3& b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

}  // namespace

Status maxDistanceToSurface(Span<const glm::vec3> positions, Span<const uint32_t> triangles,
                            Span<const glm::vec3> points, float* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "maxDistanceToSurface: out is null"};
  Status s = checkTriangles(positions, triangles);
  if (!s.isOk()) return s;
  const TriangleGrid grid(positions, triangles);
  // A point nearer than the worst so far cannot change the answer: its search stops at the
  // first triangle within the worst (the usual early exit of Hausdorff distances).
  float worst = 0.0f;
  for (const glm::vec3& p : points) worst = std::max(worst, grid.nearestSquared(p, worst));
  *out = std::sqrt(worst);
  return Status::ok();
}

Status surfaceDistance(Span<const glm::vec3> positions, Span<const uint32_t> a,
                       Span<const uint32_t> b, float* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "surfaceDistance: out is null"};
  Status s = checkTriangles(positions, a);
  if (s.isOk()) s = checkTriangles(positions, b);
  if (!s.isOk()) return s;
  const std::vector<glm::vec3> pa = samplePoints(positions, a), pb = samplePoints(positions, b);
  float ab = 0.0f, ba = 0.0f;
  s = maxDistanceToSurface(positions, b, pa, &ab);
  if (s.isOk()) s = maxDistanceToSurface(positions, a, pb, &ba);
  if (s.isOk()) *out = std::max(ab, ba);
  return s;
}

Status measureLodErrors(SkinnedMesh* mesh, bool overwrite) {
  if (mesh == nullptr) return {StatusCode::kInvalidArgument, "measureLodErrors: mesh is null"};
  uint32_t max_joint = 0;
  for (const glm::u16vec4& j : mesh->joints)
    for (int k = 0; k < 4; ++k) max_joint = std::max<uint32_t>(max_joint, j[k]);
  Status s = mesh->validate(max_joint + 1);
  if (!s.isOk()) return s;
  std::vector<std::vector<float>> errors(mesh->sub_meshes.size());
  for (size_t sm = 0; sm < mesh->sub_meshes.size(); ++sm) {
    const SubMesh& sub = mesh->sub_meshes[sm];
    if (!overwrite && !sub.lod_error_units.empty()) {
      errors[sm] = sub.lod_error_units;
      continue;
    }
    const auto range = [&](const IndexRange& r) {
      return Span<const uint32_t>(mesh->indices.data() + r.first_index, r.index_count);
    };
    errors[sm].push_back(0.0f);
    for (size_t l = 1; l < sub.lods.size(); ++l) {
      if (sub.lods[l].index_count == 0) {
        // A dropped level's error is how far the part lies from the rest of the character,
        // which the part alone cannot tell (si::buildPartLods measures it): kept as given.
        if (sub.lod_error_units.size() != sub.lods.size())
          return {StatusCode::kInvalidArgument,
                  strCat("measureLodErrors: sub-mesh ", sm, " '", sub.name, "' LOD ", l,
                         " is empty (the part dropped) and has no error; give its error "
                         "(si::buildPartLods measures it)")};
        errors[sm].push_back(sub.lod_error_units[l]);
        continue;
      }
      float e = 0.0f;
      s = surfaceDistance(mesh->positions, range(sub.lods[0]), range(sub.lods[l]), &e);
      if (!s.isOk()) return s;
      errors[sm].push_back(e);
    }
  }
  for (size_t sm = 0; sm < errors.size(); ++sm) mesh->sub_meshes[sm].lod_error_units = errors[sm];
  return Status::ok();
}

Status lodErrorsByLevel(const SkinnedMesh& mesh, std::vector<float>* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "lodErrorsByLevel: out is null"};
  const size_t levels = mesh.maxLodCount();
  std::vector<float> errors(levels, 0.0f);
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm) {
    const SubMesh& sub = mesh.sub_meshes[sm];
    if (sub.lod_error_units.size() != sub.lods.size() || sub.lods.empty())
      return {StatusCode::kInvalidArgument,
              strCat("lodErrorsByLevel: sub-mesh ", sm, " '", sub.name,
                     "' has no LOD errors (si::measureLodErrors or si::buildLodChain)")};
    for (size_t l = 0; l < levels; ++l)
      errors[l] = std::max(errors[l], sub.lod_error_units[std::min(l, sub.lods.size() - 1)]);
  }
  for (size_t l = 1; l < levels; ++l) errors[l] = std::max(errors[l], errors[l - 1]);
  if (!errors.empty()) errors[0] = 0.0f;
  *out = std::move(errors);
  return Status::ok();
}

Status summarizeLodLevels(const SkinnedMesh& mesh, std::vector<LodLevelSummary>* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "summarizeLodLevels: out is null"};
  std::vector<float> errors;
  Status s = lodErrorsByLevel(mesh, &errors);
  if (!s.isOk()) return s;
  std::vector<LodLevelSummary> levels(errors.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    levels[l].error_units = errors[l];
    for (const SubMesh& sm : mesh.sub_meshes)
      levels[l].triangles += sm.lods[std::min(l, sm.lods.size() - 1)].index_count / 3;
  }
  *out = std::move(levels);
  return Status::ok();
}

}  // namespace si
