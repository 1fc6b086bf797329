// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "window_app.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "si/headless/headless_context.h"

namespace demo {
namespace {

constexpr char kHelp[] =
    "crowd_demo keys:\n"
    "  F1          this help\n"
    "  ESC         quit\n"
    "  Space       camera: automatic fly-through on/off (off: fly yourself)\n"
    "  W A S D     fly forward, left, back, right;  Q E  down, up;  Shift: faster\n"
    "  arrows      turn (or drag with the right mouse button)\n"
    "  + / -       double / halve the crowd\n"
    "  ] / [       LOD lines (and the far line) 25 % farther / nearer\n"
    "  T           tint every character by its LOD (red 0, green 1, blue 2, ...)\n"
    "  F           re-bake in the next palette format (f32, f16, quat)\n"
    "  P           next drawing path (instanced by the measured choice, vertex-shader\n"
    "              skinning, compute pre-skinning, rigid, traditional, cpu-skinned)\n"
    "  C           crossfade every character to its next clip (0.5 s)\n"
    "  M           mixed scene on/off: other character kinds (--mix, else the sample Fox and\n"
    "              CesiumMan) share the field, drawn by the same renderer\n"
    "  V           animation events on/off: markers at every clip's start and middle; the\n"
    "              console prints the events reported each second\n"
    "  R           root motion on/off: the field walks and turns (clips baked in place, the\n"
    "              crowd moves each character by its clip's motion)\n"
    "  X           motion vectors on/off: the crowd is drawn once more into a colour + motion\n"
    "              target; the console prints the mean and largest motion twice a second\n"
    "  L           layered animation on/off: every other character waves its right arm over\n"
    "              what it plays (an overlay on the arm's joints, fading in and out)\n"
    "  B           blend space on/off: every other character walks and runs by a speed that\n"
    "              drifts over time (the walk and the run blended in local space, in step)\n"
    "  G           live poses on/off: the nearest characters turn their heads to the camera\n"
    "              and one falls and gets up every two seconds, drawn in the crowd's batches\n"
    "  O           props on/off: every other character holds a staff in its left hand (a\n"
    "              prop from a glTF file at a socket; the embedded character)\n"
    "  H           shadows on/off: three cascades, each a view of the crowd culled for its\n"
    "              own sun camera, cast the characters' shadows on a ground plane\n";

std::string g_glfw_error;
void onGlfwError(int code, const char* message) {
  g_glfw_error = "GLFW error " + std::to_string(code) + ": " + (message ? message : "");
}

void* getProc(void*, const char* name) {
  return reinterpret_cast<void*>(glfwGetProcAddress(name));
}

// Maps a --keys item to a GLFW key code (0 when unknown).
int keyCode(const std::string& k) {
  if (k.size() == 1) {
    const char c = char(std::toupper(static_cast<unsigned char>(k[0])));
    if (c >= 'A' && c <= 'Z') return GLFW_KEY_A + (c - 'A');
    if (c == '+' || c == '=') return GLFW_KEY_EQUAL;
    if (c == '-') return GLFW_KEY_MINUS;
    if (c == '[') return GLFW_KEY_LEFT_BRACKET;
    if (c == ']') return GLFW_KEY_RIGHT_BRACKET;
  }
  if (k == "space") return GLFW_KEY_SPACE;
  if (k == "f1") return GLFW_KEY_F1;
  if (k == "esc") return GLFW_KEY_ESCAPE;
  return 0;
}

using ViewportFn = void (*)(int, int, int, int);
using ReadPixelsFn = void (*)(int, int, int, int, unsigned, unsigned, void*);

class App {
 public:
  App(GLFWwindow* window, DemoScene* scene) : window_(window), scene_(scene) {}

