// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// si::crowd: the CPU half of skinned instancing. CrowdManager owns every instance's state in
/// structure-of-arrays form and, each frame, advances time, picks a LOD by distance, culls
/// against the camera and buckets the survivors per (LOD, sub-mesh); InstanceBatcher
/// (instance_batcher.h) splits the buckets into uniform-block-sized batches of std140 records.
/// No GPU is needed: the GPU's limits arrive as plain numbers. Its options (crowd_desc.h), an
/// instance's description (instance_desc.h), animation events (animation_event.h) and views
/// (crowd_view.h) have headers of their own.
///
/// Usage:
/// \code
///   si::CrowdDesc desc;
///   desc.palette = &palette;                      // from si::bakePalette or si::loadPalette
///   desc.sub_mesh_count = 4;
///   desc.lod_count = 3;
///   si::CrowdManager crowd;
///   si::Status s = crowd.init(desc);
///   si::InstanceDesc one;
///   one.position = {10.0, 0.0, 5.0};
///   one.clip = uint32_t(palette.findClip("walk"));
///   si::InstanceHandle h;
///   s = crowd.add(one, &h);
///   crowd.update(1.0 / 60.0, camera);             // every frame
///   // then InstanceBatcher::build(crowd, ...) and one draw per batch.
/// \endcode

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "si/core/baked_palette.h"
#include "si/core/layer_mask.h"
#include "si/core/prop.h"
#include "si/core/skeleton.h"
#include "si/core/transform.h"
#include "si/crowd/animation_event.h"
#include "si/crowd/blend_space.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_desc.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/gpu_crowd_state.h"
#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_desc.h"
#include "si/crowd/instance_record.h"
#include "si/crowd/parallel_for.h"

namespace si {

namespace detail {
struct CrowdState;
}

/// Owns instance state and produces, each frame, the visible instances bucketed per
/// (LOD, sub-mesh) with their shader records. Not thread-safe; one update at a time. Movable,
/// not copyable.
///
/// A crowd simulates once per frame and selects for any number of cameras: update(dt, camera)
/// does both for the crowd's own view (view(), where the selection is read); frames
/// drawn from several cameras (shadow cascades, split screen) call advance(dt) once, then
/// CrowdView::select for each view (crowd_view.h).
class CrowdManager {
 public:
  CrowdManager();
  ~CrowdManager();
  /// Moving keeps the crowd's views attached to it.
  CrowdManager(CrowdManager&&) noexcept;
  CrowdManager& operator=(CrowdManager&&) noexcept;
  CrowdManager(const CrowdManager&) = delete;
  CrowdManager& operator=(const CrowdManager&) = delete;

  /// Validates and adopts `desc`. Fails with kInvalidArgument naming the field: no palette, a
  /// palette that fails BakedPalette::validate() (its message included),
  /// sub_mesh_count outside 1..32, lod_count above 8, a negative or non-finite radius,
  /// lod distances not increasing or of the wrong count, an animation LOD rate <= 0, an unknown
  /// LOD mode, LOD errors of the wrong count, negative, not finite or decreasing (or missing
  /// for kScreenError), a pixel budget not finite and > 0, more than 256 worker threads.
  Status init(const CrowdDesc& desc);

  /// Adds an instance. kInvalidArgument (naming the field) for a clip out of range, a scale
  /// <= 0, a non-finite position, rotation, time or speed, a negative speed; kLimitExceeded past
  /// 2^20 instances. `out` is untouched on failure.
  Status add(const InstanceDesc& desc, InstanceHandle* out);
  /// Adds one instance per position with random variations, clip, time, heading and speed from
  /// a generator seeded with `desc.seed` (the same desc gives the same crowd). Handles are
  /// appended to `out` (may be null). Fails like add() and adds nothing then.
  Status addRandom(const RandomCrowdDesc& desc, std::vector<InstanceHandle>* out);
  /// Removes an instance in O(1). kNotFound for a stale or invalid handle.
  Status remove(InstanceHandle h);
  /// Whether `h` is a live instance.
  bool contains(InstanceHandle h) const;
  /// Number of live instances.
  uint32_t size() const;

