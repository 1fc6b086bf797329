// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The crowd in a browser (scripts/web.sh, docs/web.md): the library's ES profile on the page's
// WebGL 2 context. The embedded procedural character (si::makeDefaultCharacter) plays the
// palette si-bake baked for it natively, embedded into the page's files at /default.sipal, or
// the palette file the page fetched to /url.sipal (the page's ?palette=URL; same character).
// An orbit camera (drag, wheel), the crowd size and the LOD distance scale come from the page
// through the exported si_web_* functions; the frame statistics go back to its #stats element.
// No threads (the crowd updates on the page's thread) and no file system beyond Emscripten's.
// The test mode (?test=FRAMES, the browser test) steps the clock by a fixed 1/30 s, stops after
// FRAMES frames and logs "si web demo: done": web_reference.cpp draws the same frame natively.
// ?count=CHARACTERS sets the crowd's first size; ?bench=SECONDS logs the statistics once after
// that long measured (scripts/web_bench.sh); ?restore=0 turns the GL state contract off.
#include <emscripten/emscripten.h>
#include <emscripten/html5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "si/core/default_character.h"
#include "si/core/palette_file.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"
#include "web_scene.h"

namespace {

struct App {
  si::Character character;
  si::BakedPalette palette;
  si::Renderer renderer;
  si::CrowdManager crowd;
  si::InstanceBatcher batcher;
  std::vector<float> base_lod_lines;
  float base_far = 0.0f;
  uint32_t instances = 0;
  float lod_scale = 1.0f;
  si::web::Orbit orbit;
  // Means over the frames after the first kWarmUp (shader compiling, first uploads) since the
  // crowd or its LOD scale last changed: the frame interval and the CPU time of a frame's code.
  static constexpr uint64_t kWarmUp = 2;
  double clock = 0.0, last_ms = 0.0, frame_ms_sum = 0.0, cpu_ms_sum = 0.0;
  uint64_t measured = 0, since_change = 0;
  uint64_t frames = 0, test_frames = 0;  // test_frames > 0: the test mode.
  double bench_seconds = 0.0;            // > 0: log the statistics once, after so long measured.
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

si::Status buildCrowd(App& a, uint32_t instances) {
  restartMeans(a);
  si::Status s = si::web::buildCrowd(a.character, a.palette, instances, &a.crowd);
  a.base_lod_lines = a.crowd.desc().lod_distances_radii;
  a.base_far = a.crowd.desc().max_distance_radii;
  a.instances = instances;
  return s;
}

si::Status applyLodScale(App& a) {
  restartMeans(a);
  std::vector<float> lines = a.base_lod_lines;
  for (float& l : lines) l *= a.lod_scale;
  return a.crowd.setLodDistances(lines, a.base_far * a.lod_scale);
}

void frame() {
  App& a = *g_app;
  if (a.failed) return;
  const double now = emscripten_get_now();
  double dt = a.last_ms > 0.0 ? std::min(0.1, (now - a.last_ms) * 1e-3) : 0.0;
  // The test mode: frame k (from 0) at k steps; then kHoldFrames more draws of the last state
  // (no step), so that the browser's compositor, which may present a frame or two late under
  // load, shows the last state when the screenshot is taken.
  if (a.test_frames > 0)
    dt = a.frames == 0 || a.frames >= a.test_frames ? 0.0 : si::web::kTestStepSeconds;
  const bool measuring = a.since_change > App::kWarmUp;
  if (measuring) a.frame_ms_sum += now - a.last_ms;
  a.last_ms = now;
  int width = 0, height = 0;
  emscripten_get_canvas_element_size("#canvas", &width, &height);
  const si::Camera camera =
      si::web::orbitCamera(a.orbit, a.instances, float(width) / float(std::max(height, 1)));
  a.clock += dt;
  si::Status s = a.crowd.update(dt, camera);
  a.renderer.clear(glm::vec4(0.55f, 0.62f, 0.7f, 1.0f));
  si::DrawStats stats;
  if (s.isOk()) s = a.renderer.drawCrowd(a.crowd, a.batcher, camera, &stats);
  if (!s.isOk()) return fail("drawing the frame", s);
  if (measuring) {
    a.cpu_ms_sum += emscripten_get_now() - now;
    ++a.measured;
  }
  ++a.since_change;
  ++a.frames;
  constexpr uint64_t kHoldFrames = 3;
  const bool done = a.test_frames > 0 && a.frames >= a.test_frames + kHoldFrames;
  if (done) {
    emscripten_cancel_main_loop();
    std::printf("si web demo: done, %llu frames, clock %.4f s\n",
                static_cast<unsigned long long>(a.test_frames), a.clock);
  }
  if (now - a.last_stats_ms < 250.0 && !done) return;
  a.last_stats_ms = now;
  const si::CrowdFrameStats& cs = a.crowd.stats();
  char text[512];
  std::snprintf(text, sizeof(text),
                "%u characters, %u visible (LOD 0-3: %u %u %u %u) | %u draw calls, %.2f M "
                "triangles | %.1f frames/s, CPU %.2f ms a frame (mean of %llu) | frame %llu",
                a.instances, cs.visible, cs.per_lod[0], cs.per_lod[1], cs.per_lod[2], cs.per_lod[3],
                stats.draw_calls, double(stats.triangles) * 1e-6,
                a.measured ? 1000.0 * a.measured / a.frame_ms_sum : 0.0,
                a.measured ? a.cpu_ms_sum / a.measured : 0.0,
                static_cast<unsigned long long>(a.measured),
                static_cast<unsigned long long>(a.frames));
  EM_ASM({ siWebStats(UTF8ToString($0), $1); }, text, double(a.frames));
  if (a.bench_seconds > 0.0 && !a.bench_logged && a.frame_ms_sum >= 1000.0 * a.bench_seconds) {
    a.bench_logged = true;  // scripts/web_bench.sh reads this line from the browser's log.
    std::printf("si web demo: bench %s\n", text);
  }
}

bool readFile(const char* path, std::vector<uint8_t>* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

}  // namespace

extern "C" {
// The page's controls.
EMSCRIPTEN_KEEPALIVE void si_web_orbit(double dx, double dy) {
  if (g_app == nullptr) return;
  g_app->orbit.yaw -= dx * 0.006;
  g_app->orbit.pitch = std::clamp(g_app->orbit.pitch + dy * 0.006, 0.05, 1.5);
}
EMSCRIPTEN_KEEPALIVE void si_web_zoom(double factor) {
  if (g_app != nullptr)
    g_app->orbit.distance = std::clamp(g_app->orbit.distance * factor, 2.0, 1500.0);
}
EMSCRIPTEN_KEEPALIVE void si_web_set_instances(int count) {
  if (g_app == nullptr) return;
  const si::Status s = buildCrowd(*g_app, uint32_t(std::clamp(count, 1, 200000)));
  if (!s.isOk()) return fail("building the crowd", s);
  const si::Status l = applyLodScale(*g_app);
  if (!l.isOk()) fail("setting the LOD distances", l);
}
EMSCRIPTEN_KEEPALIVE void si_web_set_lod_scale(double scale) {
  if (g_app == nullptr) return;
  g_app->lod_scale = float(std::clamp(scale, 0.05, 20.0));
  const si::Status s = applyLodScale(*g_app);
  if (!s.isOk()) fail("setting the LOD distances", s);
}
}

int main() {
  // ?test=FRAMES and ?count=CHARACTERS from the page's query string (0: not given).
  const int test_frames = EM_ASM_INT(
      { return parseInt(new URLSearchParams(location.search).get("test") || "0", 10) || 0; });
  const int count = EM_ASM_INT(
      { return parseInt(new URLSearchParams(location.search).get("count") || "0", 10) || 0; });
  const int bench = EM_ASM_INT(
      { return parseInt(new URLSearchParams(location.search).get("bench") || "0", 10) || 0; });
  const int restore =
      EM_ASM_INT({ return new URLSearchParams(location.search).get("restore") == "0" ? 0 : 1; });
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
  a.test_frames = uint64_t(std::max(test_frames, 0));
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
  rd.debug_checks = 1;  // Every GL error named, and the page stops.
  rd.restore_state = restore != 0;  // ?restore=0: the state contract off (docs/web.md's table).
  if (s.isOk()) s = a.renderer.init(info, rd);
  si::CharacterId id;
  if (s.isOk()) s = a.renderer.addCharacter(a.character, a.palette, &id);
  if (s.isOk()) s = a.batcher.init(a.renderer.batchLimits());
  if (s.isOk())
    s = buildCrowd(a, count > 0 ? uint32_t(std::min(count, 200000)) : si::web::kDefaultInstances);
  if (!s.isOk()) return fail("starting", s), 1;
  std::printf("si web demo: %s, %zu clips from %s\n", a.renderer.skinningPathReason(id).c_str(),
              a.palette.clips.size(), file);
  emscripten_set_main_loop(frame, 0, false);
  return 0;
}
