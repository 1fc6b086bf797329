// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "bake/joint_bounds.h"

#include <algorithm>
#include <cmath>

#include "core/palette_texel.h"

namespace si::detail {

namespace {

// The largest magnitude each morph target's weight reaches in the palette's frames (border
// frames included: cubic interpolation reads them).
std::vector<float> largestMorphWeights(const BakedPalette& p) {
  const PaletteLayout& l = p.layout;
  std::vector<float> largest(l.morph_target_count, 0.0f);
  const int64_t border = l.border_frames;
  for (uint32_t c = 0; c < p.clips.size(); ++c)
    for (int64_t f = -border; f < int64_t(p.clips[c].frame_count) + border; ++f)
      for (uint32_t t = 0; t < l.morph_target_count; t += 4) {
        const glm::vec4 w = paletteTexel(p, l.morphTexel(c, f, t));
        for (uint32_t k = 0; k < 4 && t + k < l.morph_target_count; ++k)
          largest[t + k] = std::max(largest[t + k], std::fabs(w[int(k)]));
      }
  return largest;
}

}  // namespace

std::vector<Aabb> jointBounds(const BakedPalette& p, const SkinnedMesh& gpu_mesh,
                              const std::vector<uint32_t>& vertices) {
  // Per vertex, how far its morph targets can move it on each axis.
  std::vector<glm::vec3> reach(gpu_mesh.positions.size(), glm::vec3(0.0f));
  const std::vector<float> largest = largestMorphWeights(p);
  for (size_t t = 0; t < gpu_mesh.morph_targets.size() && t < largest.size(); ++t) {
    const MorphTarget& target = gpu_mesh.morph_targets[t];
    for (size_t k = 0; k < target.vertices.size(); ++k)
      reach[target.vertices[k]] += glm::abs(target.position_deltas[k]) * largest[t];
  }
  std::vector<Aabb> out(p.palette_joints.size());
  for (uint32_t v : vertices)
    for (size_t k = 0; k < gpu_mesh.influenceCount(); ++k) {
      const Influence in = gpu_mesh.influence(v, k);
      if (in.weight == 0.0f || in.joint >= p.skeleton_to_palette.size()) continue;
      const int32_t slot = p.skeleton_to_palette[in.joint];
      if (slot < 0) continue;
      out[size_t(slot)].extend(gpu_mesh.positions[v] - reach[v]);
      out[size_t(slot)].extend(gpu_mesh.positions[v] + reach[v]);
    }
  for (Aabb& b : out) {
    if (b.empty()) {
      b = Aabb();  // None: nothing drawn follows the joint.
      continue;
    }
    const glm::vec3 pad =
        1e-5f * (b.max - b.min) + 1e-6f * glm::max(glm::abs(b.min), glm::abs(b.max));
    b.min -= pad;
    b.max += pad;
  }
  return out;
}

}  // namespace si::detail
