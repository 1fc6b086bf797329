// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager's answers about an instance's pose (a joint's matrix and a socket's frame as
// drawn, the baked pose as local transforms for the engine's IK or animation runtime), and the
// live poses the engine gives it.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/palette_texel.h"
#include "core/str_cat.h"
#include "crowd/crowd_state.h"
#include "crowd/instance_overlay.h"
#include "crowd/live_pose_rows.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"

namespace si {
using detail::strCat;

namespace {
// The model-space skinning matrices of palette slots `slots` of dense instance `i` as its
// record draws them (instance world excluded), into `out`; with `live_pose` false, its clips' alone
// (a live pose left out).
void drawnSkinning(const detail::CrowdState& state, const CrowdDesc& desc, uint32_t i,
                   Span<const uint32_t> slots, bool live_pose, Span<glm::mat4> out) {
  const detail::InstanceStore& st = state.store;
  const BakedPalette& p = *desc.palette;
  const double clock = state.clock;
  // The instance's clips at the times its record draws them: held on the animation-LOD grid at
  // and past CrowdDesc::animation_lod_start (its LOD of the last update), as the records do
  // (detail::scalarRecord).
  const bool stepped = st.views[0].lods[i] >= detail::animationLodStart(desc);
  const double step_seconds = detail::animationStepSeconds(desc);
  const auto matrix = [&](const detail::Playback& pb, uint32_t at, bool step) {
    double t = detail::localTime(pb, state.clips[pb.clip], clock);
    if (step) t = detail::steppedTime(t, step_seconds);
    return emulateSkinningMatrix(p, pb.clip, sampleFrames(p.clips[pb.clip], t), at);
  };
  // A live pose alone, or handing over with the clip (frame_builder.cpp's setLiveFrame): the
  // live frame as the record's clip A, the clip's playback as its clip B, the clip's weight.
  const uint32_t live = live_pose ? st.live_slot[i] : detail::kNoLivePose;
  const float clip_weight = live != detail::kNoLivePose ? st.live.clipWeight(live, clock) : 1.0f;
  const auto base = [&](uint32_t at) {
    if (clip_weight <= 0.0f) return st.live.matrix(live, at);
    if (clip_weight < 1.0f)
      return st.live.matrix(live, at) * (1.0f - clip_weight) +
             matrix(st.playback[i], at, stepped) * clip_weight;
    glm::mat4 m = matrix(st.playback[i], at, stepped);
    if (st.fading(i, clock)) {
      const float w = float(std::clamp((clock - st.fade_start[i]) / st.fade_duration[i], 0.0, 1.0));
      m = matrix(st.fade_from[i], at, stepped) * (1.0f - w) + m * w;  // The shader blends them so.
    }
    return m;
  };
  // Layered animation: the overlay on its mask and a 2D blend's extra layers after it, at the
  // weights their records carry, as the shader composes them.
  const detail::OverlayState& o = st.overlays[i];
  LayerRecord extras[kExtraLayerRecords];
  const LayerRecord layer =
      o.active ? detail::layerRecordsOf(o, state.clips, p, clock, extras) : LayerRecord{};
  LayerPose layers[1 + kExtraLayerRecords];
  layers[0] = {[&](uint32_t at) { return matrix(o.playback, at, false); }, layerWeight(layer)};
  for (uint32_t k = 0; k < kExtraLayerRecords; ++k)
    layers[1 + k] = {[&, k](uint32_t at) { return matrix(o.extra[k].playback, at, false); },
                     layerWeight(extras[k])};
  for (size_t k = 0; k < slots.size(); ++k)
    out[k] = o.active ? emulateLayeredChain(state.layer_masks[o.mask], slots[k], base,
                                            Span<const LayerPose>(layers, 1 + kExtraLayerRecords))
                      : base(slots[k]);
}
// Why `call` (setLivePose or setLivePoses) is refused whatever its poses: a crowd without room
// for live poses, or a blend that is negative or not finite; ok otherwise.
Status liveCallRefusal(const char* call, const detail::LivePoses& live, double blend_seconds) {
  if (live.capacity() == 0)
    return {StatusCode::kInvalidArgument,
            strCat(call, ": the crowd holds no live poses (CrowdDesc::live_pose_capacity is 0)")};
  if (!std::isfinite(blend_seconds) || blend_seconds < 0.0)
    return {StatusCode::kInvalidArgument, strCat(call, ": blend_seconds must be finite and >= 0")};
  return Status::ok();
}

// Why setLivePose refuses matrix `k` of `skinning` (LivePoses::write's first bad one).
Status badLiveMatrix(PaletteFormat format, Span<const glm::mat4> skinning, size_t k) {
  const float range = detail::formatRange(format);
  const glm::mat4& m = skinning[k];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r)
      if (!(std::fabs(m[c][r]) <= range))
        return {StatusCode::kNotFinite,
                strCat("setLivePose: matrix ", k, " holds ", m[c][r], ", which the palette's ",
                       paletteFormatName(format), " texels do not")};
  return {StatusCode::kInvalidArgument,
          strCat("setLivePose: matrix ", k, "'s last row is not 0 0 0 1")};
}

// setLivePoses' poses per task on the workers.
constexpr size_t kPosesPerBatchTask = 32;

// The texel of the morph weights a live pose of instance `i` carries: its clip's frame at the
// crowd clock (the clip plays on underneath).
uint32_t liveWeightsTexel(const detail::CrowdState& state, const BakedPalette& p, uint32_t i) {
  const detail::Playback& pb = state.store.playback[i];
  uint32_t frame = 0;
  if (p.layout.morph_target_count > 0)
    frame = sampleFrames(p.clips[pb.clip], detail::localTime(pb, state.clips[pb.clip], state.clock))
                .frame;
  return p.layout.frameTexel(pb.clip, frame);
}

}  // namespace

