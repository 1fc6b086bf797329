// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo, the main job: bakes the embedded character (or a glTF model, or loads a si-bake
// palette file) and renders a crowd of it. With a display it opens a window (GLFW) with a
// camera fly-through and keys for the crowd size, LOD lines, bake format, drawing path and a
// crossfade of every character (F1 lists them); without one (or with --headless) it renders
// N frames offscreen (EGL or OSMesa), writes a PNG and prints the frame statistics.
// Usage: crowd_demo --help
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/example_options.h"
#include "demo_scene.h"
#include "si/core/morph_target.h"
#include "si/headless/headless_context.h"
#include "window_app.h"

namespace {

enum class Mode { kAuto, kHeadless, kWindow };

struct Options {
  demo::SceneOptions scene;
  demo::WindowOptions window;
  Mode mode = Mode::kAuto;
  uint32_t frames = 0;  // 0: 3 headless, until ESC in a window.
  uint32_t width = 1280, height = 720;
  std::string out = "crowd.png";
  si::HeadlessBackend backend = si::HeadlessBackend::kAuto;
  bool summary = false;
};

void usage(std::FILE* f) {
  std::fprintf(
      f,
      "usage: crowd_demo [--headless | --window] [--instances N] [--frames N] [--size WxH]\n"
      "                  [--out PATH] [--backend auto|egl-device|egl-surfaceless|osmesa]\n"
      "                  [--format f32|f16|quat] [--rate HZ] [--seed N] [--summary]\n"
      "                  [--model FILE.gltf|FILE.glb] [--clips NAME,...] [--palette FILE]\n"
      "                  [--keys K,K,...] [--lod-pixels PX] [--mix FILE,...|samples]\n"
      "                  [--events] [--root-motion] [--motion-vectors] [--layers] [--props] "
      "[--blend] "
      "[--shadows]\n"
      "                  [--impostors] [--impostor-atlas full|small] [--faces N] [--close-up]\n"
      "Renders a crowd of the embedded character (default 4000 characters, 1280x720).\n"
      "With a display it opens a window (F1 lists the keys; ESC quits); without one, or with\n"
      "--headless, it renders --frames frames (default 3, 1/60 s apart) offscreen, writes the\n"
      "PNG --out and prints frame statistics. --window insists on a window; with --frames N it\n"
      "closes after N frames and writes --out from the window's last frame.\n"
      "--rate bakes every clip at a fixed rate instead of the automatic one. --summary prints\n"
      "the character and its palette only. --model renders a glTF character (its clips, or\n"
      "those --clips names). --palette loads a palette file written by si-bake instead of\n"
      "baking. --keys presses window keys, one per frame (e.g. +,f,p,c,]) for scripted runs.\n"
      "--mix starts with a mixed scene: the character and these other glTF kinds (samples: the\n"
      "sample Fox and CesiumMan) share the field, all drawn by one renderer (key M toggles it).\n"
      "--events puts markers at the start and middle of every clip and counts the animation\n"
      "events the crowd reports (key V toggles it).\n"
      "--root-motion plays the clips that carry root motion (the embedded character's\n"
      "walk_forward and walk_turn_left) and lets the crowd move every character by it; the\n"
      "statistics give the mean distance travelled (key R toggles it).\n"
      "--motion-vectors also draws the crowd with motion vectors into an offscreen colour +\n"
      "motion target each frame; the statistics give the mean and largest motion in pixels\n"
      "(key X toggles it).\n"
      "--layers has every other character wave its right arm over what it plays (layered\n"
      "animation: the wave clip on the right clavicle's branch; key L toggles it).\n"
      "--props has every other character hold a staff in its left hand: a prop read from a\n"
      "glTF file (the sample RiggedSimple) attached at a socket (key O toggles it).\n"
      "--blend has every other character walk and run by a speed drifting over time: a blend\n"
      "space of the walk and the run, phase-synchronised (key B toggles it).\n"
      "--shadows draws the crowd's shadows on a ground plane: three shadow cascades, each a\n"
      "view of the crowd (si::CrowdView) culled and LOD'd for its own sun camera (key H).\n"
      "--lod-pixels extends the LOD chains (si::buildLodChain, errors over the clips' poses)\n"
      "and picks each character's LOD by projected error within PX pixels instead of the\n"
      "technique's distance lines.\n"
      "--impostors adds an animated impostor past the last LOD (Renderer::buildImpostor); it\n"
      "takes over from the levels that change more pixels than it at the heights it would\n"
      "draw in their place (budget: --lod-pixels, 1 if not given); not with --motion-vectors (key "
      "X is then off), and the\n"
      "baseline paths draw none. --impostor-atlas small: 8 azimuths, 2 elevations, 4 frames per\n"
      "clip (full: si::ImpostorDesc's defaults).\n"
      "--live poses the characters nearest the camera live (setLivePose): they turn their\n"
      "heads to it (a look-at on their baked pose), and every two seconds one falls flat and\n"
      "gets back up into its clip, each handed over from its clip and back (key G).\n"
      "--faces N gives the character N face-like morph targets (1 to 256; not with --palette):\n"
      "bumps over sectors of the head (what is weighted to the first joint whose name ends in\n"
      "\"head\", else what rises above 85 %% of the height), animated by every clip, each on its\n"
      "own phase. --close-up puts\n"
      "the headless camera at head height among the first rows, facing them.\n");
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      usage(stdout);
      std::exit(0);
    } else if (a == "--headless") {
      o->mode = Mode::kHeadless;
    } else if (a == "--window") {
      o->mode = Mode::kWindow;
    } else if (a == "--instances" && has) {
      o->scene.instances = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--frames" && has) {
      o->frames = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2) return false;
    } else if (a == "--out" && has) {
      o->out = argv[++i];
    } else if (a == "--rate" && has) {
      o->scene.rate_hz = std::strtof(argv[++i], nullptr);
      if (!(o->scene.rate_hz > 0.0f)) return false;
    } else if (a == "--seed" && has) {
      o->scene.seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--model" && has) {
      o->scene.model = argv[++i];
    } else if (a == "--palette" && has) {
      o->scene.palette = argv[++i];
    } else if (a == "--clips" && has) {
      o->scene.clips = si::examples::splitList(argv[++i]);
    } else if (a == "--events") {
      o->scene.events = true;
    } else if (a == "--root-motion") {
      o->scene.root_motion = true;
    } else if (a == "--motion-vectors") {
      o->scene.motion_vectors = true;
    } else if (a == "--layers") {
      o->scene.layers = true;
    } else if (a == "--props") {
      o->scene.props = true;
    } else if (a == "--blend") {
      o->scene.blend = true;
    } else if (a == "--shadows") {
      o->scene.shadows = true;
    } else if (a == "--faces" && has) {
      const long n = std::strtol(argv[++i], nullptr, 10);
      if (n < 1 || n > long(si::kMaxMorphTargets)) return false;
      o->scene.faces = uint32_t(n);
    } else if (a == "--close-up") {
      o->scene.close_up = true;
    } else if (a == "--live") {
      o->scene.live = true;
    } else if (a == "--mix" && has) {
      o->scene.mix = si::examples::splitList(argv[++i]);
      if (std::string(argv[i]) == "samples") o->scene.mix = demo::defaultMix();
    } else if (a == "--keys" && has) {
      o->window.keys = si::examples::splitList(argv[++i]);
    } else if (a == "--lod-pixels" && has) {
      o->scene.lod_pixels = std::strtof(argv[++i], nullptr);
      if (!(o->scene.lod_pixels > 0.0f) || !std::isfinite(o->scene.lod_pixels)) return false;
    } else if (a == "--impostors") {
      o->scene.impostors = true;
    } else if (a == "--impostor-atlas" && has) {
      const std::string v = argv[++i];
      if (v != "full" && v != "small") return false;
      o->scene.small_atlas = v == "small";
    } else if (a == "--summary") {
      o->summary = true;
    } else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else if (a == "--format" && has) {
      const std::string f = argv[++i];
      if (f == "f32") o->scene.format = si::PaletteFormat::kMatrix3x4F32;
      else if (f == "f16") o->scene.format = si::PaletteFormat::kMatrix3x4F16;
      else if (f == "quat") o->scene.format = si::PaletteFormat::kQuatTranslationF32;
      else return false;
    } else {
      return false;
    }
  }
  if (o->scene.faces > 0 && !o->scene.palette.empty()) return false;  // Baked without them.
  if (o->scene.impostors) {
    if (o->scene.motion_vectors) return false;  // Impostors draw no motion vectors.
    if (o->scene.lod_pixels == 0.0f) o->scene.lod_pixels = 1.0f;
  }
  return o->scene.instances > 0 && o->scene.instances <= (1u << 20) && o->width > 0 &&
         o->height > 0;
}

int fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "crowd_demo: %s: %s\n", what, s.toString().c_str());
  return 1;
}

void printStats(const demo::DemoScene& scene, const si::DrawStats& stats, double update_ms,
                double submit_ms, double gpu_ms, uint32_t frames) {
  const si::CrowdFrameStats& cs = scene.crowd().view().stats();
  std::printf("%-28s %12s\n", "statistic (last frame)", "value");
  std::printf("%-28s %12u\n", "instances", cs.instances);
  std::printf("%-28s %12u\n", "visible", cs.visible);
  for (uint32_t l = 0; l < scene.crowd().desc().lod_count; ++l)
    std::printf("%-28s %12u\n", ("visible at LOD" + std::to_string(l)).c_str(), cs.per_lod[l]);
  std::printf("%-28s %12u\n", "culled (frustum)", cs.culled_frustum);
  std::printf("%-28s %12u\n", "culled (distance)", cs.culled_distance);
  if (scene.events())
    std::printf("%-28s %12llu\n", ("animation events (" + std::to_string(frames) + " frames)").c_str(),
                static_cast<unsigned long long>(scene.eventsSinceOn()));
  if (scene.rootMotion())
    std::printf("%-28s %12.3f units\n", "root motion: mean travel", scene.meanTravel());
  if (scene.motionVectors()) {
    const si::MotionSummary& m = scene.motionSummary();
    std::printf("%-28s %12.3f px\n", "motion vectors: mean", m.mean_pixels);
    std::printf("%-28s %12.3f px\n", "motion vectors: largest", m.max_pixels);
  }
  if (scene.layers())
    std::printf("%-28s %12u\n", "layers: overlays playing", scene.overlays());
  if (scene.props()) std::printf("%-28s %12u\n", "props: staffs held", scene.propsHeld());
  if (scene.blend()) std::printf("%-28s %12u\n", "blend: characters blending", scene.blending());
  if (scene.live())
    std::printf("%-28s %12u looking, %u falling\n", "live poses:", scene.looking(),
                scene.falling());
  if (scene.palette().layout.morph_target_count > 0)
    std::printf("%-28s %12u\n", "faces: morph targets baked",
                scene.palette().layout.morph_target_count);
  if (scene.shadows())
    std::printf("%-28s %12u (3 cascades, %u drawn by the main view)\n", "shadows: casters drawn",
                scene.shadowCasters(), scene.crowd().view().stats().visible);
  if (scene.otherKinds() > 0)
    std::printf("%-28s %12u (%zu character kinds in one renderer)\n", "other kinds visible",
                scene.otherKindsVisible(), scene.otherKinds() + 1);
  std::printf("%-28s %12u\n", "draw calls", stats.draw_calls);
  std::printf("%-28s %12llu\n", "triangles", static_cast<unsigned long long>(stats.triangles));
  std::printf("%-28s %12u\n", "instances per draw (max)", scene.batcher().capacityPerDraw());
  std::printf("%-28s %12.3f\n", "CPU update ms (mean)", update_ms);
  std::printf("%-28s %12.3f\n", "CPU batch+submit ms (mean)", submit_ms);
  std::printf("%-28s %12.3f\n", "GPU ms (mean)", gpu_ms);
}

