// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::CrowdExport: what GPU-driven selection (si::gl, Renderer::drawCrowdGpuCulled) reads of a
/// crowd and its views, as the plain std430 structs of gpu_crowd_state.h: every instance's
/// state, overlays and 2D blend layers, live poses, the clips, which instances changed since a
/// version, and per view its LOD lines (CullParams) and the LODs its hysteresis starts from. A
/// renderer of the engine's own that culls on the GPU reads the same; an application that draws
/// through CrowdView's selection never needs it. No GPU and no allocation of its own.
///
/// Usage (what the GL back-end does each frame):
/// \code
///   si::CrowdExport out(crowd);
///   if (out.stateVersion() != uploaded_version) {
///     out.changedSince(uploaded_version, &changed, &placed);   // runs of dense indices
///     states.resize(count of changed);                         // the runs, one after another
///     out.state(changed, states.data(), nullptr);
///     uploaded_version = out.stateVersion();
///   }
///   si::CullParams params = si::CrowdExport::cullParams(view, camera);
/// \endcode

#include <cstdint>
#include <vector>

#include "si/core/span.h"
#include "si/crowd/camera.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/handle_pool.h"

namespace si {

class CrowdManager;
class CrowdView;

/// A read-only window on one crowd's GPU-facing state. Cheap to make (one pointer); valid
/// while the crowd lives. Dense index i is the i-th live instance in the crowd's storage order
/// (the order of state()); it changes when instances are removed (the last moves into the gap).
class CrowdExport {
 public:
  explicit CrowdExport(const CrowdManager& crowd) : crowd_(&crowd) {}

  /// Changes whenever exported state changes (init, add, remove, setters, play, crossfade,
  /// overlays, blends, setLodDistances, root motion moving an instance); not when a selection
  /// moves LODs (the GPU does the same) or a crossfade runs out (its end is read from the clock).
  /// A live pose changes it when the instance takes or frees its slot; a pose set again on a
  /// held slot changes livePoseVersion() only. Unique across all crowds of the process: a new crowd
  /// never repeats an old one's version.
  uint64_t stateVersion() const;
  /// Every instance's state in dense order (`handles`, may be null, receives the handles in the
  /// same order): index i of the GPU's selection is dense index i.
  void state(std::vector<GpuInstanceState>* out, std::vector<InstanceHandle>* handles) const;
  /// The instances of the dense index runs `runs` (changedSince()'s, say) as state() exports
  /// them, one run after another into `out` (as many entries as the runs' counts add up to)
  /// and, when not null, their handles into `handles`. Every run must lie within the crowd's
  /// size() (nothing is written otherwise). Churn scatters the runs over the crowd: the reads
  /// are prefetched ahead, and past 512 indices the work runs on CrowdDesc::worker_threads
  /// threads (the output does not depend on their number). overlays() and extraLayers() do the
  /// same. Each entry of `out` is written once and never read, so `out` may be a
  /// write-combined mapping (a staging buffer): the GPU-driven path exports into its staging
  /// ring so. A single run: `state(si::Span<const si::DenseRange>(&run, 1), ...)`.
  void state(Span<const DenseRange> runs, GpuInstanceState* out, InstanceHandle* handles) const;
  /// Which dense indices changed since the crowd's stateVersion() was `since` (a version it
  /// returned earlier, under the same CrowdManager::identity()): into `changed`, the indices
  /// whose exported state (state(), overlays(), extraLayers()) changed after it; into `placed`
  /// (may be null), those holding another instance than then (added, or moved there by a
  /// removal: what is kept per index must start over there). Both sorted, within size(), as
  /// runs of adjacent indices (a run costs a GPU-driven upload a 16-byte table entry, less than
  /// one unchanged instance uploaded again). A `since` of 0 gives everything. Cost: asked with
  /// the version the last call was made at (one consumer asking every frame), the changes
  /// since, kept as bits while they were made (O(changed words of 64 indices)); else a log of
  /// the recent changes while under an eighth of the indices changed, else O(size() / 1024)
  /// plus the changed chunks. Calls on several threads at once are safe (as every const call).
  void changedSince(uint64_t since, std::vector<DenseRange>* changed,
                    std::vector<DenseRange>* placed) const;
  /// The palette's clips as the GPU reads them, and the frame times of non-uniform clips (then
  /// the interval modes of cubic clips, as small whole numbers: GpuClipInfo::modes_offset).
  void clips(std::vector<GpuClipInfo>* clips, std::vector<double>* frame_times) const;

