// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Live poses (CrowdManager::setLivePose): the frames of palette texels, two per posed
// instance, that the engine writes and the instances' records point at. They follow the
// palette's texels (their first texel is the palette texture's texel count) in its format, so
// every path reads them as it reads a baked frame (each slot's first frames, then each slot's
// second, so that the poses of a step lie together). A slot's two frames take turns: the first
// write of a crowd step goes to the frame the last step's records did not name, so the
// previous records (motion vectors) still read the previous pose. No GL.

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/live_pose_rows.h"
#include "si/core/baked_palette.h"
#include "si/core/bounds.h"
#include "si/core/span.h"
#include "si/core/status.h"
#include "si/crowd/handle_pool.h"

namespace si::detail {

/// An instance's slot when it has no live pose.
inline constexpr uint32_t kNoLivePose = 0xFFFFFFFFu;

class LivePoses {
 public:
  /// Room for `capacity` poses of `palette`'s frames (none for 0). kUnsupported for a
  /// quaternion palette, kLimitExceeded when the texels would pass 2^32.
  Status reset(const BakedPalette* palette, uint32_t capacity);
  uint32_t capacity() const { return capacity_; }
  /// Poses held.
  uint32_t count() const { return capacity_ - uint32_t(free_.size()); }
  /// A free slot for instance `owner` into `slot`, drawn wholly live (weight 1); kLimitExceeded
  /// when all are taken.
  Status take(InstanceHandle owner, uint32_t* slot);
  void release(uint32_t slot);

  // The hand-over (CrowdManager::setLivePose and clearLivePose with a blend): each slot's live
  // weight fades linearly from `from` to `to` over a span of the crowd clock; 1 draws the live
  // pose alone, 0 the clip alone.
  struct Fade {
    float from = 1.0f, to = 1.0f;
    double start = 0.0, duration = 0.0;
  };
  /// Slot `slot`'s fade (CrowdExport::livePoses exports it for GPU-driven culling).
  const Fade& fadeOf(uint32_t slot) const { return fades_[slot]; }
  /// Slot `slot`'s live weight fades from `from` to `to` over `seconds` from `clock` (0: at once).
  void fade(uint32_t slot, float from, float to, double seconds, double clock);
  /// Slot `slot`'s live weight at `clock`.
  float liveWeight(uint32_t slot, double clock) const;
  /// The weight of the record's clip (1 - the live weight) at `clock`, as the record carries it.
  float clipWeight(uint32_t slot, double clock) const { return 1.0f - liveWeight(slot, clock); }
  /// Whether slot `slot` fades towards 0 (released when it gets there).
  bool fadingOut(uint32_t slot) const { return fades_[slot].to == 0.0f; }
  /// The owners of the slots that have faded out by `clock` (each to be released by its owner).
  void fadedOut(double clock, std::vector<InstanceHandle>* owners) const;
  /// Slots fading out now.
  uint32_t fadingOutCount() const { return fading_out_; }
  /// Writes slot `slot`'s frame in crowd step `step` (CrowdState::steps): `skinning` (one
  /// model-space matrix per palette joint) in the palette's format, then the morph weights of
  /// baked frame `weights_frame_texel`; into its other frame when the last write was in another
  /// step, else over the same one. Checked as it is stored: returns the first matrix the
  /// palette cannot hold (firstBadJointReference's, with the format's range), leaving the slot
  /// as it was, or skinning.size() when written.
  size_t write(uint32_t slot, Span<const glm::mat4> skinning, uint32_t weights_frame_texel,
               uint64_t step);
  // write() in steps, so that the poses of a batch (CrowdManager::setLivePoses) are stored
  // and committed on several threads, each slot by one of them: where slot `slot`'s pose of
  // step `step` can be stored straight (its other frame, which nothing names), or nullptr when
  // it goes over its current frame (write() alone, through scratch); then store() (write()'s
  // check and store, returning the first bad matrix) and, for a pose stored whole, poseBounds()
  // of its box; then commit() with its bounds and the batch's version (batchVersion(), the same
  // for every pose of the batch); once all are committed, on one thread, endBatch().
  uint8_t* directFrame(uint32_t slot, uint64_t step);
  size_t store(Span<const glm::mat4> skinning, uint8_t* frame, Aabb* box) const;
  /// What bounds slot `slot`'s current pose, in the instance's model space (storePose's box of
  /// the palette's joint bounds, padded for the format's rounding; the sphere around the box as a
  /// baked clip's). `known` is false for a palette without joint bounds (the clip's sphere
  /// culls it then).
  struct Bounds {
    Aabb box;
    Sphere sphere;
    bool known = false;
  };
  const Bounds& boundsOf(uint32_t slot) const { return bounds_[slot]; }
  /// *bounds set for a pose whose unpadded box (store()'s) is `box`: padded for the format's
  /// rounding, its sphere the one a baked clip's box gets (empty box: none known).
  void poseBounds(const Aabb& box, Bounds* bounds) const;
  /// Makes the pose stored whole into directFrame() (its bounds poseBounds()') slot `slot`'s
  /// current one, written at `version` (batchVersion()'s). Any thread, one per slot.
  void commit(uint32_t slot, const Bounds& bounds, uint32_t weights_frame_texel, uint64_t step,
              uint64_t version);
  /// The version a batch's commits carry: the next one.
  uint64_t batchVersion() const { return version_ + 1; }
  /// After a batch's commits at `version`: version() moves on to it.
  void endBatch(uint64_t version) { version_ = std::max(version_, version); }
  /// The first texel of slot `slot`'s current frame, as a record's frames name it.
  uint32_t frameTexel(uint32_t slot) const { return first_texel_ + frameOf(slot) * stride_; }
  /// Palette joint `joint`'s matrix of slot `slot`'s current frame as the shader reads it (half
  /// floats widened).
  glm::mat4 matrix(uint32_t slot, uint32_t joint) const;
  uint32_t firstTexel() const { return first_texel_; }
  Span<const uint8_t> texels() const { return texels_; }
  /// The texels written after version `since` (a version() seen before; 0: every texel), as
  /// one span of texels() in texels: [*first, *first + *count). The frames of one side lie
  /// together (side 0's, then side 1's), so poses set in one step take one side's span.
  void changedTexels(uint64_t since, uint32_t* first, uint32_t* count) const;
  /// Changes with every write, fade and release (a consumer uploads again when it has moved).
  uint64_t version() const { return version_; }

