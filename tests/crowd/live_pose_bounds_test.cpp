// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// How a live pose is selected: culled by its own bounds (BakedPalette::joint_bounds carried by
// the pose's matrices), not by its clip's sphere (every vertex the shader draws lies inside
// them, and a pose drawn far from where its clip would be is selected where it is), and never
// drawn as its clip's impostor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "crowd/crowd_test_helpers.h"
#include "crowd/live_pose_helpers.h"
#include "crowd/morph_face_fixture.h"
#include "si/crowd/crowd_export.h"

namespace si {
namespace {

using test::Face;
using test::face;

// The stored matrices of clip `clip`'s frame `frame`.
std::vector<glm::mat4> clipFrame(const BakedPalette& p, uint32_t clip, uint32_t frame) {
  std::vector<glm::mat4> pose(p.palette_joints.size());
  for (uint32_t slot = 0; slot < pose.size(); ++slot)
    pose[slot] = decodeJoint(p, clip, frame, slot);
  return pose;
}

// The slot's bounds as the GPU-driven culling reads them (CrowdExport::livePoses).
GpuLivePose exportedSlot(const CrowdManager& crowd, InstanceHandle h) {
  std::vector<GpuInstanceState> states;
  std::vector<InstanceHandle> handles;
  std::vector<GpuLivePose> slots;
  CrowdExport(crowd).state(&states, &handles);
  CrowdExport(crowd).livePoses(&slots);
  for (size_t i = 0; i < handles.size(); ++i)
    if (handles[i] == h) return slots[states[i].live_pose];
  ADD_FAILURE() << "the instance is not exported";
  return GpuLivePose();
}

// The face character (tests/crowd/morph_face_fixture.h) with a fourth target that moves its
// first ten vertices sideways by half its height, from weight 0 at the start of "walk" to 1 at
// its end: far past any joint's own vertices.
struct FarTarget {
  Character character;
  uint32_t walk = 0;
};
const FarTarget& farTarget() {
  static const FarTarget f = [] {
    FarTarget out;
    out.character = face().character;
    Character& c = out.character;
    MorphTarget t;
    t.name = "far";
    for (uint32_t v = 0; v < 10; ++v) {
      t.vertices.push_back(v);
      t.position_deltas.push_back(glm::vec3(0.5f * c.height(), 0.0f, 0.0f));
    }
    c.mesh.morph_targets.push_back(t);
    for (Clip& clip : c.clips) {
      MorphWeightTrack& w = clip.morph_tracks[0];
      const bool walk = clip.name == "walk";
      std::vector<float> values;
      for (int key = 0; key < 2; ++key) {
        for (int k = 0; k < 3; ++k) values.push_back(w.values[size_t(3 * key + k)]);
        values.push_back(walk ? float(key) : 0.0f);
      }
      w.target_count = 4;
      w.values = values;
    }
    out.walk = uint32_t(c.findClip("walk"));
    return out;
  }();
  return f;
}

// Every vertex the shader draws of poses far from any clip's lies inside the bounds the crowd
// gives them: on a character whose morph targets move vertices past their joints' own (at the
// weights of the frame the pose takes), in float and half-float palettes, with the bind pose
// moved hundreds of units (half floats' rounding of the move shifts every vertex), a baked
// frame's pose laid down and moved, and each joint's matrix an arbitrary affine map (turns,
// shears, scales, moves). The baked frame's bounds stay close to its clip's box.
TEST(LivePoseBounds, EveryDrawnVertexLiesInsideThePosesBounds) {
  const FarTarget& f = farTarget();
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16}) {
    SCOPED_TRACE(paletteFormatName(format));
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    bd.format = format;
    BakedPalette p;
    ASSERT_TRUE(bakePalette(f.character, bd, &p, nullptr).isOk());
    ASSERT_EQ(p.joint_bounds.size(), p.palette_joints.size());
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(test::liveDesc(p, f.character, 1)).isOk());
    const BakedClip& walk = p.clips[f.walk];
    InstanceDesc d;
    d.clip = f.walk;
    d.time_seconds = walk.duration_seconds;  // The last frame's morph weights, "far" at 1,
    d.speed = 0.0f;                          // go with every pose.
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    std::vector<float> weights(p.layout.morph_target_count);
    const uint32_t last = p.layout.frameTexel(f.walk, int64_t(walk.frame_count) - 1);
    ASSERT_TRUE(emulateMorphWeights(p, last, last, 0.0f, IntervalMode::kLinear, weights).isOk());
    ASSERT_EQ(weights.size(), 4u);
    ASSERT_GT(weights[3], 0.99f);
    const SkinnedMesh& mesh = f.character.mesh;
    std::vector<glm::vec3> drawn(mesh.positions.size());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float height = p.character_height;
    double worst = -1.0;  // The largest of (distance from the centre / radius) over vertices.
    for (int trial = 0; trial < 24; ++trial) {
      std::vector<glm::mat4> pose = clipFrame(p, f.walk, uint32_t(trial) % 8);
      if (trial >= 1 && trial < 4) {  // The bind pose moved by hundreds of units.
        const glm::vec3 move = glm::vec3(300.3f, 0.1f, -200.7f) * float(trial);
        for (glm::mat4& m : pose) m = glm::translate(glm::mat4(1.0f), move);
      } else if (trial >= 4) {
        // Laid down, turned and moved by up to 10 heights.
        const glm::mat4 body =
            glm::translate(glm::mat4(1.0f), 10.0f * height * glm::vec3(u(rng), u(rng), u(rng))) *
            glm::rotate(glm::mat4(1.0f), 1.5708f, glm::normalize(glm::vec3(u(rng), u(rng), 1.0f)));
        for (glm::mat4& m : pose) m = body * m;
      }
      if (trial >= 14) {
        // Every joint an arbitrary affine map.
        for (glm::mat4& m : pose) {
          for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) m[c][r] = (r == c ? 1.05f : 0.0f) + 0.95f * u(rng);
          m[3] = glm::vec4(height * glm::vec3(u(rng), u(rng), u(rng)), 1.0f);
        }
      }
      ASSERT_TRUE(crowd.setLivePose(h, pose).isOk());
      const GpuLivePose slot = exportedSlot(crowd, h);
      ASSERT_EQ(slot.bounded, 1u);
      // Drawn as the shader draws the stored matrices (half floats rounded), per skeleton joint.
      std::vector<glm::mat4> matrices(p.skeleton_to_palette.size(), glm::mat4(1.0f));
      for (size_t j = 0; j < matrices.size(); ++j) {
        const int32_t s = p.skeleton_to_palette[j];
        if (s < 0) continue;
        matrices[j] = pose[size_t(s)];
        if (format == PaletteFormat::kMatrix3x4F16)
          for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r)
              matrices[j][c][r] = halfToFloat(floatToHalf(matrices[j][c][r]));
      }
      ASSERT_TRUE(emulateSkinning(mesh, matrices, drawn, {}, weights).isOk());
      const glm::vec3 lo(slot.box_min[0], slot.box_min[1], slot.box_min[2]);
      const glm::vec3 hi(slot.box_max[0], slot.box_max[1], slot.box_max[2]);
      const glm::vec3 center(slot.sphere[0], slot.sphere[1], slot.sphere[2]);
      size_t outside = 0;
      for (const glm::vec3& q : drawn) {
        outside += glm::any(glm::lessThan(q, lo)) || glm::any(glm::greaterThan(q, hi)) ||
                   glm::length(q - center) > slot.sphere[3];
        worst = std::max(worst, double(glm::length(q - center) / slot.sphere[3]));
      }
      EXPECT_EQ(outside, 0u) << "trial " << trial;
      if (trial == 0) {  // A baked frame: not much wider than the clip's own box.
        const Aabb& clip = p.clips[f.walk].bounds;
        for (int a = 0; a < 3; ++a)
          EXPECT_LE(hi[a] - lo[a], 1.5f * (clip.max[a] - clip.min[a]) + 0.05f * height) << a;
      }
    }
    std::printf("%s: the farthest drawn vertex at %.3f of the bounds' radius\n",
                paletteFormatName(format), worst);
  }
}

