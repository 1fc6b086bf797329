// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven path: a CrowdView's selection and records computed by compute passes over the
// crowd's state in shader storage (shaders/cull*.comp.glsl), bucketed per (LOD,
// sub-mesh); then either an indirect pre-skinning dispatch (shaders/gpu_skin.comp.glsl) and a
// vertex-pulling multi-draw, or vertex-shader skinning, each one glMultiDrawElementsIndirect.
// The selection arithmetic is src/crowd/cull_math.h's, so both select exactly the same
// instances and LODs. With overlays (layered animation) the cull pass also writes each visible
// instance's layer record, which the layered skinning programs read by visible index. With motion
// vectors it also writes each visible instance's previous record: what it drew of the same
// instance (by handle) at the previous frame, kept on the GPU, or else InstanceBatcher::
// buildPrevious's fallback. A frame is a crowd step: draws between two steps are one frame. The
// crowd's state is the path's, uploaded once for every view; what a view keeps between frames
// (LODs, visibility history, drawn records) is its own (gpu_view_slots.h). The CPU's work per
// frame does not depend on the crowd's size.

#include <array>
#include <vector>

#include "gl/paths/draw_path.h"
#include "gl/paths/gpu_view_slots.h"
#include "gl/resources/live_texels_held.h"
#include "si/gl/gpu_memory.h"

namespace si::detail {

class GpuCulledPath final : public DrawPath {
 public:
  Status prepare(const DrawResources&) override { return Status::ok(); }
  /// Uploads the crowd's state when it changed, creates the pre-skinned ring when first
  /// needed and sets the frame's parameters (the renderer has checked the crowd's palette).
  /// kInvalidArgument for more buckets than 256; kLimitExceeded past the storage-block limit.
  Status uploadFrame(const DrawResources& r, const PathFrame& frame) override;
  Status draw(const DrawResources& r, const PathFrame& frame, DrawStats* stats) override;
  void release() override;
  /// Its buffers' and its views' bytes (Renderer::gpuMemory).
  void memory(CrowdGpuMemory* out) const;

  /// After the timer read: visible instances, triangles, pre-skinned vertices and the
  /// instances skinned in the vertex shader, from the GPU's counters (both phases' with
  /// occlusion culling).
  void readCounts(const DrawResources& r, const CrowdDesc& desc, DrawStats* stats) const;
  /// The last frame's selection: (dense index, LOD) per visible instance (with occlusion
  /// culling, the second phase's only).
  Status readSelection(std::vector<glm::uvec2>* selection) const;

 private:
  // Uploads the crowd's state when it changed (or the crowd, its shape or the character did).
  Status uploadState(const DrawResources& r, const CrowdManager& crowd, uint32_t buckets);
  // The crowd's overlays, when it plays any (sets layers_).
  Status uploadOverlays(const GlInfo& info, const CrowdManager& crowd);
  // The crowd's live pose slots (CrowdExport::livePoses) when they changed: where each slot's
  // frame is and its hand-over, which the cull pass reads for posed instances.
  Status uploadLivePoses(const CrowdManager& crowd);
  // What changed since the upload of version_ (gpu_state_upload.cpp): the changed instances'
  // state and overlays; where other instances sit now, the views start over (placed_).
  Status uploadChanges(const GlInfo& info, const CrowdManager& crowd);
  Status ensureRing(const DrawResources& r, bool motion);
  // The view's slot: found or made, sized for the crowd and seeded after each upload (its LODs
  // from CrowdExport::lods, nothing visible last frame).
  Status prepareView(const PathFrame& f);
  // Motion vectors: moves the view's cameras on at a new frame, creates its drawn records and
  // the previous outputs, sets the cull pass's uniforms.
  Status prepareMotion(const DrawResources& r, const PathFrame& f);
  // Cull, commands, scatter and the draws, with the cull pass in occlusion `phase` (0 off).
  void runPasses(const DrawResources& r, const PathFrame& f, uint32_t phase, DrawStats* st);
  // Every buffer of the path's own (not its views').
  std::array<GLuint, 19> buffers() const {
    return {state_,
            clips_,
            times_,
            counters_,
            records_,
            visible_,
            entries_,
            identity_,
            commands_,
            ranges_,
            bucket_info_,
            entry_data_,
            counts_read_back_,
            overlays_,
            layers_out_,
            previous_out_,
            previous_layers_out_,
            live_poses_,
            impostor_quads_};
  }

