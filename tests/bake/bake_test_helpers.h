// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Synthetic characters for baker tests: a chain of joints along +Y with a tube of vertices.

#include <cmath>
#include <string>

#include "core/test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/character.h"

namespace si::test {

/// A chain of `joint_count` joints 1 unit apart along +Y, with one ring of 4 vertices (radius
/// 0.25) per joint rigidly bound to it, and a top ring bound to the last joint; one sub-mesh
/// with one LOD. Height: joint_count units. Clips are added by the test.
inline Character chainCharacter(size_t joint_count) {
  Character c;
  c.name = "chain";
  for (size_t i = 0; i < joint_count; ++i) {
    c.skeleton.joint_names.push_back("joint" + std::to_string(i));
    c.skeleton.parents.push_back(i == 0 ? Skeleton::kNoParent : int32_t(i - 1));
    Transform t;
    t.translation = i == 0 ? glm::vec3(0.0f) : glm::vec3(0, 1, 0);
    c.skeleton.rest_pose.push_back(t);
    glm::mat4 ibm(1.0f);
    ibm[3] = glm::vec4(0, -float(i), 0, 1);
    c.skeleton.inverse_bind_matrices.push_back(ibm);
  }
  SkinnedMesh& m = c.mesh;
  const size_t rings = joint_count + 1;
  for (size_t r = 0; r < rings; ++r) {
    const uint16_t joint = uint16_t(std::min(r, joint_count - 1));
    for (int k = 0; k < 4; ++k) {
      const float a = float(k) * 1.5707963f;
      m.positions.push_back(glm::vec3(0.25f * std::cos(a), float(r), 0.25f * std::sin(a)));
      m.normals.push_back(glm::vec3(std::cos(a), 0.0f, std::sin(a)));
      m.joints.push_back(glm::u16vec4(joint, 0, 0, 0));
      m.weights.push_back(glm::vec4(1, 0, 0, 0));
    }
  }
  for (uint32_t r = 0; r + 1 < rings; ++r)
    for (uint32_t k = 0; k < 4; ++k) {
      const uint32_t a = r * 4 + k, b = r * 4 + (k + 1) % 4;
      m.indices.insert(m.indices.end(), {a, b, a + 4, b, b + 4, a + 4});
    }
  m.sub_meshes.push_back(SubMesh{"body", {IndexRange{0, uint32_t(m.indices.size())}}, 0, {}});
  return c;
}

/// A clip of `c` with no tracks.
inline Clip blankClip(const Character& c, const std::string& name, float duration,
                      LoopMode loop = LoopMode::kOnce) {
  Clip clip;
  clip.name = name;
  clip.duration_seconds = duration;
  clip.loop_mode = loop;
  clip.joint_tracks.resize(c.skeleton.jointCount());
  return clip;
}

/// The rotation of `angle` radians about unit `axis`, in float (core/test_helpers.h).
using test::axisAngleF;

// A small palette with every clip-table feature: STEP frame times, a loop, markers, root motion.
inline BakedPalette smallPalette(PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                                 InterpolationChoice interpolation = InterpolationChoice::kLinear) {
  Character c = chainCharacter(3);
  Clip step = blankClip(c, "step", 0.5f);
  step.joint_tracks[1].translation.interpolation = Interpolation::kStep;
  step.joint_tracks[1].translation.times_seconds = {0.0f, 0.25f};
  step.joint_tracks[1].translation.values = {{0, 1, 0}, {0.5f, 1, 0}};
  c.clips.push_back(step);
  Clip swing = blankClip(c, "swing", 1.0f, LoopMode::kLoop);
  swing.joint_tracks[2].rotation.times_seconds = {0.0f, 0.5f, 1.0f};
  swing.joint_tracks[2].rotation.values = {glm::quat(1, 0, 0, 0), axisAngleF(0.5, {1, 0, 0}),
                                           glm::quat(1, 0, 0, 0)};
  swing.markers = {{0.25, "left"}, {1.0, "loop end"}};  // The baker copies them.
  c.clips.push_back(swing);
  Clip travel = blankClip(c, "travel", 0.3f);  // Baked in place, with its root motion.
  travel.root_motion.extract = true;
  travel.joint_tracks[0].translation.times_seconds = {0.0f, 0.3f};
  travel.joint_tracks[0].translation.values = {glm::vec3(0.0f), glm::vec3(0.5f, 0.0f, 0.25f)};
  travel.joint_tracks[0].rotation.times_seconds = {0.0f, 0.3f};
  travel.joint_tracks[0].rotation.values = {glm::quat(1, 0, 0, 0), axisAngleF(0.4, {0, 1, 0})};
  c.clips.push_back(travel);
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 10.0f;
  d.format = format;
  d.interpolation = interpolation;
  BakedPalette p;
  EXPECT_TRUE(bakePalette(c, d, &p, nullptr).isOk());
  return p;
}

}  // namespace si::test