// A pose moved 30 m from its instance (an engine's ragdoll thrown away) is selected where it
// is drawn, while its clip's sphere lies out of view; the same pose in a palette without joint
// bounds (a palette file before version 6) is culled by its clip's sphere, as before. A pose
// moved out of view while its clip's sphere stays in view is still drawn (the two are culled
// together, as a crossfade's two clips are).
TEST(LivePoseBounds, APoseIsSelectedWhereItIsDrawn) {
  BakedPalette without = test::defaultPalette();
  without.joint_bounds.clear();
  const Camera camera = test::testCamera({0.0, 1.5, 6.0}, {0.0, 1.0, 0.0});
  for (const BakedPalette* p :
       {&test::defaultPalette(), static_cast<const BakedPalette*>(&without)}) {
    const bool bounded = !p->joint_bounds.empty();
    SCOPED_TRACE(bounded ? "with joint bounds" : "without");
    CrowdDesc cd = test::liveDesc(2);
    cd.palette = p;
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(cd).isOk());
    InstanceDesc away, here;
    away.position = glm::dvec3(30.0, 0.0, 0.0);
    InstanceHandle ha, hh;
    ASSERT_TRUE(crowd.add(away, &ha).isOk());
    ASSERT_TRUE(crowd.add(here, &hh).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    ASSERT_EQ(crowd.view().stats().visible, 1u);  // Only `here`.
    std::vector<glm::mat4> pose = clipFrame(*p, 0, 0);
    for (glm::mat4& m : pose) m = glm::translate(glm::mat4(1.0f), glm::vec3(-30.0f, 0, 0)) * m;
    ASSERT_TRUE(crowd.setLivePose(ha, pose).isOk());
    for (glm::mat4& m : pose) m = glm::translate(glm::mat4(1.0f), glm::vec3(60.0f, 0, 0)) * m;
    ASSERT_TRUE(crowd.setLivePose(hh, pose).isOk());  // Drawn 30 m away, its clip here.
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    const Span<const InstanceHandle> seen = crowd.view().visibleHandles();
    EXPECT_EQ(std::count(seen.begin(), seen.end(), ha), bounded ? 1 : 0);
    EXPECT_EQ(std::count(seen.begin(), seen.end(), hh), 1);
  }
}