  // Per-instance setters: kNotFound for a stale handle, kInvalidArgument for bad values.
  /// Places the instance as of the crowd clock now (root motion not yet applied is dropped): a
  /// teleport, drawn with no object motion in the next frame's motion vectors on every path.
  Status setTransform(InstanceHandle h, const glm::dvec3& position, const glm::quat& rotation,
                      float scale);
  /// Opts the instance in or out of root motion (InstanceDesc::root_motion). On: it moves from
  /// the crowd clock now on. Off: the motion up to now is applied first.
  ///
  /// How update() moves an instance that opted in: by M(u0)^-1 * M(u1), the baked motion of its
  /// playback between the unwrapped clip times of the clock it last moved at and now (one
  /// whole cycle per loop boundary crossed, so any time step gives the same path; a clip played
  /// once stops moving it at its end). During a crossfade the two clips' motions over the step
  /// are blended by the new clip's weight at the step's middle. play() and crossfade() first
  /// apply the motion of the playback they replace. update() and advance() both move them.
  /// Moving changes CrowdExport::stateVersion() (GPU-driven selection re-exports the state).
  Status setRootMotion(InstanceHandle h, bool enabled);
  /// The tint (alpha 255, as InstanceDesc::color); keeps the custom layer.
  Status setColor(InstanceHandle h, glm::u8vec4 color);
  /// The custom texture layer (as InstanceDesc::custom_layer); keeps the tint.
  Status setCustomLayer(InstanceHandle h, uint8_t custom_layer);
  Status setVariationMask(InstanceHandle h, uint32_t mask);
  /// Starts `clip` at clip-local `time_seconds` with `speed`, cancelling any crossfade.
  Status play(InstanceHandle h, uint32_t clip, double time_seconds, float speed);
  /// Blends from the current clip (which keeps playing) to `clip` over `blend_seconds` (> 0):
  /// during the blend the record carries both clips and the weight of the new one.
  Status crossfade(InstanceHandle h, uint32_t clip, double blend_seconds, double time_seconds = 0.0);
  /// The instance's current state (as an InstanceDesc) and clip-local time.
  Status get(InstanceHandle h, InstanceDesc* out) const;

  /// Advances the crowd clock by `dt_seconds` (>= 0, finite), then, as advance(dt) does, the
  /// crowd's simulation (root motion, events) and, for
  /// every instance: picks its LOD, culls it against `camera` and the far distance, and buckets
  /// the visible ones per (LOD, sub-mesh) with their records. Culled instances cost no time advance
  /// of their own: playback time is derived from the crowd clock. Returns kInvalidArgument for a
  /// bad dt. Allocates only while the crowd grows past its previous high-water mark. The work runs
  /// on CrowdDesc::worker_threads threads; the output does not depend on their number. Given a
  /// `parallel_for`, the work is cut into tasks of 4096 instances that it runs instead (on an
  /// engine's job system, say; parallel_for.h), with the same records, buckets and statistics.
  ///
  /// How to step a frame: update(dt, camera) when the CPU selects for the crowd's own view;
  /// advance(dt) when the selection is made elsewhere (CrowdView::select for several cameras,
  /// or the GPU: Renderer::drawCrowdGpuCulled).
  Status update(double dt_seconds, const Camera& camera, const ParallelFor& parallel_for = {});

  /// The frame's simulation without a selection, for frames that select with CrowdViews or on
  /// the GPU: advances the crowd clock (a compensated sum: within a few ulps of the exact one
  /// after a week of 60 Hz frames), applies root motion and reports the animation events
  /// passed (events()), each once per frame whatever the number of views. O(1) for a crowd
  /// with no root motion and no clip markers. update(dt, camera) is advance(dt) then
  /// view().select(camera), in one pass. kInvalidArgument for a dt that is negative, not
  /// finite, or would take the clock past the largest double (the crowd is unchanged then).
  /// Its tasks run on CrowdDesc::worker_threads threads, or on `parallel_for` when given.
  Status advance(double dt_seconds, const ParallelFor& parallel_for = {});
  /// The crowd's own view: what update() selects. Its selection (records, buckets, LODs,
  /// statistics, motion-vector records, layer records) is read there, and drawn from there
  /// (InstanceBatcher::build(crowd.view(), ...), Renderer::drawCrowd(id, crowd.view(), ...)).
  const CrowdView& view() const;