Status CrowdManager::jointMatrix(InstanceHandle h, uint32_t joint, glm::dmat4* out) const {
  uint32_t i = 0;
  const Status s = state_ ? state_->store.denseIndexFor(h, out, "jointMatrix", &i) : noCrowd();
  if (!s.isOk()) return s;
  const detail::InstanceStore& st = state_->store;
  const BakedPalette& p = *desc_.palette;
  if (joint >= p.skeleton_to_palette.size() || p.skeleton_to_palette[joint] < 0)
    return {StatusCode::kOutOfRange,
            strCat("jointMatrix: joint ", joint, " is not in the palette")};
  const uint32_t slot = uint32_t(p.skeleton_to_palette[joint]);
  glm::mat4 m;
  drawnSkinning(*state_, desc_, i, Span<const uint32_t>(&slot, 1), true, Span<glm::mat4>(&m, 1));
  glm::dmat4 world(glm::mat3_cast(glm::dquat(st.rotations.get(i))) * double(st.scales[i]));
  world[3] = glm::dvec4(st.positions.get(i), 1.0);
  *out = world * glm::dmat4(m);
  return Status::ok();
}

Status CrowdManager::socketTransform(InstanceHandle h, const Socket& socket,
                                     glm::dmat4* out) const {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "socketTransform: out is null"};
  glm::dmat4 joint;
  const Status s = jointMatrix(h, socket.joint, &joint);
  if (!s.isOk()) return {s.code(), strCat("socketTransform '", socket.name, "': ", s.message())};
  *out = joint * glm::dmat4(socket.bind_frame);
  return Status::ok();
}

Status CrowdManager::setLivePose(InstanceHandle h, Span<const glm::mat4> skinning,
                                 double blend_seconds) {
  uint32_t i = 0;
  Status s = state_ ? state_->store.denseIndex(h, &i) : noCrowd();
  if (!s.isOk()) return s;
  detail::InstanceStore& st = state_->store;
  const BakedPalette& p = *desc_.palette;
  s = liveCallRefusal("setLivePose", st.live, blend_seconds);
  if (!s.isOk()) return s;
  if (skinning.size() != p.palette_joints.size())
    return {StatusCode::kCountMismatch,
            strCat("setLivePose: ", skinning.size(), " matrices, the palette stores ",
                   p.palette_joints.size(), " joints (BakedPalette::palette_joints)")};
  // Checked as it is stored, four values at a time (the poses of a thousand instances a frame
  // pass here); a refused matrix is then looked at again to name what is wrong with it.
  const double clock = state_->clock;
  uint32_t slot = st.live_slot[i];
  const bool from_clip = slot == detail::kNoLivePose;
  if (from_clip) {
    s = st.live.take(h, &slot);
    if (!s.isOk()) return s;
  }
  const size_t k = st.live.write(slot, skinning, liveWeightsTexel(*state_, p, i), state_->steps);
  if (k < skinning.size()) {
    if (from_clip) st.live.release(slot);
    return badLiveMatrix(p.format, skinning, k);
  }
  if (from_clip) {  // The live weight fades in from 0; the instance's state names its slot.
    st.live_slot[i] = slot;
    st.live.fade(slot, 0.0f, 1.0f, blend_seconds, clock);
    st.changed(i);
  } else if (st.live.fadingOut(slot)) {  // Handing back: it fades in again from where it is.
    st.live.fade(slot, st.live.liveWeight(slot, clock), 1.0f, blend_seconds, clock);
  }
  // A pose set again changes its slot (frame, bounds, fade: livePoseVersion), not the
  // instance's state, which the GPU-driven path would upload again for nothing.
  return Status::ok();
}