// An impostor shows its clip's frames: an instance holding a live pose takes the last mesh
// level where it would take the impostor's, and the impostor again once its pose is cleared.
TEST(LivePoseBounds, APoseStaysAMeshWhereItsClipWouldBeAnImpostor) {
  CrowdDesc cd = test::liveDesc(1);
  ASSERT_GE(cd.lod_count, 3u);
  cd.impostor_lod = cd.lod_count - 1;
  cd.max_distance_radii = -1.0f;  // No far line.
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(0.0, 0.0, -400.0);  // Past every LOD line.
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = test::testCamera({0.0, 1.5, 6.0}, {0.0, 1.0, -400.0});
  const auto levelDrawn = [&]() {
    EXPECT_TRUE(crowd.update(0.0, camera).isOk());
    const CrowdFrameStats& s = crowd.view().stats();
    for (uint32_t lod = 0; lod < cd.lod_count; ++lod)
      if (s.per_lod[lod] == 1u) return lod;
    return cd.lod_count;
  };
  EXPECT_EQ(levelDrawn(), cd.impostor_lod);
  ASSERT_TRUE(crowd.setLivePose(h, clipFrame(*cd.palette, 0, 3)).isOk());
  EXPECT_EQ(levelDrawn(), cd.impostor_lod - 1);
  ASSERT_TRUE(crowd.clearLivePose(h).isOk());
  EXPECT_EQ(levelDrawn(), cd.impostor_lod);
}

}  // namespace
}  // namespace si
