// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The browser page's scene and controls, shared by the page (web_main.cpp) and its native twin
// (web_reference.cpp), so that the browser test compares the same crowd from the same camera at
// the same time after the same control moves: the embedded character on a grid 1.6 m apart,
// random clips, times, headings and parts from one seed, seen by an orbit camera about the
// field's centre; a drag orbits, the wheel zooms, the crowd size and a LOD distance scale are
// set from the page's controls.
#include <cstdint>
#include <string>
#include <vector>

#include "si/core/character.h"
#include "si/crowd/camera.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace si::web {

inline constexpr uint32_t kDefaultInstances = 2500;
inline constexpr uint32_t kMaxInstances = 200000;
inline constexpr uint64_t kSeed = 7;
/// The test mode's step (the browser test steps the page's frames by it).
inline constexpr double kTestStepSeconds = 1.0 / 30.0;
/// The controls: orbit radians per pixel dragged, and the zoom factor exp(wheel delta x this).
inline constexpr double kOrbitRadiansPerPixel = 0.006;
inline constexpr double kZoomPerWheelUnit = 0.001;

struct Orbit {
  double yaw = 0.6, pitch = 0.35, distance = 30.0;
};

/// The scene: a renderer with the character, its crowd, the batcher and the camera's orbit.
class Scene {
 public:
  /// Inits the renderer on the current context (`info`, `renderer_desc`), adds `character`
  /// playing `palette` (both must outlive the scene) and builds a crowd of `instances`.
  Status init(const GlInfo& info, const RendererDesc& renderer_desc, const Character& character,
              const BakedPalette& palette, uint32_t instances);
  /// A new crowd of `instances` (clamped to 1 .. kMaxInstances), the LOD scale kept.
  Status setInstances(uint32_t instances);
  /// Multiplies the crowd's LOD lines and far line by `scale` (clamped to 0.05 .. 20).
  Status setLodScale(double scale);
  /// A drag of (dx, dy) pixels: yaw and pitch (pitch clamped to 0.05 .. 1.5 radians).
  void drag(double dx, double dy);
  /// A wheel turn of `delta_y` (the WheelEvent's deltaY): distance x exp(delta_y x 0.001).
  void wheel(double delta_y);
  /// Steps the crowd by `dt` seconds and draws it, cleared, into the current framebuffer.
  Status frame(double dt, float aspect, DrawStats* stats);
  /// The last frame's crowd: "N characters, V visible (LOD 0-3: a b c d) | D draw calls,
  /// T M triangles", as the page shows it.
  std::string statsLine() const;

  const Renderer& renderer() const { return renderer_; }
  CharacterId character() const { return id_; }
  uint32_t instances() const { return instances_; }

 private:
  Camera camera(float aspect) const;

  const Character* character_ = nullptr;
  const BakedPalette* palette_ = nullptr;
  Renderer renderer_;
  CharacterId id_;
  InstanceBatcher batcher_;
  CrowdManager crowd_;
  std::vector<float> base_lod_lines_;
  float base_far_ = 0.0f;
  uint32_t instances_ = 0;
  double lod_scale_ = 1.0;
  Orbit orbit_;
  DrawStats last_draw_;
};

}  // namespace si::web