Status CrowdManager::setLivePoses(Span<const InstanceHandle> handles,
                                  Span<const glm::mat4> skinning, double blend_seconds,
                                  const ParallelFor& parallel_for) {
  if (!state_) return noCrowd();
  detail::CrowdState& cs = *state_;
  detail::InstanceStore& st = cs.store;
  const BakedPalette& p = *desc_.palette;
  const size_t joints = p.palette_joints.size();
  const Status refused = liveCallRefusal("setLivePoses", st.live, blend_seconds);
  if (!refused.isOk()) return refused;
  if (skinning.size() != handles.size() * joints)
    return {StatusCode::kCountMismatch,
            strCat("setLivePoses: ", skinning.size(), " matrices for ", handles.size(),
                   " handles of ", joints, " joints each (BakedPalette::palette_joints)")};
  const auto poseOf = [&](size_t k) {
    return Span<const glm::mat4>(skinning.data() + k * joints, joints);
  };
  // On the workers: each pose's instance found and, for a slot held since an earlier step and
  // claimed first in the batch, its pose stored straight into the slot's other frame (which
  // nothing names) and committed, all at the batch's version. Nothing else of the crowd changes
  // there. A batch with no slot held yet (every pose from its clip) skips them.
  using Outcome = detail::CrowdState::BatchPose::Outcome;
  std::vector<detail::CrowdState::BatchPose>& batch = cs.live_batch;
  batch.assign(handles.size(), detail::CrowdState::BatchPose());
  const uint64_t version = st.live.batchVersion();
  const uint64_t step = cs.steps;
  const ParallelTask store = [&](uint32_t t) {
    const size_t end = std::min(handles.size(), size_t(t + 1) * kPosesPerBatchTask);
    for (size_t k = size_t(t) * kPosesPerBatchTask; k < end; ++k) {
      detail::CrowdState::BatchPose& b = batch[k];
      uint32_t i = 0;
      if (!st.denseIndex(handles[k], &i).isOk()) {
        b.outcome = Outcome::kStale;
        continue;
      }
      b.slot = st.live_slot[i];
      if (b.slot == detail::kNoLivePose) continue;  // From its clip: in order.
      if (!cs.live_claims.claim(b.slot)) {
        b.outcome = Outcome::kNamedTwice;
        continue;
      }
      uint8_t* frame = st.live.directFrame(b.slot, step);
      if (frame == nullptr) continue;  // Set again in this step: over its frame, in order.
      Aabb box;
      b.bad = st.live.store(poseOf(k), frame, &box);
      if (b.bad < joints) {
        b.outcome = Outcome::kBad;
        continue;
      }
      detail::LivePoses::Bounds bounds;
      st.live.poseBounds(box, &bounds);
      st.live.commit(b.slot, bounds, liveWeightsTexel(cs, p, i), step, version);
      b.outcome = Outcome::kCommitted;
    }
  };
  if (st.live.count() > 0) {
    cs.live_claims.start(st.live.capacity());
    const uint32_t tasks = uint32_t((handles.size() + kPosesPerBatchTask - 1) / kPosesPerBatchTask);
    ParallelFor own;
    const ParallelFor& run = parallel_for ? parallel_for : (own = detail::crowdWorkers(cs));
    if (run && tasks > 1) {
      run(tasks, store);
    } else {
      for (uint32_t t = 0; t < tasks; ++t) store(t);
    }
    st.live.endBatch(version);
  }
  // In order: the refusals named, hand-backs faded in again, and the other poses set one at a
  // time (a slot named twice gets all its poses again, so its last good one holds).
  Status first = Status::ok();
  const auto refuse = [&](size_t k, const Status& s) {
    if (first.isOk()) first = {s.code(), strCat("setLivePoses: pose ", k, ": ", s.message())};
  };
  const double clock = cs.clock;
  for (size_t k = 0; k < handles.size(); ++k) {
    const detail::CrowdState::BatchPose& b = batch[k];
    Outcome outcome = b.outcome;
    if (outcome != Outcome::kStale && outcome != Outcome::kInOrder &&
        cs.live_claims.namedTwice(b.slot))
      outcome = Outcome::kNamedTwice;
    if (outcome == Outcome::kStale) {
      uint32_t i = 0;
      refuse(k, st.denseIndex(handles[k], &i));
    } else if (outcome == Outcome::kInOrder || outcome == Outcome::kNamedTwice) {
      const Status s = setLivePose(handles[k], poseOf(k), blend_seconds);
      if (!s.isOk()) refuse(k, s);
    } else if (outcome == Outcome::kBad) {
      refuse(k, badLiveMatrix(p.format, poseOf(k), b.bad));
    } else if (st.live.fadingOut(b.slot)) {  // Handing back: it fades in again from where it is.
      st.live.fade(b.slot, st.live.liveWeight(b.slot, clock), 1.0f, blend_seconds, clock);
    }
  }
  return first;
}