  // ---- Animation events ----
  /// Adds a marker at clip-local `time_seconds` of `clip`; from the next update() on, every
  /// instance whose playback passes it reports an event. A pass is counted between the crowd
  /// clock of the instance's previous update() and now: (then, now] in clip time, from a
  /// playback's start inclusive when it began since (add, play, crossfade), as many times as a
  /// looping clip wraps past it, and for the clip fading out of a crossfade until the fade
  /// ends. In a looping clip a marker at the duration is the next loop's start (it fires with
  /// one at 0). Instances whose clips have no markers cost nothing. kInvalidArgument for a clip out
  /// of range or a time outside [0, duration] or not finite; `index` (may be null) receives
  /// the marker's index.
  Status addClipMarker(uint32_t clip, double time_seconds, const std::string& name,
                       uint32_t* index = nullptr);
  /// Every marker: the palette's (BakedClip::markers, from the character's clips: a glTF
  /// file's animation extras, or Clip::markers), added by init() clip by clip, then those of
  /// addClipMarker().
  const std::vector<ClipMarker>& clipMarkers() const;
  /// The events of the last update() or advance(), by instance in dense order (the same for
  /// any thread count).
  Span<const AnimationEvent> events() const;
  /// Seconds on the crowd clock (compensated sum of every dt; a dt of 0 leaves it bitwise).
  double clockSeconds() const;

  // ---- Layered animation (si/core/layer_mask.h) ----
  /// Masks a crowd may hold.
  static constexpr uint32_t kMaxLayerMasks = 16;
  /// Adds a joint mask of the crowd's palette (si::buildLayerMask) and gives its index in
  /// `id` (may be null): the masks' ids are 0, 1, ... in the order they are added.
  /// kInvalidArgument when the mask fails mask.validate(palette) (naming why); kLimitExceeded
  /// past kMaxLayerMasks.
  Status addLayerMask(const LayerMask& mask, uint32_t* id);
  /// The masks added, in id order.
  Span<const LayerMask> layerMasks() const;
  /// Plays `clip` from clip-local `time_seconds` at `speed` on the joints of mask `mask`, over
  /// the instance's clip (which keeps playing every other joint, crossfades included). The
  /// overlay's weight fades from its current value (0 when none plays) to `weight` over
  /// `blend_seconds` (0: at once). A new overlay replaces the one playing, continuing from its
  /// weight. kNotFound for a stale handle; kInvalidArgument for a clip or mask out of range,
  /// a weight outside [0, 1], a negative or non-finite blend, a non-finite time or speed.
  Status playOverlay(InstanceHandle h, uint32_t clip, uint32_t mask, float weight,
                     double blend_seconds, double time_seconds = 0.0, float speed = 1.0f);
  /// Fades the instance's overlay to weight 0 over `blend_seconds` (0: at once); nothing when
  /// it plays none. kNotFound for a stale handle, kInvalidArgument for a negative or
  /// non-finite blend.
  Status stopOverlay(InstanceHandle h, double blend_seconds);
  // ---- Blend spaces (si/crowd/blend_space.h) ----
  /// Blend spaces a crowd may hold.
  static constexpr uint32_t kMaxBlendSpaces = 16;
  /// Adds a blend space of the crowd's palette on one of its layer masks and gives its index in
  /// `id` (may be null; ids are 0, 1, ... in order). kInvalidArgument when space.validate()
  /// fails (naming why), kLimitExceeded past kMaxBlendSpaces.
  Status addBlendSpace(const BlendSpace& space, uint32_t* id);
  /// The blend spaces added, in id order.
  Span<const BlendSpace> blendSpaces() const;
  /// Plays blend space `space` at `parameter` (clamped to its first and last positions) from
  /// `phase` (the fraction of the cycle, 0 at every clip's start) at `speed` (1: each clip at
  /// its own rate when it plays alone). With `blend_seconds` > 0 the instance crossfades into
  /// it: its clip fades to the blend's lower clip and its overlay's weight to the blend's, over
  /// that span. The blend replaces the instance's overlay; play(), crossfade(), playOverlay()
  /// and stopOverlay() end it (crossfade() fades the upper clip out over its span). Root
  /// motion travels as the clips blend. kNotFound for a stale handle; kInvalidArgument for a
  /// space out of range, a parameter, phase or speed not finite, a negative speed, a negative
  /// or non-finite blend.
  /// A 2D space's point (x, y) is clamped to its grid; a 1D space reads x alone.
  Status playBlend(InstanceHandle h, uint32_t space, BlendParameter parameter, double blend_seconds,
                   double phase = 0.0, float speed = 1.0f);
  /// Moves a blending instance to `parameter` (clamped), keeping its phase: the clips around the
  /// new value continue from the fraction of the cycle reached, at the new blended period.
  /// kNotFound for a stale handle; kInvalidArgument for a non-finite parameter or an instance
  /// that plays no blend.
  /// A 2D space reads (x, y); setBlendParameter(h, x) keeps the instance's y, and a 1D space
  /// reads x alone.
  Status setBlendParameter(InstanceHandle h, BlendParameter parameter);
  /// A blending instance's space, parameter (x, y; y 0 on a 1D space) and phase (cycles, in
  /// [0, 1) for looping clips) at the crowd clock. kNotFound for a stale handle,
  /// kInvalidArgument for an instance that plays no blend or a null output.
  Status blendState(InstanceHandle h, uint32_t* space, glm::vec2* parameter, double* phase) const;