  void onKey(int key) {
    si::Status s;
    switch (key) {
      case GLFW_KEY_F1: std::printf("%s", kHelp); break;
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
      case GLFW_KEY_SPACE:
        auto_fly_ = !auto_fly_;
        std::printf("camera: %s\n", auto_fly_ ? "fly-through" : "manual");
        break;
      case GLFW_KEY_EQUAL:
      case GLFW_KEY_KP_ADD:
      case GLFW_KEY_MINUS:
      case GLFW_KEY_KP_SUBTRACT: {
        const bool more = key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD;
        const uint32_t n = scene_->instanceCount();
        s = scene_->setInstanceCount(more ? std::min(n * 2, 1u << 20) : std::max(n / 2, 1u));
        std::printf("crowd: %u characters\n", scene_->instanceCount());
        break;
      }
      case GLFW_KEY_RIGHT_BRACKET:
      case GLFW_KEY_LEFT_BRACKET:
        s = scene_->scaleLodLines(key == GLFW_KEY_RIGHT_BRACKET ? 1.25f : 0.8f);
        std::printf("LOD lines at %.2f x the defaults\n", double(scene_->lodScale()));
        break;
      case GLFW_KEY_T:
        scene_->toggleLodTint();
        std::printf("LOD tint %s\n", scene_->lodTint() ? "on" : "off");
        break;
      case GLFW_KEY_F:
        std::printf("re-baking...\n");
        s = scene_->cycleFormat();
        std::printf("palette format: %s\n", si::paletteFormatName(scene_->palette().format));
        break;
      case GLFW_KEY_P:
        scene_->cyclePath();
        std::printf("path: %s\n", drawPathName(scene_->path()));
        break;
      case GLFW_KEY_M:
        s = scene_->toggleMixed();
        std::printf("mixed scene %s\n", scene_->mixed() ? "on" : "off");
        break;
      case GLFW_KEY_V:
        s = scene_->toggleEvents();
        std::printf("animation events %s\n", scene_->events() ? "on" : "off");
        break;
      case GLFW_KEY_R:
        s = scene_->toggleRootMotion();
        std::printf("root motion %s\n", scene_->rootMotion() ? "on" : "off");
        break;
      case GLFW_KEY_X:
        scene_->toggleMotionVectors();
        std::printf("motion vectors %s\n", scene_->motionVectors() ? "on" : "off");
        break;
      case GLFW_KEY_L:
        s = scene_->toggleLayers();
        std::printf("layered animation %s\n", scene_->layers() ? "on" : "off");
        break;
      case GLFW_KEY_B:
        s = scene_->toggleBlend();
        std::printf("blend space %s\n", scene_->blend() ? "on" : "off");
        break;
      case GLFW_KEY_G:
        s = scene_->toggleLive();
        std::printf("live poses %s\n", scene_->live() ? "on" : "off");
        break;
      case GLFW_KEY_O:
        s = scene_->toggleProps();
        std::printf("props %s\n", scene_->props() ? "on" : "off");
        break;
      case GLFW_KEY_H:
        scene_->toggleShadows();
        std::printf("shadows %s\n", scene_->shadows() ? "on" : "off");
        break;
      case GLFW_KEY_C:
        s = scene_->crossfadeAll();
        std::printf("crossfading every character to its next clip\n");
        break;
      default: break;
    }
    // A knob that cannot turn (e.g. the rotation format on scaled joints) says why; the scene
    // keeps its previous state.
    if (!s.isOk()) std::printf("  not changed: %s\n", s.toString().c_str());
  }

  // Advances the camera by dt and returns it.
  si::Camera camera(double dt, float aspect) {
    const double unit = scene_->unit();
    const glm::dvec3 center = scene_->fieldCenter();
    if (auto_fly_) {
      // A slow orbit around the field at 9 m, looking at a point ahead on the field.
      fly_time_ += dt;
      const double r = std::min(scene_->fieldHalfExtent(), 60.0 * unit) + 8.0 * unit;
      const double a = fly_time_ * 0.08;
      eye_ = center + glm::dvec3(r * std::cos(a), 9.0 * unit, r * std::sin(a));
      const glm::dvec3 to = glm::normalize(center - eye_ + glm::dvec3(0, 5.0 * unit, 0));
      yaw_ = std::atan2(to.x, to.z);
      pitch_ = std::asin(std::clamp(to.y, -1.0, 1.0));
    } else {
      const double speed = unit * (glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) ? 40.0 : 8.0) * dt;
      const glm::dvec3 forward(std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_),
                               std::cos(yaw_) * std::cos(pitch_));
      const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
      const auto down = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
      eye_ += forward * speed * (down(GLFW_KEY_W) - down(GLFW_KEY_S)) +
              right * speed * (down(GLFW_KEY_D) - down(GLFW_KEY_A)) +
              glm::dvec3(0, 1, 0) * speed * (down(GLFW_KEY_E) - down(GLFW_KEY_Q));
      yaw_ += dt * 1.5 * (down(GLFW_KEY_LEFT) - down(GLFW_KEY_RIGHT));
      pitch_ += dt * 1.5 * (down(GLFW_KEY_UP) - down(GLFW_KEY_DOWN));
      double mx = 0.0, my = 0.0;
      glfwGetCursorPos(window_, &mx, &my);
      if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && dragging_) {
        yaw_ -= (mx - mouse_x_) * 0.004;
        pitch_ -= (my - mouse_y_) * 0.004;
      }
      dragging_ = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
      mouse_x_ = mx;
      mouse_y_ = my;
      pitch_ = std::clamp(pitch_, -1.5, 1.5);
    }
    const glm::dvec3 forward(std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_),
                             std::cos(yaw_) * std::cos(pitch_));
    return si::Camera::lookAt(eye_, eye_ + forward, glm::vec3(0, 1, 0), 0.9f, aspect,
                              float(0.2 * unit), float(2000.0 * unit));
  }

 private:
  GLFWwindow* window_;
  DemoScene* scene_;
  bool auto_fly_ = true, dragging_ = false;
  double fly_time_ = 0.0, yaw_ = 0.0, pitch_ = 0.0, mouse_x_ = 0.0, mouse_y_ = 0.0;
  glm::dvec3 eye_ = glm::dvec3(0.0);
};

