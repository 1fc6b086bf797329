// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd's instances: dense structure-of-arrays state behind generation-counted handles,
// and every change to it (add, remove, setters, play, crossfade), each validated first and
// bumping the state version. The per-frame work (frame_builder.h) reads it.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "crowd/change_log.h"
#include "crowd/changed_bits.h"
#include "crowd/instance_columns.h"
#include "crowd/instance_overlay.h"
#include "crowd/live_poses.h"
#include "crowd/playback.h"
#include "si/core/baked_palette.h"
#include "si/crowd/blend_space.h"
#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_desc.h"
#include "si/crowd/instance_record.h"

namespace si::detail {

/// A new state version, unique across every crowd of the process, so a consumer keyed on
/// (address, version) never mistakes a new crowd at a reused address for the old one.
uint64_t nextStateVersion();

/// What one view (si::CrowdView; lane 0 is the crowd's own update()) keeps per instance, in
/// dense order: the LOD its hysteresis starts from and, with previous records, each instance's
/// record index in the view's last selection and, during a selection, in the one before.
struct ViewLanes {
  std::vector<uint8_t> lods;
  std::vector<uint32_t> record_slot;
  std::vector<uint32_t> previous_slot;
  bool used = false;
};

/// Change stamps are kept per chunk of this many dense indices too (a multiple of it divides
/// the frame builder's chunks, so its parallel tasks stamp disjoint chunks).
inline constexpr uint32_t kStampChunk = 1024;

struct InstanceStore {
  /// Empties the store for instances playing `palette`'s clips.
  void reset(const BakedPalette* palette);
  uint32_t size() const { return static_cast<uint32_t>(scales.size()); }

  /// kInvalidArgument naming the field (see CrowdManager::add).
  Status validate(const InstanceDesc& d) const;
  /// Appends a validated instance under the just-allocated handle `h`, playing from `clock`.
  void push(const InstanceDesc& d, InstanceHandle h, double clock);
  /// The dense index of a live handle; kNotFound otherwise.
  Status denseIndex(InstanceHandle h, uint32_t* dense) const;
  /// The same for a query `what` writing into `out`: h's status, or kInvalidArgument for a
  /// null `out`.
  Status denseIndexFor(InstanceHandle h, const void* out, const char* what, uint32_t* dense) const;
  /// Removes in O(1) (the last instance moves into the hole).
  Status remove(InstanceHandle h);

  /// Also drops root motion not yet applied: the instance is where it is put at `clock`.
  Status setTransform(InstanceHandle h, const glm::dvec3& position, const glm::quat& rotation,
                      float scale, double clock);
  /// Opts in or out of root motion at `clock` (motion before it, when opting out, is applied).
  Status setRootMotion(InstanceHandle h, bool enabled, double clock);
  /// Sets the tint (kInvalidArgument unless its alpha is 255), keeping the custom layer.
  Status setColor(InstanceHandle h, glm::u8vec4 color);
  /// Sets the custom layer select, keeping the tint.
  Status setCustomLayer(InstanceHandle h, uint8_t custom_layer);
  Status setVariationMask(InstanceHandle h, uint32_t mask);
  // play() and crossfade() first apply the root motion of the playback they replace.
  Status play(InstanceHandle h, uint32_t clip, double time_seconds, float speed, double clock);
  Status crossfade(InstanceHandle h, uint32_t clip, double blend_seconds, double time_seconds,
                   double clock);
  /// Plays `clip` on mask `mask` over instance `h`'s clip, its weight fading from what it is
  /// now to `weight` over `blend_seconds` (0: at once); the arguments checked by the caller
  /// except the handle.
  Status playOverlay(InstanceHandle h, uint32_t clip, uint32_t mask, float weight,
                     double blend_seconds, double time_seconds, float speed, double clock);
  /// Fades `h`'s overlay out over `blend_seconds` (nothing when it has none); a blend ends.
  Status stopOverlay(InstanceHandle h, double blend_seconds, double clock);
  /// Fades dense index `i`'s overlay out over `seconds` (0: at once) from the weight it has at
  /// `clock`; a blend ends (the lower clip plays on).
  void fadeOverlayOut(uint32_t i, double seconds, double clock);
  /// Dense index `i`'s overlay about to start anew at `clock` (playOverlay, playBlend): the root
  /// motion of what it replaces applied, the overlay counted and marked active; its weight
  /// before (0 when it played none) to fade from.
  float restartOverlay(uint32_t i, double clock);
  /// Blend spaces (instance_blend.cpp; arguments checked by the caller except the handle):
  /// starts `space` (crowd id `space_id`) at `parameter` from phase `phase` (cycles), the
  /// instance's clip crossfading to the blend's first clip and the layers' weights fading to
  /// the blend's over `blend_seconds` (0: at once).
  Status playBlend(InstanceHandle h, const BlendSpace& space, uint32_t space_id,
                   glm::vec2 parameter, double blend_seconds, double phase, float speed,
                   double clock);
  /// Moves a blending instance to `parameter` on its space (of `spaces`, the crowd's), keeping
  /// its phase (kInvalidArgument when it does not blend).
  Status setBlendParameter(InstanceHandle h, const std::vector<BlendSpace>& spaces,
                           glm::vec2 parameter, double clock);
  /// Dense index `i`'s playback and layers for its blend at `parameter` from `phase` at
  /// `clock` (a crossfade or weight fade under way keeps running towards the new clips).
  void anchorBlend(uint32_t i, const BlendSpace& space, glm::vec2 parameter, double phase,
                   double clock);
  /// Ends dense index `i`'s blend, if any: its overlay fades out over `seconds` (0: at once).
  void endBlend(uint32_t i, double seconds, double clock);
  /// Every instance's events counted as reported up to `clock` (when markers first appear).
  void markEventsReported(double clock);
  /// Stamps dense index `i` with the current version: its exported state changed
  /// (CrowdExport::changedSince). `placed`: a different instance is there now.
  void stamp(uint32_t i, bool placed = false);
  /// A new version, and index `i` stamped with it and logged: what every change of one
  /// instance ends with.
  void changed(uint32_t i, bool placed = false);
  /// Runs `set(i)` on live handle `h`'s dense index and marks it changed; else h's status.
  template <class Set>
  Status change(InstanceHandle h, Set&& set) {
    uint32_t i = 0;
    const Status s = denseIndex(h, &i);
    if (s.isOk()) {
      set(i);
      changed(i);
    }
    return s;
  }
  /// A new version for stamps written from parallel tasks (root motion), which the change log
  /// does not hold: it starts after it (changedSince scans the stamps for versions before).
  void unloggedVersion();
  /// A lane for a new view (every instance at LOD 0, no previous record); its index.
  uint32_t addView();
  /// Frees a lane (lane 0, the crowd's own, is never released).
  void releaseView(uint32_t lane);
  /// Dense index `i`'s live pose released, if it has one (the instance back to its clip).
  void releaseLivePose(uint32_t i);
  /// Releases the live poses whose hand-over back to the clip is over at `clock`.
  void releaseFadedLivePoses(double clock);
  /// Whether dense index `i` crossfades at `clock`: a fade set and not yet over (the GPU's
  /// culling pass reads it so). A fade that is over stays in the columns until the next play.
  bool fading(uint32_t i, double clock) const {
    return fade_duration[i] > 0.0 && clock - fade_start[i] < fade_duration[i];
  }