  /// The instance's skinning matrix of skeleton joint `joint` at the crowd clock's current
  /// time, in world space (instance world * palette skinning matrix, crossfade blended, the
  /// overlay composed on its mask; at and past CrowdDesc::animation_lod_start, at the stepped
  /// times its record draws, by its LOD of the last update), from
  /// the baked palette so it matches what is drawn: it maps a bind-pose model-space point
  /// weighted to the joint to its drawn world position. Multiply by the joint's bind matrix
  /// (inverse of its inverse bind matrix) for the joint's own frame (attachments, picking).
  /// kNotFound for a stale handle, kOutOfRange for a joint not in the palette.
  Status jointMatrix(InstanceHandle h, uint32_t joint, glm::dmat4* out) const;
  /// The world frame of `socket` (si/core/prop.h) on the instance as drawn:
  /// jointMatrix(socket.joint) * socket.bind_frame, so a prop attached there (si::attachProp)
  /// is drawn at this frame times its own vertices (spawn effects, physics, hit tests at it).
  /// kNotFound for a stale handle, kOutOfRange for a socket joint not in the palette (bake
  /// after attaching the prop, or any part weighted to the joint), kInvalidArgument for a
  /// null `out`.
  Status socketTransform(InstanceHandle h, const Socket& socket, glm::dmat4* out) const;
  // ---- Live poses: the engine poses the instance (IK, ragdoll, procedural, its own runtime) ----
  /// From the next selection on, the instance draws `skinning` (one model-space skinning
  /// matrix per palette joint, in BakedPalette::palette_joints order: joint model matrix times
  /// inverse bind, as the palette stores them; si::paletteSkinning gives them from local
  /// transforms) instead of its clip, which keeps playing underneath (its morph weights, events
  /// and root motion go on; clearLivePose() returns to it). An overlay still composes over the
  /// pose on its mask. Call again to change the pose; it holds until then. From the clip, the
  /// pose fades in over `blend_seconds` (0: at once), blended per joint with the clip as a
  /// crossfade is; while it fades out (clearLivePose), it fades in again from where it is; a
  /// pose already in is just changed. The crowd writes the pose in the palette's format into
  /// one of the two frames each of its CrowdDesc::live_pose_capacity poses has
  /// (CrowdExport::livePoseTexels: the first pose set in a crowd step goes to the frame the
  /// last selection did not name, so motion vectors read the previous pose; set poses before
  /// selecting) and the record points there; jointMatrix() and socketTransform() answer with
  /// it. Every path of si::Renderer draws it (the frames uploaded after the palette's when
  /// they changed).
  /// kNotFound for a stale handle; kInvalidArgument for a crowd without live pose capacity, a
  /// negative or non-finite blend, or a matrix whose last row is not 0 0 0 1; kCountMismatch
  /// for a count other than the palette's joints; kNotFinite for a matrix that is not finite or
  /// past what the palette's format holds; kLimitExceeded when every live pose is taken (for an
  /// instance without one, before its matrices are read). A refused pose changes nothing.
  Status setLivePose(InstanceHandle h, Span<const glm::mat4> skinning, double blend_seconds = 0.0);
  /// setLivePose() for each of `handles` in order, `skinning` holding their poses one after
  /// another (handles.size() x the palette's joints), the poses stored on several threads:
  /// `parallel_for` when given, else the crowd's workers (CrowdDesc::worker_threads). The
  /// result is what the calls one by one give, a handle named twice included (its last pose
  /// holds). Each pose is set or refused as setLivePose() would; the others are set whatever
  /// one's fate, and the first refusal is returned, naming its pose ("setLivePoses: pose 7:
  /// ..."). kCountMismatch (nothing set) when the matrices are not handles.size() poses.
  Status setLivePoses(Span<const InstanceHandle> handles, Span<const glm::mat4> skinning,
                      double blend_seconds = 0.0, const ParallelFor& parallel_for = {});
  /// Back to the clip (nothing for an instance without a live pose): the clip fades in over
  /// the last pose set in `blend_seconds` (0: at once), and the pose's frame is freed when it
  /// is in (at the first update() or advance() past the blend). kNotFound for a stale handle,
  /// kInvalidArgument for a negative or non-finite blend. Removing an instance frees it too.
  Status clearLivePose(InstanceHandle h, double blend_seconds = 0.0);
  /// The instance's baked pose now (its clips as jointMatrix() computes them: crossfade,
  /// overlay and animation-LOD steps included; a live pose left out, so that what an engine
  /// sets from it each frame does not feed back), as local joint transforms of `skeleton` (the
  /// one the palette was baked from) in the instance's model space: what an engine's IK,
  /// look-at (si::applyLookAt, si/core/look_at.h) or animation runtime starts from;
  /// si::composePose gives its matrices back. Stored joints are read from the palette (a blended
  /// matrix's shear dropped: si::decomposePose); joints the palette leaves out (no vertex weighted
  /// to them) hold their rest transform. kNotFound for a stale handle; kInvalidArgument for a
  /// skeleton of another joint count or one that does not validate; kCountMismatch for `out` not of
  /// its joint count.
  Status localPose(InstanceHandle h, const Skeleton& skeleton, Span<TransformD> out) const;

