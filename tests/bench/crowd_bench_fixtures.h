// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the crowd's CPU benchmarks share: the embedded character's palettes, a field of
// characters, and poses for setLivePose taken from a clip.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"

namespace si::bench {

// The embedded character at 30 Hz; `moving`: with its travelling clips (root motion);
// `automatic`: baked with the default desc instead (automatic rates, frames at the keys where
// that takes fewer: non-uniform frame times, found by a search per instance).
inline const si::BakedPalette& palette(bool moving = false, bool automatic = false) {
  static const auto bake = [](bool with_moving_clips, bool default_desc) {
    si::DefaultCharacterDesc cd;
    cd.moving_clips = with_moving_clips;
    si::Character c;
    if (!si::makeDefaultCharacter(cd, &c).isOk()) std::abort();
    si::BakeDesc d;
    if (!default_desc) d.rate_mode = si::RateMode::kFixed;
    si::BakedPalette out;
    if (!si::bakePalette(c, d, &out, nullptr).isOk()) std::abort();
    return out;
  };
  static const si::BakedPalette plain = bake(false, false), travelling = bake(true, false);
  static const si::BakedPalette plain_default = bake(false, true);
  return automatic ? plain_default : moving ? travelling : plain;
}

// A square field of `count` characters 1.5 m apart, random armour, clips and times;
// `max_distance_radii` as in CrowdDesc (0: the default far line, negative: none). `motion`: 0
// any clip of the plain palette; 1 the travelling clips (walk_forward, walk_turn_left) played
// in place; 2 the same with root motion applied to every instance; 3 any clip of the plain
// character baked with the default desc (compare with 0: what non-uniform frames cost); 4 as 0,
// every instance crossfading into another clip (a 1000 s fade: it never ends while timed); 5 as
// 0 with animation-LOD stepping from LOD 1 (CrowdDesc::animation_lod_start).
inline std::unique_ptr<si::CrowdManager> field(int64_t count, float max_distance_radii,
                                               uint32_t threads, int64_t motion,
                                               bool previous_records, uint32_t live_poses = 0) {
  auto crowd = std::make_unique<si::CrowdManager>();
  si::CrowdDesc d;
  d.palette = &palette(motion == 1 || motion == 2, motion == 3);
  d.sub_mesh_count = 4;
  d.lod_count = 3;
  d.max_distance_radii = max_distance_radii;
  d.worker_threads = threads;
  d.previous_records = previous_records;
  d.live_pose_capacity = live_poses;
  if (motion == 5) d.animation_lod_start = 1;
  if (!crowd->init(d).isOk()) std::abort();
  const int64_t side = int64_t(std::ceil(std::sqrt(double(count))));
  std::vector<glm::dvec3> positions;
  for (int64_t i = 0; i < count; ++i)
    positions.push_back(glm::dvec3(double(i % side), 0.0, double(i / side)) * 1.5);
  si::RandomCrowdDesc r;
  r.positions = positions;
  r.optional_mask = 0xE;
  const uint32_t travelling[] = {uint32_t(palette(true).findClip("walk_forward")),
                                 uint32_t(palette(true).findClip("walk_turn_left"))};
  if (motion == 1 || motion == 2) r.clips = travelling;
  r.root_motion = motion == 2;
  std::vector<si::InstanceHandle> handles;
  if (!crowd->addRandom(r, &handles).isOk()) std::abort();
  if (motion == 4) {
    const uint32_t clips = uint32_t(d.palette->clips.size());
    for (size_t i = 0; i < handles.size(); ++i)
      if (!crowd->crossfade(handles[i], uint32_t(i % clips), 1000.0, 0.1 * double(i % 13)).isOk())
        std::abort();
  }
  return crowd;
}

// Poses for setLivePose: the stored matrices of clip 0's first 16 frames (repeated when it has
// fewer), one per palette joint each.
inline std::vector<std::vector<glm::mat4>> clipPoses(const si::BakedPalette& p) {
  std::vector<std::vector<glm::mat4>> poses(16, std::vector<glm::mat4>(p.palette_joints.size()));
  for (uint32_t k = 0; k < poses.size(); ++k)
    for (uint32_t j = 0; j < p.palette_joints.size(); ++j)
      poses[k][j] = si::decodeJoint(p, 0, k % p.clips[0].frame_count, j);
  return poses;
}

}  // namespace si::bench
