// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager's layered animation: the crowd's joint masks and each instance's overlay.
#include <cmath>

#include "core/str_cat.h"
#include "crowd/crowd_state.h"
#include "si/crowd/crowd_manager.h"

namespace si {

using detail::strCat;

Status CrowdManager::addLayerMask(const LayerMask& mask, uint32_t* id) {
  if (!state_) return noCrowd();
  const Status s = mask.validate(*desc_.palette);
  if (!s.isOk())
    return {StatusCode::kInvalidArgument, strCat("addLayerMask '", mask.name, "': ", s.message())};
  if (state_->layer_masks.size() >= kMaxLayerMasks)
    return {StatusCode::kLimitExceeded,
            strCat("addLayerMask: a crowd holds at most ", kMaxLayerMasks, " masks")};
  state_->layer_masks.push_back(mask);
  if (id != nullptr) *id = uint32_t(state_->layer_masks.size() - 1);
  return Status::ok();
}

Span<const LayerMask> CrowdManager::layerMasks() const {
  const detail::CrowdState& st = state_ ? *state_ : emptyState();
  return Span<const LayerMask>(st.layer_masks.data(), st.layer_masks.size());
}

Status CrowdManager::playOverlay(InstanceHandle h, uint32_t clip, uint32_t mask, float weight,
                                 double blend_seconds, double time_seconds, float speed) {
  if (!state_) return noCrowd();
  if (clip >= desc_.palette->clips.size())
    return {StatusCode::kInvalidArgument,
            strCat("playOverlay: clip ", clip, " is past the palette's ", desc_.palette->clips.size())};
  if (mask >= state_->layer_masks.size())
    return {StatusCode::kInvalidArgument,
            strCat("playOverlay: mask ", mask, " is past the crowd's ", state_->layer_masks.size(),
                   " (addLayerMask)")};
  if (!(weight >= 0.0f && weight <= 1.0f) || !std::isfinite(blend_seconds) || blend_seconds < 0.0 ||
      !std::isfinite(time_seconds) || !std::isfinite(speed))
    return {StatusCode::kInvalidArgument,
            "playOverlay: weight must be in [0, 1], blend_seconds finite and >= 0, time and "
            "speed finite"};
  return state_->store.playOverlay(h, clip, mask, weight, blend_seconds, time_seconds, speed,
                                   state_->clock);
}

Status CrowdManager::stopOverlay(InstanceHandle h, double blend_seconds) {
  if (!state_) return noCrowd();
  if (!std::isfinite(blend_seconds) || blend_seconds < 0.0)
    return {StatusCode::kInvalidArgument, "stopOverlay: blend_seconds must be finite and >= 0"};
  return state_->store.stopOverlay(h, blend_seconds, state_->clock);
}

}  // namespace si