 private:
  const BakedPalette* palette_ = nullptr;
  uint32_t capacity_ = 0;
  uint32_t first_texel_ = 0;
  uint32_t stride_ = 0;  // Texels per frame (the palette's frame stride).
  std::vector<uint32_t> free_;
  std::vector<Fade> fades_;             // Per slot.
  std::vector<Bounds> bounds_;          // Per slot: of its current frame.
  std::vector<JointBox> joint_boxes_;   // The palette's joint bounds (none: empty).
  std::vector<InstanceHandle> owners_;  // Per slot.
  std::vector<uint8_t> sides_;          // Per slot: which of its two frames is current.
  std::vector<uint64_t> frame_versions_;  // Per frame: the version of its last write (0: none).
  // The bytes of frame `frame_index` (side 0's frames, then side 1's).
  uint8_t* frameBytes(uint32_t frame_index);
  // commit()'s rest: the frame made current and marked written at `version`, the morph
  // weights copied.
  void settle(uint32_t slot, bool direct, uint32_t weights_frame_texel, uint64_t step,
              uint64_t version);
  // Slot `slot`'s current frame: side 0's frames first (one per slot), then side 1's.
  uint32_t frameOf(uint32_t slot) const { return sides_[slot] * capacity_ + slot; }
  std::vector<uint64_t> written_;       // Per slot: the step of its last write (kNever: none).
  static constexpr uint64_t kNever = ~uint64_t(0);
  uint32_t fading_out_ = 0;
  std::vector<uint8_t> texels_;
  std::vector<uint8_t> scratch_;  // A pose written over a current frame, until checked.
  uint64_t version_ = 0;
};

}  // namespace si::detail
