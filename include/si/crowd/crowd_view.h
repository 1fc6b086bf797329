// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::CrowdView: one camera's selection of a crowd. A frame draws a crowd several times (the
/// main camera, shadow cascades, a second player, a reflection); each view culls, picks LODs
/// (with its own hysteresis) and buckets the records for its own camera, while the crowd
/// advances once per frame (CrowdManager::advance: clock, playback, crossfades, events, root
/// motion). Views are independent of each other and of their order.
///
/// A frame with a main view and three shadow cascades:
/// \code
///   si::CrowdView main_view, cascade[3];
///   main_view.init(crowd);
///   si::CrowdViewDesc shadow;
///   shadow.lod_bias = 1;                  // one LOD coarser in the shadow maps
///   shadow.max_distance_radii = -1.0f;    // the cascade's own frustum is the far line
///   for (si::CrowdView& c : cascade) c.init(crowd, shadow);
///   // every frame:
///   crowd.advance(dt);                    // once
///   main_view.select(camera);
///   for (int i = 0; i < 3; ++i) cascade[i].select(light_camera[i]);
///   // then draw each view: Renderer::drawCrowd(view, batcher, view_camera, ...)
/// \endcode
///
/// CrowdManager::update(dt, camera) is advance(dt) and the selection of the crowd's own view
/// (CrowdManager::view()) in one pass; a CrowdView given the same camera selects exactly the same
/// records, buckets, LODs and statistics.

#include <cstdint>
#include <memory>
#include <vector>

#include "si/core/span.h"
#include "si/core/status.h"
#include "si/crowd/camera.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_record.h"
#include "si/crowd/parallel_for.h"

namespace si {

class CrowdManager;
namespace detail {
struct ViewState;
}

/// Statistics of one selection (CrowdManager::update(), CrowdView::select()).
struct CrowdFrameStats {
  uint32_t instances = 0;
  uint32_t visible = 0;
  uint32_t culled_frustum = 0;
  uint32_t culled_distance = 0;
  uint32_t per_lod[8] = {};  ///< Visible instances per LOD.
  uint32_t bucket_entries = 0;  ///< Sum over buckets (instances x worn sub-meshes).
};

/// A run of consecutive records of one bucket: records()[first .. first + count).
struct RecordRun {
  uint32_t first = 0;
  uint32_t count = 0;
};

/// A view's own selection rules. Zero fields take the crowd's.
struct CrowdViewDesc {
  /// Drawn LODs are this many levels coarser than the view's distance (or screen-error) LOD,
  /// clamped to the coarsest: shadow cascades usually want coarser meshes. 0 to 7.
  uint32_t lod_bias = 0;
  /// The crowd's LOD lines times this (> 0; 0 means 1): 0.5 brings every LOD in to half the
  /// distance. Hysteresis and the far line are unchanged.
  float lod_distance_scale = 0.0f;
  /// The view's far line in radii; 0 means the crowd's CrowdDesc::max_distance_radii, negative
  /// means none (a shadow cascade whose camera sits far up the light: its frustum culls).
  float max_distance_radii = 0.0f;
  /// Keep the previous selection's records for motion vectors (as CrowdDesc::previous_records,
  /// which the crowd's own view follows). Off by default.
  bool previous_records = false;
};

/// One camera's culling, LODs and buckets of a CrowdManager's instances; the crowd's own view
/// (CrowdManager::view()) is one too. Every selection is read here. Movable, not copyable. A view
/// follows its crowd through moves; when the crowd is destroyed or init() again, the view is
/// detached: select() fails until the view is init() again, and its accessors give what it last
/// selected. One call at a time on a crowd and its views.
class CrowdView {
 public:
  CrowdView();
  ~CrowdView();
  CrowdView(CrowdView&&) noexcept;
  CrowdView& operator=(CrowdView&&) noexcept;
  CrowdView(const CrowdView&) = delete;
  CrowdView& operator=(const CrowdView&) = delete;

  /// Attaches the view to an initialized crowd (detaching it from any other). Every instance
  /// starts at LOD 0 with no previous record, as in a new crowd. kInvalidArgument for a crowd
  /// without init(), a lod_bias above 7, a lod_distance_scale negative or not finite, a
  /// max_distance_radii not finite; the view is unchanged then.
  Status init(CrowdManager& crowd, const CrowdViewDesc& desc = CrowdViewDesc());
  /// Whether the view is attached to a crowd (init() succeeded and the crowd lives and was not
  /// init() again since).
  bool attached() const;
  /// The crowd the view selects from, or null when detached.
  const CrowdManager* crowd() const;
  /// The view's rules (the crowd's own view: previous_records as CrowdDesc's, no other rule).
  const CrowdViewDesc& desc() const;
  /// The crowd's sub-mesh and LOD counts when the view was init() (bucket b = lod *
  /// subMeshCount() + sub-mesh); 0 before.
  uint32_t subMeshCount() const;
  uint32_t lodCount() const;