  /// Whether overlays() exports anything: some instance holds an overlay (playing or faded
  /// out).
  bool playsOverlays() const;
  /// Every instance's overlay in dense order, or nothing (`out` emptied) while no instance
  /// plays one: what GPU-driven culling needs to write the layer records.
  void overlays(std::vector<GpuOverlayState>* out) const;
  /// The overlays of the dense index runs `runs`, one run after another into `out` (a zero
  /// entry where none plays), every run within size().
  void overlays(Span<const DenseRange> runs, GpuOverlayState* out) const;
  /// Whether selections write extra layer records: the crowd holds a 2D blend space and some
  /// instance holds an overlay.
  bool writesExtraLayers() const;
  /// 2D blends: kExtraLayerRecords entries per instance in dense order, each extra layer as
  /// its own overlay state (on the overlay's mask, fading over the overlay's span), from which
  /// the GPU writes CrowdView::extraLayerRecords() as a selection does; nothing (`out`
  /// emptied) unless writesExtraLayers().
  void extraLayers(std::vector<GpuOverlayState>* out) const;
  /// The extra layers of the dense index runs `runs` into `out` (kExtraLayerRecords entries
  /// per index, the runs one after another), every run within size().
  void extraLayers(Span<const DenseRange> runs, GpuOverlayState* out) const;

  /// Live poses (CrowdManager::setLivePose): the texels of 2 x CrowdDesc::live_pose_capacity
  /// frames (each pose's current and previous) in the palette's format, which a renderer places
  /// after the palette's texels (at livePoseFirstTexel(), the palette texture's texel count) so
  /// that records of posed instances read them as they read a baked frame. Empty without live
  /// poses.
  Span<const uint8_t> livePoseTexels() const;
  uint32_t livePoseFirstTexel() const;
  /// The live texels written after livePoseVersion() was `since` (0: all of them), as one span
  /// of livePoseTexels() counted in texels: [*first, *first + *count), count 0 for none. What a
  /// renderer that uploaded the texels at `since` uploads again; poses set in one crowd step lie
  /// together (about half the texels when every pose changes).
  void livePoseTexelsChangedSince(uint64_t since, uint32_t* first, uint32_t* count) const;
  /// Copies the live texels [first, first + count) of livePoseTexels() (counted in texels: the
  /// span livePoseTexelsChangedSince() gave, say) into `out`. Each byte of `out` is written
  /// once and never read, so `out` may be a write-combined mapping (a staging buffer: the GL
  /// renderer copies so). Past 256 KiB the copy is cut into tasks on
  /// CrowdDesc::worker_threads threads (1,000 poses of 60 joints are 2.9 MB of float texels).
  /// Nothing is written when the span passes livePoseTexels() or `out` is null.
  void copyLivePoseTexels(uint32_t first, uint32_t count, uint8_t* out) const;
  /// Changes whenever the live texels do (a renderer uploads them again when it has moved).
  uint64_t livePoseVersion() const;
  /// Live poses held now (those handing back to their clips included).
  uint32_t livePoseCount() const;
  /// Every live pose slot (CrowdDesc::live_pose_capacity of them, held or not), in slot order:
  /// its current frame and its hand-over, which GpuInstanceState::live_pose names. GPU-driven
  /// culling writes a posed instance's record from it as update() does; it changes with
  /// livePoseVersion().
  void livePoses(std::vector<GpuLivePose>* out) const;
  /// The slots of the runs `slots` (each within CrowdDesc::live_pose_capacity) into `out`, the
  /// runs one after another, each slot written whole and once (so `out` may be a staging ring's
  /// write-combined mapping: the GL renderer exports straight into it).
  void livePoses(Span<const DenseRange> slots, GpuLivePose* out) const;

  /// The selection parameters of `view` for `camera`: the crowd's LOD lines and far line with
  /// the view's rules applied (CrowdViewDesc), what CrowdView::select() uses. Default
  /// parameters for a detached view.
  static CullParams cullParams(const CrowdView& view, const Camera& camera);
  /// The view's LOD per instance in dense order, before its lod_bias: the hysteresis state its
  /// last selection left, which GPU-driven culling starts from. Empty when detached.
  static void lods(const CrowdView& view, std::vector<uint32_t>* out);
  /// The same for the dense index runs `runs` only, one run after another into `out`: what a
  /// GPU-driven draw re-seeds where instances were added or moved. Nothing is written when a
  /// run passes the crowd's size or the view is detached.
  static void lods(const CrowdView& view, Span<const DenseRange> runs, uint32_t* out);

 private:
  size_t indicesIn(Span<const DenseRange> runs, const void* out) const;
  const CrowdManager* crowd_;
};

}  // namespace si
