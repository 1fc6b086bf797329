// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's blend space (key B, --blend): every other character of the main crowd walks and
// runs by a speed that drifts over time (a blend space of the walk and the run on a full-body
// mask, phase-synchronised, its parameter moved every frame).
#include <cmath>

#include "demo_scene.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"

namespace demo {

si::Status DemoScene::applyBlend(double blend_seconds) {
  blending_ = 0;
  const int32_t walk = palette_.findClip("walk"), run = palette_.findClip("run");
  if (!options_.blend) {
    for (size_t i = 1; i < handles_.size(); i += 2) {
      uint32_t space = 0;
      glm::vec2 parameter(0.0f);
      double phase = 0.0;
      if (!crowd_.blendState(handles_[i], &space, &parameter, &phase).isOk()) continue;
      const si::Status s = crowd_.crossfade(handles_[i], uint32_t(walk), blend_seconds);
      if (!s.isOk()) return s;
    }
    return si::Status::ok();
  }
  if (walk < 0 || run < 0)
    return {si::StatusCode::kNotFound, "blend: the palette has no 'walk' and 'run' clips to blend"};
  if (crowd_.blendSpaces().empty()) {  // Once per crowd (a re-layout makes a new one).
    si::LayerMask body;
    uint32_t mask = 0;
    si::Status s = si::buildFullBodyMask(character_.skeleton, palette_, "body", &body);
    if (s.isOk()) s = crowd_.addLayerMask(body, &mask);
    if (s.isOk())
      s = crowd_.addBlendSpace({"locomotion", {uint32_t(walk), uint32_t(run)}, {0.0f, 1.0f}, mask},
                               nullptr);
    if (!s.isOk()) return {s.code(), "blend: " + s.message()};
  }
  for (size_t i = 1; i < handles_.size(); i += 2) {
    const si::Status s =
        crowd_.playBlend(handles_[i], 0, blendParameter(i), blend_seconds, 0.1 * double(i % 9));
    if (!s.isOk()) return s;
    ++blending_;
  }
  return si::Status::ok();
}

float DemoScene::blendParameter(size_t i) const {
  // Between the walk and the run, drifting with the clock, each character at its own rate.
  const double t = crowd_.clockSeconds();
  return float(0.5 + 0.5 * std::sin(t * (0.3 + 0.05 * double(i % 7)) + 0.7 * double(i)));
}

si::Status DemoScene::moveBlends() {
  if (!options_.blend) return si::Status::ok();
  for (size_t i = 1; i < handles_.size(); i += 2) {
    const si::Status s = crowd_.setBlendParameter(handles_[i], blendParameter(i));
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

si::Status DemoScene::toggleBlend() {
  return toggleOption(&options_.blend, [&] { return applyBlend(0.5); });
}

}  // namespace demo
