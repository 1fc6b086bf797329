// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_demo's cascaded shadows (--shadows, key H): three si::CrowdViews of the crowd, each
// selected for an orthographic sun camera round a slice of the main camera's depth range and
// drawn depth-only into a layer of a shadow map; then a ground plane that samples them. The
// characters cast shadows on the ground, also those outside the main view. The demo's own GL
// (the host's part): the library draws only the crowd.

#include <cstdint>
#include <vector>

#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace demo {

class CascadedShadows {
 public:
  static constexpr uint32_t kCascades = 3;
  static constexpr uint32_t kResolution = 2048;
  /// The sun's direction (the renderer's default light).
  static glm::vec3 sunDirection() { return glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f)); }

  /// Creates the shadow map and the ground program (the context current).
  si::Status initGl();
  void releaseGl();
  /// Attaches the cascades' views to `crowd` (again after it was re-laid out).
  si::Status attach(si::CrowdManager& crowd);
  /// Selects each cascade for this frame's sun cameras round `camera`'s view of the ground
  /// (a disc at `centre` of `radius`), and draws each depth-only into its layer. Leaves the
  /// framebuffer and viewport bound before it as they were.
  si::Status render(si::Renderer& renderer, const si::InstanceBatcher& batcher,
                    const si::Camera& camera, const glm::dvec3& centre, double radius);
  /// Draws the ground (y = 0, `radius` round `centre`) seen by `camera`, lit and shadowed.
  si::Status drawGround(const si::Camera& camera, const glm::dvec3& centre, double radius,
                        const glm::vec3& light_direction);
  /// Whether the cascades are attached to a crowd (a crowd laid out again detaches them).
  bool attached() const { return views_.size() == kCascades && views_[0].attached(); }
  /// Characters the cascades drew in the last frame (summed over the cascades).
  uint32_t drawn() const { return drawn_; }

 private:
  std::vector<si::CrowdView> views_;
  std::vector<si::Camera> lights_;
  uint32_t texture_ = 0, program_ = 0, vao_ = 0, drawn_ = 0;
  uint32_t framebuffers_[kCascades] = {};
};

}  // namespace demo