  const BakedPalette* palette = nullptr;
  const std::vector<ClipTiming>* clip_timings = nullptr;  // The palette's (the crowd's State).
  HandlePool handles;
  uint64_t version = 0;
  uint64_t identity = 0;  // The version reset() gave: one per init() of one crowd.

  // Dense state; slot_to_dense maps handle slots to it. Positions and rotations one array per
  // component (the frame builder's blocks load them with vector loads).
  DVec3Columns positions;
  QuatColumns rotations;
  std::vector<float> scales;
  std::vector<uint32_t> colors;  // The record's appearance word (si::packAppearance).
  std::vector<uint32_t> masks;
  std::vector<Playback> playback;
  std::vector<Playback> fade_from;  // Valid while fading(i, clock).
  std::vector<double> fade_start;
  std::vector<double> fade_duration;  // 0 when no crossfade was set.
  // Animation events (animation_events.h): the crowd clock each instance last reported at, and
  // whether its playback started since then (reported from its start, inclusive).
  std::vector<double> events_clock;
  std::vector<uint8_t> events_new;
  // Root motion (instance_root_motion.h): whether the instance opted in, and the crowd clock it
  // last moved at; how many opted in (0: update() skips the pass).
  std::vector<uint8_t> root_motion;
  std::vector<double> motion_clock;
  uint32_t root_motion_count = 0;
  // setTransform() calls per instance (teleports): exported, so the GPU-driven path does not
  // take a record drawn at another placement as the previous one.
  std::vector<uint32_t> placements;
  // Per view (lane 0: CrowdManager::update()'s): LODs and, for motion vectors, record indices
  // (kNoPreviousRecord for none; setTransform() clears them in every lane).
  std::vector<ViewLanes> views;
  // Layered animation (instance_overlay.h): each instance's overlay, and how many ever played
  // one (0: update() writes no layer records).
  std::vector<OverlayState> overlays;
  uint32_t overlay_count = 0;
  // Live poses (CrowdManager::setLivePose): each instance's slot (kNoLivePose without one) and
  // the slots' frames.
  std::vector<uint32_t> live_slot;
  LivePoses live;
  std::vector<InstanceHandle> dense_handles;
  std::vector<uint32_t> slot_to_dense;
  // Change stamps (GPU-driven uploads in proportion to change): per dense index the version at
  // which its exported state last changed, and at which its occupant did (an instance added
  // there, or moved there by a removal); per chunk of kStampChunk indices the largest of each.
  std::vector<uint64_t> changed_at, placed_at;
  std::vector<uint64_t> chunk_changed_at, chunk_placed_at;
  // And the recent changes (changed() logs each; root motion restarts it), and the changes
  // since the last consumer took them (changed() sets each; root motion invalidates them).
  ChangeLog change_log;
  mutable PendingChanges pending;
};

/// An instance's appearance word from its desc (si::packAppearance).
inline uint32_t packAppearance(const InstanceDesc& d) {
  return si::packAppearance(d.color.r, d.color.g, d.color.b, d.custom_layer);
}
/// The tint of an appearance word (alpha 255, as it was accepted).
inline glm::u8vec4 appearanceColor(uint32_t c) {
  return glm::u8vec4(c & 0xFF, (c >> 8) & 0xFF, (c >> 16) & 0xFF, 255);
}

}  // namespace si::detail
