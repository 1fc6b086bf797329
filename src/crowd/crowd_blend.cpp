// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// CrowdManager's blend spaces (si/crowd/blend_space.h): the crowd's spaces and each instance's
// blend (the store's side: instance_blend.cpp).
#include <cmath>

#include "core/str_cat.h"
#include "crowd/crowd_state.h"
#include "si/crowd/crowd_manager.h"

namespace si {

using detail::strCat;

Status CrowdManager::addBlendSpace(const BlendSpace& space, uint32_t* id) {
  if (!state_) return noCrowd();
  const Status s = space.validate(*desc_.palette, uint32_t(state_->layer_masks.size()));
  if (!s.isOk()) return {s.code(), "addBlendSpace: " + s.message()};
  if (state_->blend_spaces.size() >= kMaxBlendSpaces)
    return {StatusCode::kLimitExceeded,
            strCat("addBlendSpace: a crowd holds at most ", kMaxBlendSpaces, " blend spaces")};
  state_->blend_spaces.push_back(space);
  if (space.is2D()) state_->extra_layers = true;
  if (id != nullptr) *id = uint32_t(state_->blend_spaces.size() - 1);
  return Status::ok();
}

Span<const BlendSpace> CrowdManager::blendSpaces() const {
  const detail::CrowdState& st = state_ ? *state_ : emptyState();
  return Span<const BlendSpace>(st.blend_spaces.data(), st.blend_spaces.size());
}

Status CrowdManager::playBlend(InstanceHandle h, uint32_t space, BlendParameter point,
                               double blend_seconds, double phase, float speed) {
  if (!state_) return noCrowd();
  const glm::vec2 parameter = point.value;
  if (space >= state_->blend_spaces.size())
    return {StatusCode::kInvalidArgument,
            strCat("playBlend: space ", space, " is past the crowd's ", state_->blend_spaces.size(),
                   " (addBlendSpace)")};
  if (!std::isfinite(parameter.x) || !std::isfinite(parameter.y) || !std::isfinite(phase) ||
      !std::isfinite(speed) || speed < 0.0f || !std::isfinite(blend_seconds) || blend_seconds < 0.0)
    return {StatusCode::kInvalidArgument,
            "playBlend: parameter, phase and speed must be finite, speed >= 0, blend_seconds "
            "finite and >= 0"};
  return state_->store.playBlend(h, state_->blend_spaces[space], space, parameter, blend_seconds,
                                 phase, speed, state_->clock);
}

Status CrowdManager::setBlendParameter(InstanceHandle h, BlendParameter point) {
  if (!state_) return noCrowd();
  glm::vec2 parameter = point.value;
  if (!std::isfinite(parameter.x) || !std::isfinite(parameter.y))
    return {StatusCode::kInvalidArgument, "setBlendParameter: the parameter is not finite"};
  if (!point.has_y) {  // x alone: a 2D blend keeps its y.
    uint32_t i = 0;
    const Status s = state_->store.denseIndex(h, &i);
    if (!s.isOk()) return s;
    parameter.y = state_->store.overlays[i].parameter_y;
  }
  return state_->store.setBlendParameter(h, state_->blend_spaces, parameter, state_->clock);
}

Status CrowdManager::blendState(InstanceHandle h, uint32_t* space, glm::vec2* parameter,
                                double* phase) const {
  if (!state_) return noCrowd();
  const detail::InstanceStore& st = state_->store;
  uint32_t i = 0;
  const Status s = st.denseIndex(h, &i);
  if (!s.isOk()) return s;
  if (space == nullptr || parameter == nullptr || phase == nullptr)
    return {StatusCode::kInvalidArgument, "blendState: a null output"};
  const detail::OverlayState& o = st.overlays[i];
  if (!o.blend) return {StatusCode::kInvalidArgument, "blendState: the instance plays no blend"};
  *space = o.space;
  *parameter = glm::vec2(o.parameter, o.parameter_y);
  *phase = detail::cycleFraction(detail::blendPhase(o, state_->clock));
  return Status::ok();
}

}  // namespace si
