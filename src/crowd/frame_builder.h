// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd's per-frame work (CrowdManager::update after the clock advanced): for every
// instance its crossfade state, far-line and frustum culling, LOD with hysteresis, its record;
// then the visible instances bucketed per (LOD, sub-mesh), in a deterministic order.

#include <cstdint>
#include <vector>

#include "crowd/instance_store.h"
#include "si/crowd/crowd_manager.h"

namespace si::detail {

/// One frame's output, reused between frames (allocates only while the crowd grows).
struct CrowdFrame {
  CrowdFrameStats stats;
  std::vector<uint32_t> visible_dense;          // Dense index of each visible instance.
  std::vector<InstanceRecord> records;          // Parallel to visible_dense.
  std::vector<InstanceHandle> visible_handles;  // Parallel to visible_dense.
  std::vector<uint32_t> bucket_offsets;         // bucket_count + 1 prefix sums.
  std::vector<uint32_t> bucket_cursor;
  std::vector<uint32_t> bucket_entries;         // Indices into records.
};

/// What a frame is built from besides the instances.
struct FrameInputs {
  const BakedPalette* palette = nullptr;
  const std::vector<ClipTiming>* clips = nullptr;  // Per palette clip.
  CullParams params;                               // CrowdManager::cullParams(camera).
  glm::dvec3 camera_position{0.0};
  double clock = 0.0;                               // The crowd clock, already advanced.
  uint32_t sub_mesh_count = 1;
};

/// Builds `frame` from `store`; updates each visible instance's LOD and ends crossfades whose
/// time is over (neither changes the state version: the GPU-driven pass does the same).
void buildFrame(const FrameInputs& in, InstanceStore& store, CrowdFrame* frame);

}  // namespace si::detail
