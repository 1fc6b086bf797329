// The consumer's crowd, shared by the engine-like host (main.cpp) and the runtime-only program
// (runtime_main.cpp), so both draw the same image: a few characters close to the camera, each
// with its own clip, time, tint and armour. si::core and si::crowd only.
#pragma once

#include <cstdint>

#include "si/crowd/camera.h"
#include "si/crowd/crowd_manager.h"

namespace consumer {

inline constexpr uint32_t kSize = 192;
inline constexpr float kClear[3] = {0.1f, 0.1f, 0.1f};

inline si::Status makeCrowd(const si::BakedPalette& palette, si::CrowdManager* crowd,
                            si::Camera* camera) {
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = 4;
  cd.lod_count = 3;
  si::Status s = crowd->init(cd);
  for (int k = 0; k < 5 && s.isOk(); ++k) {
    si::InstanceDesc d;
    d.position = glm::dvec3(-2.0 + k, 0.0, -1.5 * (k % 2));
    d.clip = uint32_t(k) % uint32_t(palette.clips.size());
    d.time_seconds = 0.17 * k;
    d.variation_mask = 1u | (uint32_t(k) << 1);
    d.color = glm::u8vec4(uint8_t(60 + 40 * k), uint8_t(220 - 30 * k), 90, 255);
    si::InstanceHandle h;
    s = crowd->add(d, &h);
  }
  *camera = si::Camera::lookAt({0.0, 1.6, 5.0}, {0.0, 0.9, -0.5}, glm::vec3(0, 1, 0), 0.9f, 1.0f,
                               0.1f, 100.0f);
  return s.isOk() ? crowd->update(0.4, *camera) : s;
}

}  // namespace consumer
