// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// CrowdManager's private state: the instance store, the clip timings, the LOD lines, the
// crowd clock and the last frame. crowd_manager.cpp holds the API, gpu_export.cpp the export
// for GPU-driven culling, frame_builder.cpp the per-frame work.

#include <memory>
#include <vector>

#include "crowd/animation_events.h"
#include "crowd/frame_builder.h"
#include "crowd/instance_store.h"
#include "si/crowd/crowd_manager.h"

namespace si {

struct CrowdManager::State {
  detail::InstanceStore store;
  detail::CrowdFrame frame;
  std::vector<detail::ClipTiming> clips;  // Per palette clip.
  detail::MarkerTable markers;
  std::vector<float> lod_lines;           // Resolved distances in radii.
  float radius = 1.0f;
  double clock = 0.0, clock_compensation = 0.0;
  // The cameras of the last update and of the one before it (motion vectors).
  Camera camera, previous_camera;
  bool updated = false;  // Whether update() has run since init().
  std::vector<LayerMask> layer_masks;  // addLayerMask(), in id order.
  // update(dt, camera)'s own workers (CrowdDesc::worker_threads), started when first needed.
  std::unique_ptr<WorkerPool> pool;
};

namespace detail {
/// LOD levels a crowd may have (the GPU's 256 buckets hold 8 x 32).
inline constexpr uint32_t kMaxLods = 8;

/// Animation-LOD stepping of a resolved desc: the first LOD whose instances are stepped (past
/// the last LOD when off) and the step in seconds (CrowdDesc::animation_lod_start, _rate_hz).
inline uint32_t animationLodStart(const CrowdDesc& d) {
  return d.animation_lod_start == 0 ? kMaxLods : d.animation_lod_start;
}
inline double animationStepSeconds(const CrowdDesc& d) {
  return 1.0 / double(d.animation_lod_rate_hz);
}
}  // namespace detail

}  // namespace si
