// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The crowd as a guest in OGRE's frame: a render queue listener that, after OGRE's main queue,
// draws a SkinnedInstancing crowd into OGRE's framebuffer with OGRE's camera (its own view and
// projection matrices, si::Camera::fromMatrices) and a material of the host's lit by OGRE's
// directional light and ambient colour (a uniform block at binding 7 the pass fills and binds,
// and puts back). Everything else is the library's state contract.
#include <OgreRenderQueueListener.h>

#include <cstdint>
#include <string>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/core/character.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace Ogre {
class Camera;
class Light;
class SceneManager;
}  // namespace Ogre

namespace si::ogre_host {

class CrowdPass : public Ogre::RenderQueueListener {
 public:
  /// Loads GL through `get_proc` (OGRE's context current), uploads the embedded character, adds
  /// the material and makes a crowd of `count` characters in a grid in front of the origin.
  Status init(void* (*get_proc)(void*, const char*), uint32_t count);
  /// Draws (or not) from the next frame on; the camera and light are read each frame.
  void enable(Ogre::Camera* camera, Ogre::Light* light, bool on);
  /// The crowd alone, drawn into a framebuffer of its own of `width` x `height` with the last
  /// frame's camera: 1 where a character covers the pixel (what OGRE's image may differ by).
  Status coverage(uint32_t width, uint32_t height, std::vector<uint8_t>* mask);
  /// The last draw's statistics and the first error (ok when none).
  const DrawStats& stats() const { return stats_; }
  const Status& error() const { return error_; }
  void shutdown();

  void renderQueueEnded(uint8_t queue_group, const std::string& invocation,
                        bool& repeat) override;

 private:
  Camera camera() const;

  Character character_;
  BakedPalette palette_;
  Renderer renderer_;
  CrowdManager crowd_;
  InstanceBatcher batcher_;
  uint32_t light_block_ = 0;
  Ogre::Camera* camera_ = nullptr;
  Ogre::Light* light_ = nullptr;
  bool on_ = false;
  DrawStats stats_;
  Status error_;
};

}  // namespace si::ogre_host
