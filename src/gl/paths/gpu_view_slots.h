// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven path's state per view (CrowdView::identity()): what one camera's culling keeps
// from frame to frame, apart from every other view's. Each view has its own LOD per instance
// (hysteresis), its own visible-last-frame flags (two-phase occlusion), its own drawn records
// (motion vectors: what it drew of each handle at the last two frames), its own motion cameras
// and its own depth pyramid. The crowd's state, clips, overlays and the passes' outputs are the
// path's, shared by every view: N views are one upload and N cull passes.
#include <cstdint>
#include <memory>
#include <vector>

#include "gl/programs/cull_layout.h"
#include "gl/resources/depth_pyramid.h"
#include "gl/resources/upload_ring.h"
#include "si/core/status.h"
#include "si/crowd/camera.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/instance_record.h"

namespace si::detail {

struct GpuViewSlot {
  uint64_t view = 0;          // CrowdView::identity().
  uint64_t seeded_upload = 0; // The crowd upload its LODs and flags were seeded for.
  uint32_t last_frame = 0;    // The path frame (crowd step) it was last drawn in.
  // Per instance (8 bytes, cull.comp.glsl's SiViewInstances): the handle it was kept for (0:
  // seeded), the LOD before the view's bias and the visible-last-frame flag; the culling pass
  // starts a place over itself where another instance sits. `capacity` instances.
  GLuint instances = kNoObject;
  uint32_t capacity = 0;
  // Motion vectors: per handle slot and frame parity, what this view drew (SiDrawn), created at
  // its first draw with motion vectors. camera_frame is the path frame its camera was set in,
  // `frame` the path frame its cameras last moved on at.
  GLuint drawn = kNoObject;
  uint32_t drawn_slots = 0, frame = 0, camera_frame = 0;
  bool previous_known = false;
  Camera camera, previous_camera;
  glm::mat4 view_projection{1.0f}, previous_view_projection{1.0f};  // Their motion's.
  DepthPyramid pyramid;  // Occlusion culling: rebuilt at each of its draws, sized for its target.

  /// Room for `count` instances' LODs and flags (recreated, and then to be seeded, when less).
  Status ensureInstances(uint32_t count);
  /// Seeds the first `count` instances for crowd upload `upload` through `uploads`: LODs from
  /// `lods` (the view's CPU LODs in dense order; 0 past its end), none visible last frame. The
  /// upload's status (the slot stays unseeded on failure).
  Status seed(UploadRing& uploads, const std::vector<uint32_t>& lods, uint32_t count,
              uint64_t upload);
  /// The same for the instances of `ranges` only, `lods` holding theirs one range after the
  /// other (CrowdExport::lods of the ranges); the others keep what they have.
  Status seed(UploadRing& uploads, const std::vector<uint32_t>& lods,
              const std::vector<DenseRange>& ranges, uint64_t upload);
  /// Motion vectors: drawn records for at least `slots_needed` handle slots (room to grow: twice
  /// the last), all with the fallback. kLimitExceeded past `max_block_bytes`
  /// (GL_MAX_SHADER_STORAGE_BLOCK_SIZE).
  Status ensureDrawn(uint32_t slots_needed, uint64_t max_block_bytes);
  void release();
};

class GpuViewSlots {
 public:
  /// Views not drawn for more frames than this lose what they kept (their next draw starts as
  /// a new view's: LODs from CrowdExport::lods, nothing visible last frame, the motion
  /// fallback). At most kMaxViews are kept; past that the least recently drawn goes.
  static constexpr uint32_t kIdleFrames = 16, kMaxViews = 32;

  /// The slot of `view`, made when new (evicting as above at path frame `frame`). Never null.
  GpuViewSlot* find(uint64_t view, uint32_t frame);
  size_t size() const { return slots_.size(); }
  /// Every view's buffers and depth pyramid, in bytes.
  uint64_t gpuBytes() const;
  /// Forgets every view (another crowd, or the path released).
  void clear();

 private:
  std::vector<std::unique_ptr<GpuViewSlot>> slots_;
};

}  // namespace si::detail
