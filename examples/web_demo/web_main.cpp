// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd in a browser (scripts/web.sh, docs/web.md): the library's ES profile on the page's
// WebGL 2 context. The embedded procedural character (si::makeDefaultCharacter) plays the
// palette si-bake baked for it natively, embedded into the page's files at /default.sipal, or
// the palette file the page fetched to /url.sipal (the page's ?palette=URL; same character).
// The scene and its controls (web_scene.h: orbit by drag, zoom by wheel, crowd size, LOD
// distance scale) are driven from the page's event handlers through the exported si_web_*
// functions; the frame statistics go back to its #stats element. No threads (the crowd updates
// on the page's thread) and no file system beyond Emscripten's.
// ?test=1 (the browser test, tests/web/browser_drive.py): no frame loop; each si_web_step(dt)
// call draws one frame after stepping the clock by dt, with its statistics, so that the test
// draws the frames web_reference.cpp draws natively, between the control moves it makes.
// ?count=CHARACTERS sets the crowd's first size; ?bench=SECONDS logs the statistics once after
// that long measured (scripts/web_bench.sh); ?restore=0 turns the GL state contract off;
// ?checks=1 checks GL errors after each call (the test mode's default), ?checks=0 does not;
// ?raster=1 has the state contract ask WebGL for the values it answers by a round trip
// (RendererDesc::webgl_restore_raster_state).
#include <emscripten/emscripten.h>
#include <emscripten/html5.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "si/core/default_character.h"
#include "si/core/palette_file.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"
#include "web_scene.h"

namespace {

struct App {
  si::Character character;
  si::BakedPalette palette;
  si::web::Scene scene;
  // Means over the frames after the first kWarmUp (shader compiling, first uploads) since the
  // crowd or its LOD scale last changed: the frame interval and the CPU time of a frame's code.
  static constexpr uint64_t kWarmUp = 2;
  double last_ms = 0.0, frame_ms_sum = 0.0, cpu_ms_sum = 0.0;
  uint64_t measured = 0, since_change = 0, frames = 0;
  bool test = false;           // ?test=1: frames drawn by si_web_step only.
  double bench_seconds = 0.0;  // > 0: log the statistics once, after so long measured.
  bool bench_logged = false;
  double last_stats_ms = 0.0;
  bool failed = false;
};
App* g_app = nullptr;

void fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "si web demo: %s: %s\n", what, s.toString().c_str());  // console.error
  if (g_app != nullptr) g_app->failed = true;
}

// Starts the means over (the scene changed).
void restartMeans(App& a) {
  a.frame_ms_sum = a.cpu_ms_sum = 0.0;
  a.measured = a.since_change = 0;
}

// Draws one frame `dt` seconds on; shows the statistics (every 250 ms, each frame in the test).
void drawFrame(App& a, double dt) {
  const double now = emscripten_get_now();
  const bool measuring = a.since_change > App::kWarmUp;
  if (measuring) a.frame_ms_sum += now - a.last_ms;
  a.last_ms = now;
  int width = 0, height = 0;
  emscripten_get_canvas_element_size("#canvas", &width, &height);
  const si::Status s = a.scene.frame(dt, float(width) / float(std::max(height, 1)), nullptr);
  if (!s.isOk()) return fail("drawing the frame", s);
  if (measuring) {
    a.cpu_ms_sum += emscripten_get_now() - now;
    ++a.measured;
  }
  ++a.since_change;
  ++a.frames;
  if (now - a.last_stats_ms < 250.0 && !a.test) return;
  a.last_stats_ms = now;
  char timing[160] = " | test mode: frames drawn when the test asks";  // No frame rate.
  if (!a.test)
    std::snprintf(timing, sizeof(timing), " | %.1f frames/s, CPU %.2f ms a frame (mean of %llu)",
                  a.measured ? 1000.0 * a.measured / a.frame_ms_sum : 0.0,
                  a.measured ? a.cpu_ms_sum / a.measured : 0.0,
                  static_cast<unsigned long long>(a.measured));
  const std::string text = a.scene.statsLine() + timing + " | frame " + std::to_string(a.frames);
  EM_ASM({ siWebStats(UTF8ToString($0), $1); }, text.c_str(), double(a.frames));
  if (a.bench_seconds > 0.0 && !a.bench_logged && a.frame_ms_sum >= 1000.0 * a.bench_seconds) {
    a.bench_logged = true;  // scripts/web_bench.sh reads this line from the browser's log.
    std::printf("si web demo: bench %s\n", text.c_str());
  }
}

void loopFrame() {
  App& a = *g_app;
  if (a.failed) return;
  const double now = emscripten_get_now();
  drawFrame(a, a.last_ms > 0.0 ? std::min(0.1, (now - a.last_ms) * 1e-3) : 0.0);
}