  /// Switches how LODs are chosen (and the pixel budget of kScreenError; 0 means 1) from the
  /// next update() on; instances keep their LOD until hysteresis lets them move. Fails with
  /// kInvalidArgument, changing nothing, for an unknown mode, a budget that is negative or not
  /// finite, or kScreenError without lod_errors_units.
  Status setLodMode(LodMode mode, float pixel_error_budget);

  /// Moves the LOD lines (lod_count - 1 increasing distances in radii) and the far line
  /// (`max_distance_radii`: 0 keeps the current one, negative means never) from the next
  /// update() on; instances keep their current LOD until hysteresis lets them move. Fails with
  /// kInvalidArgument as init() does for these fields, and changes nothing then.
  Status setLodDistances(Span<const float> lod_distances_radii, float max_distance_radii = 0.0f);

  const CrowdDesc& desc() const { return desc_; }

  // ---- Frames (what the GPU-driven paths read: si::CrowdExport) ----
  /// The clock steps taken since init(): every update() and advance() that
  /// succeeded, dt 0 included. A step is a frame for motion vectors on every path (the
  /// GPU-driven path counts its frames by it): step once per rendered frame, with dt 0 while
  /// the clock is held (pause, photo mode, rendering faster than simulating).
  uint64_t stepCount() const;
  /// This crowd since its last init(): unique across all crowds and init() calls of the process
  /// (0 before init). What GPU-driven draws kept of a crowd (motion vectors' previous frame)
  /// belongs to this identity, so a new crowd at a reused address never inherits it.
  uint64_t identity() const;

 private:
  friend class CrowdView;
  // The step update() and advance() begin with: checks init() and dt, advances the clock.
  Status advanceClock(double dt_seconds);
  friend class CrowdExport;
  static const detail::CrowdState& emptyState();
  static Status noCrowd();
  // Instance store, clip timings, the clock, the views (src/crowd/crowd_state.h).
  std::unique_ptr<detail::CrowdState> state_;
  CrowdDesc desc_;
};

}  // namespace si