void onKey(GLFWwindow* window, int key, int, int action, int) {
  if (action == GLFW_PRESS || action == GLFW_REPEAT)
    static_cast<App*>(glfwGetWindowUserPointer(window))->onKey(key);
}

// Reads the back buffer (bottom-up) into top-down RGBA rows; returns the pixels that differ
// from the first one (the clear colour in a corner of the sky... or of the field).
size_t readBackBuffer(ReadPixelsFn read_pixels, int w, int h, std::vector<uint8_t>* rgba) {
  std::vector<uint8_t> raw(size_t(w) * h * 4);
  read_pixels(0, 0, w, h, 0x1908 /*GL_RGBA*/, 0x1401 /*GL_UNSIGNED_BYTE*/, raw.data());
  rgba->resize(raw.size());
  for (int y = 0; y < h; ++y)
    std::copy_n(raw.data() + size_t(h - 1 - y) * w * 4, size_t(w) * 4, rgba->data() + size_t(y) * w * 4);
  size_t differing = 0;
  for (size_t i = 0; i < raw.size(); i += 4)
    differing += std::memcmp(&raw[i], &raw[0], 3) != 0;
  return differing;
}

}  // namespace

WindowResult runWindow(const WindowOptions& o, DemoScene* scene, std::string* why) {
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((display == nullptr || !*display) && (wayland == nullptr || !*wayland)) {
    *why = "no DISPLAY or WAYLAND_DISPLAY";
    return WindowResult::kNoDisplay;
  }
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) {
    *why = "glfwInit failed: " + g_glfw_error;
    return WindowResult::kNoDisplay;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  GLFWwindow* window =
      glfwCreateWindow(int(o.width), int(o.height), "crowd_demo", nullptr, nullptr);
  if (window == nullptr) {  // Some displays have no multisampled visuals.
    glfwWindowHint(GLFW_SAMPLES, 0);
    window = glfwCreateWindow(int(o.width), int(o.height), "crowd_demo", nullptr, nullptr);
  }
  if (window == nullptr) {
    *why = "no GL 4.5 core window: " + g_glfw_error;
    glfwTerminate();
    return WindowResult::kNoDisplay;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(o.frames > 0 ? 0 : 1);
  WindowResult result = WindowResult::kDone;
  {
    si::GlInfo info;
    si::Status s = si::loadGl(&getProc, nullptr, &info);
    if (s.isOk()) s = scene->initGl(info);
    const auto viewport = reinterpret_cast<ViewportFn>(glfwGetProcAddress("glViewport"));
    const auto read_pixels = reinterpret_cast<ReadPixelsFn>(glfwGetProcAddress("glReadPixels"));
    if (s.isOk()) {
      std::printf("Window %ux%u: %s, GL %s. F1 lists the keys; ESC quits.\n", o.width, o.height,
                  info.renderer.c_str(), info.version.c_str());
    }
    App app(window, scene);
    glfwSetWindowUserPointer(window, &app);
    glfwSetKeyCallback(window, onKey);
    using Clock = std::chrono::steady_clock;
    auto last = Clock::now(), last_title = last;
    double frame_ms_sum = 0.0, gpu_ms_sum = 0.0;
    uint32_t frames_since_title = 0;
    uint64_t events_printed = 0;
    si::DrawStats stats;
    for (uint32_t frame = 0; s.isOk() && !glfwWindowShouldClose(window); ++frame) {
      glfwPollEvents();
      if (frame < o.keys.size()) {
        const int key = keyCode(o.keys[frame]);
        if (key == 0) {
          s = si::Status(si::StatusCode::kInvalidArgument, "unknown --keys item '" + o.keys[frame] + "'");
          break;
        }
        app.onKey(key);
      }
      int w = 0, h = 0;
      glfwGetFramebufferSize(window, &w, &h);
      if (w == 0 || h == 0) continue;  // Minimised.
      viewport(0, 0, w, h);
      const auto now = Clock::now();
      // Scripted runs step a fixed 1/60 s so they are reproducible.
      const double dt =
          o.frames > 0 ? 1.0 / 60.0 : std::min(0.1, std::chrono::duration<double>(now - last).count());
      frame_ms_sum += std::chrono::duration<double, std::milli>(now - last).count();
      last = now;
      si::Camera camera = app.camera(dt, float(w) / float(h));
      camera.viewport_height_pixels = float(h);  // For --lod-pixels.
      scene->setViewportSize(uint32_t(w), uint32_t(h));
      s = scene->frame(dt, camera, &stats);
      if (!s.isOk()) break;
      gpu_ms_sum += std::max(0.0, stats.gpu_ms);
      ++frames_since_title;
      if (std::chrono::duration<double>(now - last_title).count() > 0.5) {
        const si::CrowdFrameStats& cs = scene->crowd().view().stats();
        char title[256];
        std::snprintf(title, sizeof title,
                      "crowd_demo | %u characters, %u visible, %u draws, %s, %s, LOD x%.2f | "
                      "%.1f ms/frame, GPU %.2f ms | F1: keys",
                      cs.instances, cs.visible, stats.draw_calls, drawPathName(scene->path()),
                      si::paletteFormatName(scene->palette().format), double(scene->lodScale()),
                      frame_ms_sum / frames_since_title, gpu_ms_sum / frames_since_title);
        glfwSetWindowTitle(window, title);
        if (scene->events()) {
          std::printf("animation events: %llu in %.1f s\n",
                      static_cast<unsigned long long>(scene->eventsSinceOn() - events_printed),
                      std::chrono::duration<double>(now - last_title).count());
          events_printed = scene->eventsSinceOn();
        }
        if (scene->motionVectors()) {
          const si::MotionSummary& m = scene->motionSummary();
          if (m.drawn_pixels > 0)
            std::printf("motion vectors: mean %.2f px, largest %.2f px over %llu drawn pixels\n",
                        m.mean_pixels, m.max_pixels,
                        static_cast<unsigned long long>(m.drawn_pixels));
          else
            std::printf("motion vectors: none on the %s path\n", drawPathName(scene->path()));
        }
        last_title = now;
        frame_ms_sum = gpu_ms_sum = 0.0;
        frames_since_title = 0;
      }
      if (o.frames > 0 && frame + 1 >= o.frames) {
        std::vector<uint8_t> rgba;
        const size_t drawn = readBackBuffer(read_pixels, w, h, &rgba);
        if (!o.out.empty()) s = si::writePng(o.out, uint32_t(w), uint32_t(h), rgba);
        const si::CrowdFrameStats& cs = scene->crowd().view().stats();
        std::printf("Window: %u frames, last with %u characters, %u visible, %u draw calls, "
                    "%llu triangles (%s, %s); %zu pixels drawn\n",
                    o.frames, cs.instances, cs.visible, stats.draw_calls,
                    static_cast<unsigned long long>(stats.triangles), drawPathName(scene->path()),
                    si::paletteFormatName(scene->palette().format), drawn);
        if (s.isOk() && (drawn == 0 || stats.draw_calls == 0))
          s = si::Status(si::StatusCode::kBackend, "the window's last frame shows nothing drawn");
        if (s.isOk() && !o.out.empty()) std::printf("Wrote %s\n", o.out.c_str());
        glfwSetWindowShouldClose(window, GLFW_TRUE);
      }
      glfwSwapBuffers(window);
    }
    if (!s.isOk()) {
      *why = s.toString();
      result = WindowResult::kFailed;
    }
    glfwSetWindowUserPointer(window, nullptr);
    scene->releaseGl();  // While the window's context is still current.
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return result;
}

}  // namespace demo
