// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Face-like morph targets for the examples and the tests (issue "Any animated glTF becomes a
// crowd"; crowd_bench --morph-targets, tests/render/morph_render_test.cpp): the character's
// head (the vertices above 85 % of its height) gets `targets` targets, each a bump around a
// sector of the head pushing its vertices out along their normals and tipping the normals up,
// like expressions and visemes; every clip animates every weight (LINEAR keys at its start,
// middle and end, each target on its own phase), and target 0 has a default weight of 0.5.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "si/core/character.h"

namespace si::examples {

/// Adds `targets` face-like targets (at most kMaxMorphTargets) to `c`'s mesh and a weights
/// track over all of them to each of its clips (replacing the clips' morph tracks); none for 0.
inline void addFaceTargets(Character* character, size_t targets) {
  if (targets == 0) return;
  Character& c = *character;
  const size_t first = c.mesh.morph_targets.size();
  const float height = c.height();
  const Aabb box = c.bindPoseBounds();
  const float top = box.max.y, head_floor = box.min.y + 0.85f * (box.max.y - box.min.y);
  glm::vec3 centre(0.0f);
  size_t head = 0;
  for (const glm::vec3& p : c.mesh.positions)
    if (p.y > head_floor) centre += p, ++head;
  centre /= float(std::max<size_t>(head, 1));
  const float pi = 3.14159265f;
  for (size_t k = 0; k < targets; ++k) {
    MorphTarget t;
    t.name = "face" + std::to_string(k);
    t.default_weight = k == 0 ? 0.5f : 0.0f;
    const float sector = 2.0f * pi * float(k) / float(targets);
    for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
      const glm::vec3 p = c.mesh.positions[v];
      if (p.y <= head_floor) continue;
      const float angle = std::atan2(p.z - centre.z, p.x - centre.x);
      float d = std::fabs(angle - sector);
      d = std::min(d, 2.0f * pi - d);
      const float reach = std::max(pi / float(targets) * 2.0f, 0.6f);
      if (d >= reach) continue;
      const float bump = 0.5f + 0.5f * std::cos(pi * d / reach);  // 1 at the sector, 0 at reach.
      const float rise = (p.y - head_floor) / (top - head_floor);
      t.vertices.push_back(uint32_t(v));
      t.position_deltas.push_back(c.mesh.normals[v] * (0.04f * height * bump * rise));
      t.normal_deltas.push_back(glm::vec3(0.0f, 0.4f * bump, 0.0f));
    }
    c.mesh.morph_targets.push_back(std::move(t));
  }
  for (Clip& clip : c.clips) {
    MorphWeightTrack w;
    w.first_target = uint32_t(first);
    w.target_count = uint32_t(targets);
    w.interpolation = Interpolation::kLinear;
    const float d = clip.duration_seconds;
    w.times_seconds = d > 0.0f ? std::vector<float>{0.0f, 0.5f * d, d} : std::vector<float>{0.0f};
    for (size_t key = 0; key < w.times_seconds.size(); ++key)
      for (size_t k = 0; k < targets; ++k)
        w.values.push_back(0.5f + 0.5f * std::sin(float(key) * 2.0f + float(k) * 1.3f));
    clip.morph_tracks = {w};
  }
}

}  // namespace si::examples
