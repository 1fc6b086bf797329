// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// CrowdManager's private state: the instance store, the clip timings, the LOD lines, the
// crowd clock and the views; a CrowdView's: its lane of the store and its last selection.
// crowd_manager.cpp holds the API, crowd_view.cpp the views', gpu_export.cpp the export for
// GPU-driven culling, frame_builder.cpp the per-frame work.

#include <memory>
#include <mutex>
#include <vector>

#include "crowd/animation_events.h"
#include "crowd/frame_builder.h"
#include "crowd/instance_store.h"
#include "crowd/slot_claims.h"
#include "si/core/bounds.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_view.h"

namespace si {

class CrowdManager;

namespace detail {

struct CrowdState;

/// A view's private state: which crowd and lane, its rules and its last selection.
struct ViewState {
  CrowdState* crowd = nullptr;  // Null: detached.
  uint32_t lane = 0;            // Its lane of the crowd's store (InstanceStore::views).
  CrowdViewDesc desc;  // The crowd's own view: previous_records as CrowdDesc's.
  uint32_t sub_mesh_count = 0, lod_count = 0;  // The crowd's, at init().
  CrowdFrame frame;
  // The cameras of the last selection and of the one before it (motion vectors).
  Camera camera, previous_camera;
  bool selected = false;  // Whether select() has run since init().
  uint64_t identity = 0;  // CrowdView::identity(): new at every init() (nextStateVersion()).
  uint64_t selections = 0;  // CrowdView::selectionCount(): selections since init().
};

struct CrowdState {
  CrowdState();
  ~CrowdState();  // Detaches every view still attached.
  CrowdState(const CrowdState&) = delete;
  CrowdState& operator=(const CrowdState&) = delete;

  CrowdManager* owner = nullptr;  // Kept up to date by CrowdManager's moves.
  InstanceStore store;
  std::vector<ClipTiming> clips;  // Per palette clip.
  MarkerTable markers;
  std::vector<float> lod_lines;   // Resolved distances in radii.
  float radius = 1.0f;
  double clock = 0.0, clock_compensation = 0.0;
  uint64_t steps = 0;                  // Clock steps taken (CrowdManager::stepCount()).
  std::vector<LayerMask> layer_masks;  // addLayerMask(), in id order.
  std::vector<BlendSpace> blend_spaces;  // addBlendSpace(), in id order.
  bool extra_layers = false;             // A 2D space was added: updates write extra layer records.
  // The frame's events (update() or advance()), and each chunk's while it runs.
  std::vector<AnimationEvent> events;
  std::vector<std::vector<AnimationEvent>> chunk_events;
  std::vector<ViewState*> views;  // Attached views, the crowd's own first.
  CrowdView own_view;             // Lane 0: update()'s.
  // The crowd's own workers (CrowdDesc::worker_threads), started when first needed (under
  // pool_mutex: views may select on several threads at once, each asking for them).
  std::mutex pool_mutex;
  std::unique_ptr<WorkerPool> pool;
  // setLivePoses' scratch, kept between calls: what the workers did with each pose of the
  // batch, and the batch's claims on the live slots.
  struct BatchPose {
    enum class Outcome : uint8_t {
      kInOrder,    // Set one at a time afterwards (from its clip, set again in this step).
      kStale,      // Its handle is stale (the status is found again in order).
      kCommitted,  // Stored straight into its slot's other frame and committed.
      kBad,        // Refused: matrix `bad` is one the palette cannot hold.
      kNamedTwice  // Its slot is named twice: all of the slot's poses set again in order.
    };
    Outcome outcome = Outcome::kInOrder;
    uint32_t slot = 0;
    size_t bad = 0;
  };
  std::vector<BatchPose> live_batch;
  SlotClaims live_claims;
};

/// Empties a view's selection for a crowd of `desc` (no records, empty buckets).
void resetSelection(const CrowdDesc& desc, ViewState* view);
/// The crowd's cull parameters for `camera`: its LOD lines (distances, or the screen-error
/// lines for this camera), far line, hysteresis and animation LOD (src/crowd/gpu_export.cpp).
CullParams crowdCullParams(const CrowdState& crowd, const Camera& camera);
/// The same with the view's rules (CrowdViewDesc) applied.
CullParams viewCullParams(const CrowdState& crowd, const ViewState& view, const Camera& camera);
/// What runs the crowd's tasks: its own workers (CrowdDesc::worker_threads, started when first
/// needed), or nothing (the calling thread) for one thread or a crowd of one chunk. Safe from
/// several threads at once (views selecting in parallel): WorkerPool::run lets one section use
/// the workers and runs the others' tasks on their own threads.
ParallelFor crowdParallelFor(CrowdState& crowd);
/// The crowd's own workers whatever its size (nothing for one thread): for calls whose work is
/// not the instances' (setLivePoses).
ParallelFor crowdWorkers(CrowdState& crowd);
/// What runs a call's tasks: `given` when the caller passed one (update(), advance() and
/// CrowdView::select take it), else the crowd's own (crowdParallelFor), made into `own`, which
/// must outlive the tasks.
const ParallelFor& taskRunner(CrowdState& crowd, const ParallelFor& given, ParallelFor* own);
/// The inputs of a frame of `view` at `camera` (its cull parameters and rules, the crowd's
/// state), its tasks run by `parallel_for` (which must outlive them). With `simulate` (update()
/// and advance(), which the crowd's owner calls on one thread) the frame simulates and collects
/// events into chunk_events, grown here; a view's selection (simulate false) touches nothing
/// of the crowd's but its own lane, so views of one crowd may select on several threads.
FrameInputs frameInputs(CrowdState& crowd, const ViewState& view, const Camera& camera,
                        const ParallelFor& parallel_for, bool simulate);
/// Builds the view's selection from `in` and moves its cameras on.
void selectView(const FrameInputs& in, const Camera& camera, ViewState* view);
/// The chunks' events of the frame just built, in chunk order, as the crowd's events.
void gatherEvents(CrowdState* crowd);

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
