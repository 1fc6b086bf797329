// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Per-part LOD: each sub-mesh's chain (plus, for a droppable part, an empty level whose error is
// its distance to the kept parts) mapped onto the character's levels by error.
#include "si/core/part_lod.h"

#include <algorithm>

#include "core/lod_poses.h"

namespace si {
using detail::strCat;

namespace {

constexpr size_t kMaxCharacterLevels = 8;  // CrowdDesc::lod_count's limit.

Span<const uint32_t> rangeOf(const SkinnedMesh& mesh, const IndexRange& r) {
  return Span<const uint32_t>(mesh.indices.data() + r.first_index, r.index_count);
}

bool hasEmptyLevel(const SubMesh& sub) {
  return std::any_of(sub.lods.begin(), sub.lods.end(),
                     [](const IndexRange& r) { return r.index_count == 0; });
}

// The sub-mesh whose bind-pose LOD 0 has the largest bounding-box diagonal.
uint32_t largestSubMesh(const SkinnedMesh& mesh) {
  uint32_t best = 0;
  float best_diagonal = -1.0f;
  for (size_t s = 0; s < mesh.sub_meshes.size(); ++s) {
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (uint32_t i : rangeOf(mesh, mesh.sub_meshes[s].lods[0])) {
      lo = glm::min(lo, mesh.positions[i]);
      hi = glm::max(hi, mesh.positions[i]);
    }
    const float diagonal = glm::length(hi - lo);
    if (diagonal > best_diagonal) best = uint32_t(s), best_diagonal = diagonal;
  }
  return best;
}

// Per droppable sub-mesh (bit set in `drop_mask`), the largest distance from its LOD 0 vertices
// and triangle centroids to the kept sub-meshes' LOD 0 surface, over the poses.
Status measureDropErrors(const Character& c, uint32_t keep_mask, uint32_t drop_mask,
                         const AnimatedLodErrorDesc& poses_desc, std::vector<float>* out) {
  const SkinnedMesh& mesh = c.mesh;
  std::vector<uint32_t> kept;
  for (size_t s = 0; s < mesh.sub_meshes.size(); ++s)
    if (keep_mask >> s & 1u) {
      const Span<const uint32_t> r = rangeOf(mesh, mesh.sub_meshes[s].lods[0]);
      kept.insert(kept.end(), r.begin(), r.end());
    }
  out->assign(mesh.sub_meshes.size(), -1.0f);
  ReferencePose pose;
  std::vector<glm::dvec3> skinned;
  std::vector<glm::vec3> positions, points;
  for (const detail::LodPose& at : detail::lodPoses(c, poses_desc)) {
    Status s = detail::skinLodPose(c, mesh, at, "buildPartLods", &pose, &skinned, &positions);
    if (!s.isOk()) return s;
    for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm) {
      if (!(drop_mask >> sm & 1u)) continue;
      const Span<const uint32_t> tris = rangeOf(mesh, mesh.sub_meshes[sm].lods[0]);
      points.clear();
      for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        const glm::vec3 &a = positions[tris[t]], &b = positions[tris[t + 1]],
                        &d = positions[tris[t + 2]];
        points.push_back(a), points.push_back(b), points.push_back(d);
        points.push_back((a + b + d) / 3.0f);
      }
      float e = 0.0f;
      s = maxDistanceToSurface(positions, kept, points, &e);
      if (!s.isOk()) return s;
      (*out)[sm] = std::max((*out)[sm], e);
    }
  }
  return Status::ok();
}

}  // namespace

