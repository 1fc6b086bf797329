// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd/live_poses.h"

#include <algorithm>
#include <cstring>

#include <glm/gtc/matrix_access.hpp>

#include "core/box_sphere.h"
#include "core/palette_texel.h"
#include "core/str_cat.h"
#include "crowd/live_pose_rows.h"
#include "si/core/transform.h"

namespace si::detail {

Status LivePoses::reset(const BakedPalette* palette, uint32_t capacity) {
  palette_ = palette;
  capacity_ = 0;
  free_.clear();
  fades_.clear();
  bounds_.clear();
  joint_boxes_.clear();
  owners_.clear();
  sides_.clear();
  frame_versions_.clear();
  written_.clear();
  fading_out_ = 0;
  texels_.clear();
  ++version_;
  if (capacity == 0) return Status::ok();
  if (palette->format == PaletteFormat::kQuatTranslationF32)
    return {StatusCode::kUnsupported,
            strCat("CrowdDesc.live_pose_capacity: live poses need a matrix palette, not ",
                   paletteFormatName(palette->format))};
  const PaletteLayout& l = palette->layout;
  const uint64_t first = l.textureTexelCount();
  const uint64_t texels = 2 * uint64_t(capacity) * l.frame_stride_texels;  // Two frames each.
  if (first + texels > 0xFFFFFFFFull)
    return {
        StatusCode::kLimitExceeded,
        strCat("CrowdDesc.live_pose_capacity: ", capacity, " poses of 2 x ", l.frame_stride_texels,
               " texels after the palette's ", first, " pass 2^32 texels")};
  capacity_ = capacity;
  first_texel_ = uint32_t(first);
  stride_ = l.frame_stride_texels;
  free_.resize(capacity);
  for (uint32_t k = 0; k < capacity; ++k) free_[k] = capacity - 1 - k;  // Slot 0 first.
  fades_.resize(capacity);
  bounds_.assign(capacity, Bounds());
  joint_boxes_ = jointBoxes(palette->joint_bounds);
  owners_.resize(capacity);
  sides_.assign(capacity, 0);
  frame_versions_.assign(size_t(2) * capacity, 0);
  written_.assign(capacity, kNever);
  texels_.assign(size_t(texels) * bytesPerTexel(palette->format), 0);
  return Status::ok();
}

Status LivePoses::take(InstanceHandle owner, uint32_t* slot) {
  if (free_.empty())
    return {StatusCode::kLimitExceeded,
            strCat("setLivePose: all ", capacity_,
                   " live poses are taken (CrowdDesc::live_pose_capacity)")};
  *slot = free_.back();
  free_.pop_back();
  fades_[*slot] = Fade();
  bounds_[*slot] = Bounds();
  owners_[*slot] = owner;
  written_[*slot] = kNever;  // Its first write stays on the current frame: nothing named it.
  return Status::ok();
}

void LivePoses::release(uint32_t slot) {
  if (fadingOut(slot)) --fading_out_;
  fades_[slot] = Fade();
  free_.push_back(slot);
  ++version_;
}

void LivePoses::fade(uint32_t slot, float from, float to, double seconds, double clock) {
  fading_out_ += uint32_t(to == 0.0f) - uint32_t(fadingOut(slot));
  fades_[slot] = Fade{from, to, clock, seconds};
  ++version_;
}

float LivePoses::liveWeight(uint32_t slot, double clock) const {
  const Fade& f = fades_[slot];
  if (!(clock - f.start < f.duration)) return f.to;  // Over (or none: duration 0).
  return float(double(f.from) +
               (double(f.to) - double(f.from)) * std::max(0.0, (clock - f.start) / f.duration));
}

void LivePoses::fadedOut(double clock, std::vector<InstanceHandle>* owners) const {
  owners->clear();
  if (fading_out_ == 0) return;
  for (uint32_t slot = 0; slot < capacity_; ++slot)
    if (fadingOut(slot) && clipWeight(slot, clock) == 1.0f) owners->push_back(owners_[slot]);
}

uint8_t* LivePoses::frameBytes(uint32_t frame_index) {
  return texels_.data() + size_t(frame_index) * stride_ * bytesPerTexel(palette_->format);
}

uint8_t* LivePoses::directFrame(uint32_t slot, uint64_t step) {
  // A new step's pose goes to the slot's other frame, which nothing names (the last step's
  // records name the current one).
  if (written_[slot] == kNever || written_[slot] == step) return nullptr;
  return frameBytes((sides_[slot] ^ 1u) * capacity_ + slot);
}

size_t LivePoses::store(Span<const glm::mat4> skinning, uint8_t* frame, Aabb* box) const {
  return storePose(palette_->format, skinning, palette_->layout.joint_stride_texels, joint_boxes_,
                   formatRange(palette_->format), frame, box);
}

void LivePoses::commit(uint32_t slot, const Bounds& bounds, uint32_t weights_frame_texel,
                       uint64_t step, uint64_t version) {
  bounds_[slot] = bounds;
  settle(slot, true, weights_frame_texel, step, version);
}

void LivePoses::settle(uint32_t slot, bool direct, uint32_t weights_frame_texel, uint64_t step,
                       uint64_t version) {
  sides_[slot] ^= uint8_t(direct);
  written_[slot] = step;
  frame_versions_[frameOf(slot)] = version;
  const PaletteLayout& l = palette_->layout;
  if (l.morph_target_count > 0) {  // The weights' texels as the baked frame holds them.
    const size_t bytes = bytesPerTexel(palette_->format);
    const uint32_t texels = (l.morph_target_count + 3) / 4;
    std::memcpy(
        frameBytes(frameOf(slot)) + size_t(l.morph_first_texel) * bytes,
        palette_->texel_bytes.data() + (size_t(weights_frame_texel) + l.morph_first_texel) * bytes,
        size_t(texels) * bytes);
  }
}

size_t LivePoses::write(uint32_t slot, Span<const glm::mat4> skinning, uint32_t weights_frame_texel,
                        uint64_t step) {
  Aabb box;
  if (uint8_t* frame = directFrame(slot, step)) {
    const size_t bad = store(skinning, frame, &box);
    if (bad < skinning.size()) return bad;
    poseBounds(box, &bounds_[slot]);
    settle(slot, true, weights_frame_texel, step, ++version_);
    return bad;
  }
  // Over the current frame: through scratch first, so that a refused pose leaves it as it was.
  const size_t joint_bytes =
      skinning.size() * palette_->layout.joint_stride_texels * bytesPerTexel(palette_->format);
  if (scratch_.size() < joint_bytes) scratch_.resize(joint_bytes);
  const size_t bad = store(skinning, scratch_.data(), &box);
  if (bad < skinning.size()) return bad;
  std::memcpy(frameBytes(frameOf(slot)), scratch_.data(), joint_bytes);
  poseBounds(box, &bounds_[slot]);
  settle(slot, false, weights_frame_texel, step, ++version_);
  return skinning.size();
}

void LivePoses::poseBounds(const Aabb& box, Bounds* bounds) const {
  // Written in place: a Bounds returned by value was copied through the stack with loads the
  // stores before them could not forward (a stall that cost as much as the box).
  Bounds& out = *bounds;
  out.box = box;
  out.known = false;
  if (out.box.empty()) return;
  // The drawn matrices are the stored ones: half floats round each value by up to 2^-11 of
  // it, moving a vertex by up to that of its coordinates; the shader's float arithmetic by
  // far less (the 1e-5 a baked clip's box is padded by).
  const float rounding = palette_->format == PaletteFormat::kMatrix3x4F16 ? 1.0f / 1024.0f : 1e-5f;
  const glm::vec3 pad = rounding * glm::max(glm::abs(out.box.min), glm::abs(out.box.max)) +
                        1e-5f * (out.box.max - out.box.min);
  out.box.min -= pad;
  out.box.max += pad;
  // The sphere a baked clip's box gets; a pose spanning past what float bounds hold keeps its
  // clip's sphere.
  double radius = 0.0;
  out.sphere = boxSphere(out.box, &radius);
  out.known = radius < 3.0e38 && isFinite(out.box.min) && isFinite(out.box.max);
}

void LivePoses::changedTexels(uint64_t since, uint32_t* first, uint32_t* count) const {
  if (since == 0) {  // Every texel, written or not.
    *first = 0;
    *count = uint32_t(frame_versions_.size()) * stride_;
    return;
  }
  uint32_t lo = uint32_t(frame_versions_.size()), hi = 0;
  for (uint32_t f = 0; f < frame_versions_.size(); ++f)
    if (frame_versions_[f] > since) lo = std::min(lo, f), hi = f + 1;
  *first = lo < hi ? lo * stride_ : 0;
  *count = lo < hi ? (hi - lo) * stride_ : 0;
}

glm::mat4 LivePoses::matrix(uint32_t slot, uint32_t joint) const {
  const size_t first = size_t(frameTexel(slot) - first_texel_) +
                       size_t(joint) * palette_->layout.joint_stride_texels;
  glm::mat4 m(1.0f);
  for (uint32_t row = 0; row < 3; ++row)
    m = glm::row(m, int(row), formatTexel(palette_->format, texels_.data(), first + row));
  return m;
}

}  // namespace si::detail
