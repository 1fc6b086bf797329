// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's layered animation (key L, --layers): every other character of the main crowd
// plays an overlay clip (the embedded character's wave) on the branch of one joint (its right
// clavicle) over whatever it is playing, fading in and out.
#include <cstdio>

#include "demo_scene.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"

namespace demo {

si::Status DemoScene::applyLayers(double blend_seconds) {
  overlays_ = 0;
  if (!options_.layers) {
    for (size_t i = 0; i < handles_.size(); i += 2) {
      const si::Status s = crowd_.stopOverlay(handles_[i], blend_seconds);
      if (!s.isOk()) return s;
    }
    return si::Status::ok();
  }
  const int32_t clip = palette_.findClip(options_.layer_clip);
  if (clip < 0)
    return {si::StatusCode::kNotFound,
            "layers: the palette has no clip '" + options_.layer_clip + "' to overlay"};
  if (crowd_.layerMasks().empty()) {  // Once per crowd (a re-layout makes a new one).
    si::LayerMask mask;
    si::Status s = si::buildLayerMask(character_.skeleton, palette_, options_.layer_root,
                                      {options_.layer_root}, &mask);
    if (s.isOk()) s = crowd_.addLayerMask(mask, nullptr);
    if (!s.isOk()) return {s.code(), "layers: " + s.message()};
  }
  for (size_t i = 0; i < handles_.size(); i += 2) {
    // Out of step with each other: each starts the clip somewhere else.
    const si::Status s = crowd_.playOverlay(handles_[i], uint32_t(clip), 0, 1.0f, blend_seconds,
                                            0.3 * double(i % 7));
    if (!s.isOk()) return s;
    ++overlays_;
  }
  return si::Status::ok();
}

si::Status DemoScene::toggleLayers() {
  return toggleOption(&options_.layers, [&] { return applyLayers(0.5); });
}

}  // namespace demo