Status buildPartLods(Character* character, const PartLodDesc& desc, PartLodReport* report) {
  if (character == nullptr)
    return {StatusCode::kInvalidArgument, "buildPartLods: character is null"};
  const SkinnedMesh& mesh = character->mesh;
  Status s = mesh.validate(character->skeleton.parents.size());
  if (!s.isOk()) return s;
  const size_t parts = mesh.sub_meshes.size();
  for (size_t sm = 0; sm < parts; ++sm)
    if (mesh.sub_meshes[sm].lod_error_units.size() != mesh.sub_meshes[sm].lods.size())
      return {StatusCode::kInvalidArgument,
              strCat("buildPartLods: sub-mesh ", sm, " '", mesh.sub_meshes[sm].name,
                     "' has no LOD errors (si::measureLodErrors, si::buildLodChain or "
                     "si::measureAnimatedLodErrors first)")};
  const uint32_t all = parts == 32 ? 0xFFFFFFFFu : (1u << parts) - 1u;
  if ((desc.keep_mask & ~all) != 0)
    return {StatusCode::kInvalidArgument,
            strCat("buildPartLods: keep_mask ", desc.keep_mask,
                   " names sub-meshes past the mesh's ", parts)};
  const uint32_t keep = desc.keep_mask != 0 ? desc.keep_mask : 1u << largestSubMesh(mesh);

  // The parts that may be dropped: outside the kept ones, not dropped by an earlier call.
  uint32_t drop_mask = 0;
  if (desc.drop)
    for (size_t sm = 0; sm < parts; ++sm)
      if (!(keep >> sm & 1u) && !hasEmptyLevel(mesh.sub_meshes[sm])) drop_mask |= 1u << sm;
  std::vector<float> drop_errors(parts, -1.0f);
  if (drop_mask != 0) {
    s = measureDropErrors(*character, keep, drop_mask, desc.poses, &drop_errors);
    if (!s.isOk()) return s;
  }
  // Each part's chain as it may be drawn: its own levels, padded with its last to the
  // character's levels, then (droppable, not yet dropped) an empty level whose error is its
  // distance to the kept parts. The drop sits past every existing level, so the character's
  // error at those levels is unchanged; the drop is taken wherever it fits within them.
  const size_t existing = mesh.maxLodCount();
  std::vector<std::vector<IndexRange>> chains(parts);
  std::vector<std::vector<float>> errors(parts);
  std::vector<std::vector<int>> own(parts);  // Padded index -> the part's own level.
  for (size_t sm = 0; sm < parts; ++sm) {
    const SubMesh& sub = mesh.sub_meshes[sm];
    for (size_t l = 0; l < existing; ++l) {
      const size_t k = std::min(l, sub.lods.size() - 1);
      chains[sm].push_back(sub.lods[k]);
      errors[sm].push_back(sub.lod_error_units[k]);
      own[sm].push_back(sub.lods[k].index_count == 0 ? -1 : int(k));
    }
    if (drop_mask >> sm & 1u) {
      chains[sm].push_back(IndexRange{0, 0});
      errors[sm].push_back(std::max(drop_errors[sm], errors[sm].back()));
      own[sm].push_back(-1);
    }
  }

  // The character's error per level: the largest of any part there, non-decreasing. One level
  // more than the existing ones where a part is dropped only there (and 8 levels allow it).
  const auto errorsOf = [&](size_t levels) {
    std::vector<float> e(levels, 0.0f);
    for (size_t l = 1; l < levels; ++l) {
      e[l] = e[l - 1];
      for (size_t sm = 0; sm < parts; ++sm)
        e[l] = std::max(e[l], errors[sm][std::min(l, errors[sm].size() - 1)]);
    }
    return e;
  };
  const auto levelOf = [&](size_t sm, size_t l, float error) {  // Padded index drawn at l.
    size_t m = std::min(l, chains[sm].size() - 1);
    while (m + 1 < chains[sm].size() && errors[sm][m + 1] <= error) ++m;
    return m;
  };
  size_t levels = existing;
  if (existing < kMaxCharacterLevels) {
    const std::vector<float> e = errorsOf(existing + 1);
    for (size_t sm = 0; sm < parts && levels == existing; ++sm)
      if (levelOf(sm, existing, e[existing]) != levelOf(sm, existing - 1, e[existing - 1]) &&
          own[sm][levelOf(sm, existing - 1, e[existing - 1])] >= 0)
        levels = existing + 1;
  }
  const std::vector<float> level_errors = errorsOf(levels);

  // Each part at each level: the coarsest of its levels within the character's error there.
  SkinnedMesh out = mesh;
  PartLodReport rep;
  rep.level_errors_units = level_errors;
  for (size_t sm = 0; sm < parts; ++sm) {
    PartLodReport::Part part;
    part.name = mesh.sub_meshes[sm].name;
    part.kept = (keep >> sm & 1u) != 0;
    part.drop_error_units = drop_errors[sm];
    SubMesh& sub = out.sub_meshes[sm];
    sub.lods.assign(levels, IndexRange{});
    sub.lod_error_units.assign(levels, 0.0f);
    for (size_t l = 0; l < levels; ++l) {
      const size_t m = levelOf(sm, l, level_errors[l]);
      sub.lods[l] = chains[sm][m];
      sub.lod_error_units[l] = errors[sm][m];
      part.level_of.push_back(own[sm][m]);
    }
    rep.parts.push_back(std::move(part));
  }
  for (size_t l = 0; l < levels; ++l) {  // levels >= existing: the longer chain's length.
    uint64_t before = 0, after = 0;
    for (size_t sm = 0; sm < parts; ++sm) {
      before += mesh.triangleCount(sm, l);
      after += out.triangleCount(sm, l);
    }
    rep.triangles_before.push_back(before);
    rep.triangles_after.push_back(after);
  }
  character->mesh = std::move(out);
  if (report != nullptr) *report = std::move(rep);
  return Status::ok();
}

}  // namespace si
