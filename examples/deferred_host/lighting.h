// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// deferred_host's lighting pass: one full-screen triangle that reads the G-buffer and lights
// every pixel by many point lights (a uniform block of the host's, binding 7) and a dim sky,
// with the glTF metallic-roughness BRDF, then tone-maps and encodes sRGB. The crowd's meshes,
// its impostors and the host's ground are lit by the same code from the same G-buffer.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "deferred_host/gbuffer.h"

namespace deferred {

struct PointLight {
  glm::dvec3 position{0.0};
  float radius = 1.0f;  ///< Where its light ends.
  glm::vec3 colour{1.0f};
};

class LightingPass {
 public:
  static constexpr uint32_t kMaxLights = 256;

  si::Status init();
  void release();
  /// Lights `gbuffer` seen by `camera` into the framebuffer bound (its viewport set).
  void draw(const GBuffer& gbuffer, const si::Camera& camera,
            const std::vector<PointLight>& lights) const;

 private:
  uint32_t program_ = 0, lights_ = 0, vao_ = 0;
};

}  // namespace deferred