Status CrowdManager::clearLivePose(InstanceHandle h, double blend_seconds) {
  uint32_t i = 0;
  const Status s = state_ ? state_->store.denseIndex(h, &i) : noCrowd();
  if (!s.isOk()) return s;
  if (!std::isfinite(blend_seconds) || blend_seconds < 0.0)
    return {StatusCode::kInvalidArgument, "clearLivePose: blend_seconds must be finite and >= 0"};
  detail::InstanceStore& st = state_->store;
  const uint32_t slot = st.live_slot[i];
  if (slot == detail::kNoLivePose) return Status::ok();
  if (blend_seconds == 0.0) {
    st.releaseLivePose(i);
    return Status::ok();
  }
  // The last pose held while the clip fades in over it; released when the fade is over.
  const double clock = state_->clock;
  st.live.fade(slot, st.live.liveWeight(slot, clock), 0.0f, blend_seconds, clock);
  st.changed(i);
  return Status::ok();
}

Status CrowdManager::localPose(InstanceHandle h, const Skeleton& skeleton,
                               Span<TransformD> out) const {
  uint32_t i = 0;
  Status s = state_ ? state_->store.denseIndex(h, &i) : noCrowd();
  if (!s.isOk()) return s;
  const BakedPalette& p = *desc_.palette;
  const size_t n = skeleton.jointCount();
  if (n != p.skeleton_to_palette.size())
    return {StatusCode::kInvalidArgument,
            strCat("localPose: the skeleton has ", n, " joints, the palette was baked from one of ",
                   p.skeleton_to_palette.size())};
  if (out.size() != n)
    return {StatusCode::kCountMismatch, strCat("localPose: out holds ", out.size(),
                                               " transforms, the skeleton has ", n, " joints")};
  s = skeleton.validate();
  if (!s.isOk()) return {s.code(), strCat("localPose: ", s.message())};
  std::vector<glm::mat4> skinning(p.palette_joints.size());
  std::vector<uint32_t> slots(skinning.size());
  for (uint32_t k = 0; k < slots.size(); ++k) slots[k] = k;
  drawnSkinning(*state_, desc_, i, slots, false, skinning);
  // Stored joints: their skinning matrix times their bind matrix; the others their rest
  // transform under their parent as now.
  std::vector<glm::dmat4> model(n);
  for (size_t j = 0; j < n; ++j) {
    const int32_t slot = p.skeleton_to_palette[j];
    const int32_t parent = skeleton.parents[j];
    if (slot >= 0)
      model[j] = glm::dmat4(skinning[size_t(slot)]) *
                 glm::inverse(glm::dmat4(skeleton.inverse_bind_matrices[j]));
    else
      model[j] = (parent == Skeleton::kNoParent ? glm::dmat4(1.0) : model[size_t(parent)]) *
                 TransformD::fromFloat(skeleton.rest_pose[j]).toMatrix();
  }
  s = decomposePose(skeleton, model, out);
  if (!s.isOk()) return {s.code(), strCat("localPose: ", s.message())};
  return Status::ok();
}

}  // namespace si
