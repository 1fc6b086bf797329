// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Face-like morph targets for the examples and the tests (issue "Any animated glTF becomes a
// crowd"; crowd_bench --morph-targets, tests/render/morph_render_test.cpp): the character's
// head (the vertices above 85 % of its height, or those weighted most to a named head joint or
// a joint under it) gets `targets` targets, each a bump around a
// sector of the head pushing its vertices out along their normals and tipping the normals up,
// like expressions and visemes; every clip animates every weight (LINEAR keys at its start,
// middle and end, each target on its own phase), and target 0 has a default weight of 0.5.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "si/core/character.h"

namespace si::examples {

/// The name of `skeleton`'s first joint whose name ends in "head" in any case ("head",
/// "mixamorig:Head"), or nullptr: the head_joint to give addFaceTargets.
inline const char* findHeadJoint(const Skeleton& skeleton) {
  for (const std::string& name : skeleton.joint_names) {
    if (name.size() < 4) continue;
    std::string tail = name.substr(name.size() - 4);
    for (char& ch : tail) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (tail == "head") return name.c_str();
  }
  return nullptr;
}

// Whether vertex `v` of `c` is weighted most to joint `head` or a joint under it.
inline bool weightedToBranch(const Character& c, size_t v, int32_t head) {
  const glm::vec4 w = c.mesh.weights[v];
  int largest = 0;
  for (int k = 1; k < 4; ++k)
    if (w[k] > w[largest]) largest = k;
  int32_t j = int32_t(c.mesh.joints[v][largest]);
  while (j != Skeleton::kNoParent && j != head) j = c.skeleton.parents[size_t(j)];
  return j == head;
}

/// Adds `targets` face-like targets (at most kMaxMorphTargets) to `c`'s mesh and a weights
/// track over all of them to each of its clips (replacing the clips' morph tracks); none for 0.
/// With `head_joint` naming a joint of the skeleton, the head is what is weighted most to it or
/// a joint under it (a held spear's tip left out); otherwise what rises above 85 % of the height.
/// Each target moves the head by up to 4 % of the height; with `bounded`, the targets that
/// overlap a place (about 10 of 50) share that, so the head keeps its size whatever their
/// number (the demo's faces; the benchmarks' targets are each at full size).
inline void addFaceTargets(Character* character, size_t targets, const char* head_joint = nullptr,
                           bool bounded = false) {
  if (targets == 0) return;
  Character& c = *character;
  const size_t first = c.mesh.morph_targets.size();
  const float height = c.height();
  const Aabb box = c.bindPoseBounds();
  const int32_t head_index = head_joint != nullptr ? c.skeleton.findJoint(head_joint) : -1;
  float top = box.max.y, head_floor = box.min.y + 0.85f * (box.max.y - box.min.y);
  std::vector<uint8_t> in_head(c.mesh.vertexCount());
  for (size_t v = 0; v < in_head.size(); ++v)
    in_head[v] =
        head_index >= 0 ? weightedToBranch(c, v, head_index) : c.mesh.positions[v].y > head_floor;
  glm::vec3 centre(0.0f);
  size_t head = 0;
  if (head_index >= 0) top = box.min.y, head_floor = box.max.y;
  for (size_t v = 0; v < in_head.size(); ++v) {
    if (!in_head[v]) continue;
    const glm::vec3 p = c.mesh.positions[v];
    centre += p, ++head;
    if (head_index >= 0) top = std::max(top, p.y), head_floor = std::min(head_floor, p.y);
  }
  centre /= float(std::max<size_t>(head, 1));
  const float pi = 3.14159265f;
  const float reach = std::max(pi / float(targets) * 2.0f, 0.6f);
  // Targets reaching one place: a sector of 2 pi / targets each, reaching `reach` either side.
  const float overlap = reach * float(targets) / pi;
  const float size = 0.04f * height * (bounded ? std::min(1.0f, 2.0f / overlap) : 1.0f);
  for (size_t k = 0; k < targets; ++k) {
    MorphTarget t;
    t.name = "face" + std::to_string(k);
    t.default_weight = k == 0 ? 0.5f : 0.0f;
    const float sector = 2.0f * pi * float(k) / float(targets);
    for (size_t v = 0; v < c.mesh.vertexCount(); ++v) {
      const glm::vec3 p = c.mesh.positions[v];
      if (!in_head[v]) continue;
      const float angle = std::atan2(p.z - centre.z, p.x - centre.x);
      // The angle between them, 0 to pi (atan2 gives -pi to pi, the sectors 0 to 2 pi: until
      // 2026-12-03 a difference past 2 pi went negative here, and every target reached the
      // vertices at negative angles: some 29 of 50 at one vertex instead of at most 10).
      float d = std::fmod(std::fabs(angle - sector), 2.0f * pi);
      d = std::min(d, 2.0f * pi - d);
      if (d >= reach) continue;
      const float bump = 0.5f + 0.5f * std::cos(pi * d / reach);  // 1 at the sector, 0 at reach.
      const float rise = top > head_floor ? (p.y - head_floor) / (top - head_floor) : 1.0f;
      t.vertices.push_back(uint32_t(v));
      t.position_deltas.push_back(c.mesh.normals[v] * (size * bump * rise));
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
