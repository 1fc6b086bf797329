// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_demo's windowed front end (GLFW): a camera fly-through over the scene and the keys
// that turn its knobs.

#include <string>
#include <vector>

#include "demo_scene.h"

namespace demo {

struct WindowOptions {
  uint32_t width = 1280, height = 720;
  uint32_t frames = 0;            ///< Close after this many frames; 0: when ESC is pressed.
  std::string out;                ///< PNG of the last frame when closing (empty: none).
  std::vector<std::string> keys;  ///< Keys pressed one per frame from the first (scripted runs).
};

enum class WindowResult {
  kDone,       ///< Ran and closed normally.
  kNoDisplay,  ///< No display or no GL 4.5 window: the caller may render headless instead.
  kFailed,     ///< The window ran but drawing failed, or it drew nothing.
};

/// Opens the window, initialises the scene's GL side in it and runs until ESC (or `frames`).
/// `why` says what went wrong for kNoDisplay and kFailed.
WindowResult runWindow(const WindowOptions& options, DemoScene* scene, std::string* why);

}  // namespace demo