  GLuint vao_ = kNoObject, preskin_vao_ = kNoObject;
  GLuint state_ = kNoObject, clips_ = kNoObject, times_ = kNoObject, counters_ = kNoObject;
  GLuint records_ = kNoObject, visible_ = kNoObject, entries_ = kNoObject, identity_ = kNoObject;
  GLuint commands_ = kNoObject, ranges_ = kNoObject, bucket_info_ = kNoObject;
  GLuint entry_data_ = kNoObject;
  // A crowd with an impostor level: the impostor quads pass's quads (kImpostorQuadBytes each).
  GLuint impostor_quads_ = kNoObject;
  // The counters as readCounts() reads them, copied there (a buffer the passes never write):
  // the last phase's, then with occlusion culling the first phase's (which the second phase
  // overwrites in the counters).
  GLuint counts_read_back_ = kNoObject;
  // Layered animation: the crowd's overlays (si::GpuOverlayState) and the cull pass's layer
  // record per visible instance; layers_ while the crowd plays overlays.
  // 2D blends (extras_, CrowdManager::writesExtraLayers): both hold the extra layers after
  // layer_capacity_ entries, 2 per instance (layer_copies_ 3; 1 without).
  GLuint overlays_ = kNoObject, layers_out_ = kNoObject;
  // Live poses: the crowd's slots (si::GpuLivePose), always bound (at least one entry), and
  // the crowd and version they were uploaded for.
  GLuint live_poses_ = kNoObject;
  uint32_t live_capacity_ = 0;
  LiveTexelsHeld live_held_;
  std::vector<uint8_t> live_bytes_;  // The slots when they do not fit one staged chunk.
  uint32_t layer_capacity_ = 0, layer_copies_ = 1;
  bool layers_ = false, extras_ = false;
  uint32_t compose_lanes_ = 0;  // Composed layers' invocations per record this frame; 0: none.
  // 2D blends: the extra layers' first index in overlays_ and layers_out_, and in
  // previous_layers_out_ (0: none; cull.comp.glsl's u_extras, u_previous_extras).
  uint32_t extraBase() const { return extras_ ? layer_capacity_ : 0u; }
  uint32_t previousExtraBase() const { return extras_ && motion_ ? previous_capacity_ : 0u; }
  // Motion vectors: the previous records and previous layer records per visible instance (the
  // passes' output; what each view drew is its slot's; 2D blends' previous extra layers after
  // previous_capacity_ layer records). frame_ counts the crowd steps drawn.
  GLuint previous_out_ = kNoObject, previous_layers_out_ = kNoObject;
  uint32_t previous_capacity_ = 0, slots_needed_ = 1, frame_ = 1;
  uint64_t frame_steps_ = 0;     // CrowdManager::stepCount() of the frame.
  uint64_t crowd_identity_ = 0;  // CrowdManager::identity() of its crowd (GpuCulledCrowds' key).
  bool motion_ = false, framed_ = false;
  // Per view: LODs, visibility history, drawn records, motion cameras, the depth pyramid; the
  // view of this draw (set by uploadFrame). uploads_ counts the crowd state's uploads.
  GpuViewSlots views_;
  GpuViewSlot* view_ = nullptr;
  uint64_t uploads_ = 0;
  // Every upload into the buffers the passes read: the renderer's ring (ScratchBuffers::uploads),
  // set by uploadFrame.
  UploadRing* staging_ = nullptr;
  bool two_phases_ = false;  // The last frame drew in two phases.
  // The instances every per-instance buffer holds (the state's, the overlays', each view's and
  // the previous records'): half as much again as the crowd when it outgrows them or, after a
  // peak, falls to a kShrinkFactor-th of them (from kShrinkFrom instances: below, the memory is
  // small), so a spawn wave or a wave of removals re-creates them a few times, not every frame.
  static constexpr uint32_t kShrinkFactor = 4, kShrinkFrom = 4096;
  bool shrinks(uint32_t n) const {
    return capacity_ >= kShrinkFrom && uint64_t(n) * kShrinkFactor <= capacity_;
  }
  uint32_t capacity_ = 0, instances_ = 0, buckets_ = 0, sub_meshes_ = 0;
  uint64_t version_ = 0, uploaded_identity_ = 0;
  // The dense ranges holding other instances after upload placed_upload_ (a partial one; 0
  // after a whole one): a view seeded at the upload before reseeds only these.
  std::vector<DenseRange> placed_;
  uint64_t placed_upload_ = 0;
  uint64_t uploaded_bytes_ = 0;  // Since the last draw (DrawStats::state_bytes_uploaded),
  uint64_t seed_bytes_ = 0;      // and of the view's seed (DrawStats::view_seed_bytes).
  // uploadChanges' lists and exports, kept between frames (their memory reused).
  std::vector<DenseRange> changed_runs_;
  std::vector<BufferPiece> pieces_;
  std::vector<InstanceHandle> changed_handles_;
  std::vector<uint8_t> changed_bytes_;   // Exports past one staged chunk.
  std::vector<DenseRange> placed_runs_;  // Where instances were placed (swapped into placed_).
  std::vector<uint32_t> seed_lods_;      // prepareView's, kept between frames.
  const CrowdManager* crowd_ = nullptr;
  GLuint vertex_source_ = kNoObject;  // The vertex buffer the VAOs were made for.
};

}  // namespace si::detail