  /// Culls the crowd's instances against `camera` and the far line, picks their LODs from this
  /// view's last ones, and buckets the visible ones with their records, at the crowd's clock
  /// (call CrowdManager::advance() once per frame first). Moves no instance and reports no
  /// event. kInvalidArgument when detached. Runs on the crowd's worker threads
  /// (CrowdDesc::worker_threads); the output does not depend on their number.
  ///
  /// Threads: different views of one crowd may select on several threads at once (shadow
  /// cascades in parallel), while nothing changes the crowd (its setters, update(), advance(),
  /// views attached or detached): each writes only its own selection. One section at a time
  /// uses the crowd's workers; the other views' selections run on their own threads. Given a
  /// `parallel_for` (parallel_for.h), its tasks run there instead.
  Status select(const Camera& camera, const ParallelFor& parallel_for = {});

  // ---- The last selection ----
  /// Its statistics.
  const CrowdFrameStats& stats() const;
  /// Buckets: bucket b = lod * subMeshCount() + sub_mesh holds
  /// bucketEntries()[bucketOffsets()[b] .. bucketOffsets()[b + 1]), indices into records()
  /// in increasing order.
  uint32_t bucketCount() const;
  const std::vector<uint32_t>& bucketOffsets() const;
  /// Expanded from the runs on the first call after a selection (so a caller that reads the
  /// runs pays nothing for it).
  const std::vector<uint32_t>& bucketEntries() const;
  /// The same buckets as runs of consecutive records: bucket b is
  /// bucketRuns()[bucketRunOffsets()[b] .. bucketRunOffsets()[b + 1]), runs in increasing
  /// order. The records lie sorted by (LOD, worn variation mask, dense order), so while a frame
  /// has at most 64 distinct worn masks a bucket has at most one run per mask, and a sub-mesh
  /// every instance wears is one run per LOD. Past 64 masks the records of a LOD are in dense
  /// order and the runs are whatever consecutive instances wear the sub-mesh.
  const std::vector<uint32_t>& bucketRunOffsets() const;
  const std::vector<RecordRun>& bucketRuns() const;
  /// One record per visible instance, sorted by (LOD, worn variation mask, dense order); each
  /// is written once, whatever sub-meshes the instance wears. Relative to camera()'s position.
  Span<const InstanceRecord> records() const;
  /// Handle of each visible instance, parallel to records().
  Span<const InstanceHandle> visibleHandles() const;
  /// Parallel to records(): each drawn instance's overlay (a zero record, weight 0, where it
  /// plays none). Empty when no instance of the crowd had played one then: crowds without
  /// layered animation write nothing and pay nothing.
  Span<const LayerRecord> layerRecords() const;
  /// Once the crowd holds a 2D blend space (CrowdManager::addBlendSpace), kExtraLayerRecords
  /// per record of records(): a 2D blend's third and fourth clips, composed after the overlay
  /// on its mask (zero records, weight 0, where an instance draws none; its layer record's
  /// kLayerExtrasBit says it draws them). Empty before, and when layerRecords() is.
  Span<const LayerRecord> extraLayerRecords() const;
  /// Motion vectors (CrowdViewDesc::previous_records; CrowdDesc::previous_records for the
  /// crowd's own view), else empty: the previous selection's records, exactly as records()
  /// gave them then, relative to previousCamera()'s position.
  Span<const InstanceRecord> previousRecords() const;
  /// Parallel to records(): the index in previousRecords() of the same instance's record, or
  /// kNoPreviousRecord where there is none: the instance was not drawn by this view's previous
  /// selection (culled, or added since) or was placed by setTransform() since (a teleport: no
  /// motion). A renderer skins the vertex with the previous record too, for its previous
  /// position; a LOD change needs no fallback (the previous record skins the current LOD's
  /// vertex), nor does a crossfade or a new clip (the record holds what was drawn).
  Span<const uint32_t> previousRecordIndices() const;
  /// The previous selection's layer records, parallel to previousRecords() (empty when that
  /// selection wrote none): motion vectors of overlays.
  Span<const LayerRecord> previousLayerRecords() const;
  /// The same of extraLayerRecords(), parallel to previousLayerRecords().
  Span<const LayerRecord> previousExtraLayerRecords() const;
  /// The camera of the last selection (records are relative to its position) and of the one
  /// before it (after the first, the last one's). Renderers project previous positions with
  /// previousCamera() (Renderer motion vectors, InstanceBatcher::buildPrevious).
  const Camera& camera() const;
  const Camera& previousCamera() const;
  // ---- For GPU-driven culling (Renderer::drawCrowdGpuCulled of a view; CrowdExport) ----
  /// This view since its last init() (the crowd's own view: since the crowd's init()): unique
  /// across all views, crowds and init() calls of the process; 0 for a view never init().
  /// What a GPU-driven renderer keeps per view (LODs, visibility history, drawn records) belongs
  /// to this identity.
  uint64_t identity() const;
  /// Selections (select(); the crowd's own view: update()) since init(). With identity() it
  /// names the records: selection n's records() are selection n + 1's previousRecords(), byte
  /// for byte, so a renderer that kept where it uploaded them can read them there again.
  uint64_t selectionCount() const;

  /// The LOD the instance was drawn at by the last selection, lod_bias included (kNotFound for
  /// a stale handle, kInvalidArgument when detached).
  Status lodOf(InstanceHandle h, uint32_t* lod) const;

 private:
  friend class CrowdManager;
  friend class CrowdExport;
  static const detail::ViewState& emptyView();
  const detail::ViewState& view() const;
  std::unique_ptr<detail::ViewState> state_;
};

}  // namespace si
