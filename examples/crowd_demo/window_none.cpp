// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo built without GLFW: no window, so the demo renders headless.
#include "window_app.h"

namespace demo {

WindowResult runWindow(const WindowOptions&, DemoScene*, std::string* why) {
  *why = "built without GLFW (install libglfw3-dev and rebuild)";
  return WindowResult::kNoDisplay;
}

}  // namespace demo