int runHeadless(const Options& o, demo::DemoScene* scene) {
  si::HeadlessDesc hd;
  hd.width = o.width;
  hd.height = o.height;
  hd.backend = o.backend;
  hd.samples = 4;
  std::unique_ptr<si::HeadlessContext> context;
  si::Status s = si::HeadlessContext::create(hd, &context);
  if (!s.isOk()) return fail("offscreen context", s);
  si::GlInfo info;
  s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail("GL", s);
  s = scene->initGl(info);
  if (!s.isOk()) {
    scene->releaseGl();
    return fail("renderer", s);
  }
  scene->setViewportSize(o.width, o.height);
  const float aspect = float(o.width) / float(o.height);
  si::Camera camera =
      o.scene.close_up ? scene->closeUpCamera(aspect) : scene->overviewCamera(aspect);
  camera.viewport_height_pixels = float(o.height);  // For --lod-pixels.
  double update_ms = 0.0, submit_ms = 0.0, gpu_ms = 0.0;
  si::DrawStats stats;
  const uint32_t frames = o.frames == 0 ? 3 : o.frames;
  for (uint32_t f = 0; f < frames; ++f) {
    s = scene->frame(1.0 / 60.0, camera, &stats);
    if (!s.isOk()) {
      scene->releaseGl();
      return fail("frame", s);
    }
    update_ms += scene->updateMs();
    submit_ms += stats.cpu_submit_ms;
    gpu_ms += stats.gpu_ms;
  }
  std::vector<uint8_t> rgba;
  s = context->readPixels(&rgba);
  if (s.isOk()) s = si::writePng(o.out, o.width, o.height, rgba);
  scene->releaseGl();  // Before the context goes.
  if (!s.isOk()) return fail("writing the image", s);
  std::printf("\nRendered %ux%u through %s (%s, GL %s); bake %.0f ms\n", o.width, o.height,
              si::headlessBackendName(context->backend()), context->renderer().c_str(),
              info.version.c_str(), scene->bakeMs());
  printStats(*scene, stats, update_ms / frames, submit_ms / frames, gpu_ms / frames, frames);
  std::printf("Wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, &o)) {
    usage(stderr);
    return 2;
  }
  demo::DemoScene scene;
  si::Status s = scene.loadCharacter(o.scene);
  if (!s.isOk()) return fail("character", s);
  if (o.summary) return 0;

  if (o.mode != Mode::kHeadless) {
    demo::WindowOptions w = o.window;
    w.width = o.width;
    w.height = o.height;
    w.frames = o.frames;
    w.out = o.frames > 0 ? o.out : std::string();
    std::string why;
    const demo::WindowResult r = demo::runWindow(w, &scene, &why);
    if (r == demo::WindowResult::kDone) return 0;
    if (r == demo::WindowResult::kFailed) {
      std::fprintf(stderr, "crowd_demo: window: %s\n", why.c_str());
      return 1;
    }
    // No display.
    if (o.mode == Mode::kWindow) {
      std::fprintf(stderr, "crowd_demo: --window: %s\n", why.c_str());
      return 1;
    }
    std::printf("No window (%s): rendering headless.\n", why.c_str());
  }
  return runHeadless(o, &scene);
}
