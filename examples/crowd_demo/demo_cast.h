// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The mixed scene's other character kinds (crowd_demo --mix, key M): each a glTF model with its
// own palette and crowd, uploaded into the scene's renderer with Renderer::addCharacter and
// drawn with its CharacterId on the scene's path. Needs a current GL context for upload/draw.

#include <memory>
#include <string>
#include <vector>

#include "si/core/core.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace demo {

class DemoCast {
 public:
  /// Imports and bakes each model (automatic rates, or `rate_hz` > 0), printing a line each.
  si::Status load(const std::vector<std::string>& files, float rate_hz);
  /// Uploads every kind into `renderer` (once per renderer; again after releaseGl()).
  si::Status upload(si::Renderer& renderer);
  void releaseGl() { uploaded_ = false; }
  /// Kind k's crowd: one instance at each of `positions[k]`, its largest extent scaled to
  /// `size` model units, random clips, times and headings from `seed`.
  si::Status layout(const std::vector<std::vector<glm::dvec3>>& positions, double size,
                    uint64_t seed);
  /// Advances and culls every kind's crowd.
  si::Status update(double dt, const si::Camera& camera);
  /// Draws every kind's crowd: the instanced paths with `mode`, or the baselines (`traditional`
  /// / `cpu`). Adds what they drew to `stats`.
  si::Status draw(si::Renderer& renderer, const si::InstanceBatcher& batcher,
                  const si::Camera& camera, si::DrawMode mode, bool traditional, bool cpu,
                  si::DrawStats* stats);

  size_t size() const { return kinds_.size(); }
  /// Visible instances of every kind at the last update.
  uint32_t visible() const;

 private:
  struct Kind {
    std::string name;
    si::Character character;
    si::BakedPalette palette;
    si::CharacterId id;
    si::CrowdManager crowd;
  };
  std::vector<std::unique_ptr<Kind>> kinds_;
  bool uploaded_ = false;
};

}  // namespace demo