// The integer the page's query string gives `name`, or `absent`.
int queryInt(const char* name, int absent) {
  return EM_ASM_INT(
      {
        const v = new URLSearchParams(location.search).get(UTF8ToString($0));
        return v == null ? $1 : (parseInt(v, 10) || 0);
      },
      name, absent);
}

bool readFile(const char* path, std::vector<uint8_t>* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

}  // namespace

extern "C" {
// The page's controls (index.html's handlers) and the test mode's frame.
EMSCRIPTEN_KEEPALIVE void si_web_orbit(double dx, double dy) {
  if (g_app != nullptr) g_app->scene.drag(dx, dy);
}
EMSCRIPTEN_KEEPALIVE void si_web_zoom(double wheel_delta_y) {
  if (g_app != nullptr) g_app->scene.wheel(wheel_delta_y);
}
EMSCRIPTEN_KEEPALIVE void si_web_set_instances(int count) {
  if (g_app == nullptr) return;
  restartMeans(*g_app);
  const si::Status s = g_app->scene.setInstances(uint32_t(std::max(count, 1)));
  if (!s.isOk()) fail("building the crowd", s);
}
EMSCRIPTEN_KEEPALIVE void si_web_set_lod_scale(double scale) {
  if (g_app == nullptr) return;
  restartMeans(*g_app);
  const si::Status s = g_app->scene.setLodScale(scale);
  if (!s.isOk()) fail("setting the LOD distances", s);
}
/// ?test=1: draws one frame after stepping the clock by `dt` seconds; returns 0, or 1 when the
/// page has failed (the error is on the console).
EMSCRIPTEN_KEEPALIVE int si_web_step(double dt) {
  if (g_app == nullptr || g_app->failed) return 1;
  drawFrame(*g_app, dt);
  return g_app->failed ? 1 : 0;
}
}

int main() {
  const int test = queryInt("test", 0);
  const int count = queryInt("count", 0);
  const int bench = queryInt("bench", 0);
  const int checks = queryInt("checks", -1);
  const int restore = queryInt("restore", 1);
  const int raster = queryInt("raster", 0);
  EmscriptenWebGLContextAttributes attributes;
  emscripten_webgl_init_context_attributes(&attributes);
  attributes.majorVersion = 2;
  attributes.minorVersion = 0;
  attributes.depth = EM_TRUE;
  attributes.antialias = EM_FALSE;
  attributes.preserveDrawingBuffer = EM_TRUE;  // The browser test reads the canvas back.
  const EMSCRIPTEN_WEBGL_CONTEXT_HANDLE context =
      emscripten_webgl_create_context("#canvas", &attributes);
  if (context <= 0 || emscripten_webgl_make_context_current(context) != EMSCRIPTEN_RESULT_SUCCESS) {
    std::fprintf(stderr, "si web demo: this browser gives no WebGL 2 context\n");
    return 1;
  }
  g_app = new App();
  App& a = *g_app;
  a.test = test > 0;
  a.bench_seconds = std::max(bench, 0);
  si::GlInfo info;
  si::Status s =
      si::loadGl([](void*, const char* name) { return emscripten_webgl_get_proc_address(name); },
                 nullptr, &info);
  if (!s.isOk()) return fail("loading WebGL 2", s), 1;
  std::printf("si web demo: %s, %s (ES profile: %s)\n", info.version.c_str(), info.renderer.c_str(),
              info.es ? "yes" : "no");
  std::vector<uint8_t> bytes;
  const char* file = readFile("/url.sipal", &bytes) ? "/url.sipal" : "/default.sipal";
  if (bytes.empty() && !readFile(file, &bytes))
    return fail(file, {si::StatusCode::kIo, "missing"}), 1;
  s = si::makeDefaultCharacter({}, &a.character);
  if (s.isOk()) s = si::loadPalette(bytes, &a.palette);
  si::RendererDesc rd;
  // In the test mode (or with ?checks=1) every GL error is named and the page stops. Not by
  // default (or with ?checks=0): in a browser glGetError waits for the GPU process to finish
  // the queued work (docs/web.md), which makes every frame wait for the last.
  rd.debug_checks = checks == 1 || (checks < 0 && a.test) ? 1 : 2;
  rd.restore_state = restore != 0;  // ?restore=0: the state contract off (docs/web.md's table).
  rd.webgl_restore_raster_state = raster != 0;  // ?raster=1: its round trips too.
  if (s.isOk())
    s = a.scene.init(info, rd, a.character, a.palette,
                     count > 0 ? uint32_t(count) : si::web::kDefaultInstances);
  if (!s.isOk()) return fail("starting", s), 1;
  std::printf("si web demo: %s, %zu clips from %s\n",
              a.scene.renderer().skinningPathReason(a.scene.character()).c_str(),
              a.palette.clips.size(), file);
  if (a.test) {
    EM_ASM({ window.siWeb.ready = true; });  // The browser test steps the frames.
    return 0;
  }
  emscripten_set_main_loop(loopFrame, 0, false);
  return 0;
}
