// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The browser page's frames drawn natively: the same scene (web_scene.h) on an OpenGL ES 3
// context of si::headless (EGL), driven by the same script of frames and control moves the
// browser test (tests/web/browser_drive.py) plays on the page. The actions run in order:
//   --step DT            draws a frame after stepping the clock by DT seconds (si_web_step)
//   --drag DX DY         a drag of (DX, DY) pixels (the page's pointer handler)
//   --wheel DY           a wheel turn (the page's wheel handler, WheelEvent.deltaY)
//   --set-instances N    the crowd size select
//   --lod SCALE          the LOD distance slider
//   --out FILE           writes the last frame to FILE (PNG)
//   --check SHOT STATS   compares the last frame with the page's canvas SHOT (PNG, its top-left
//                        960 x 540; the share of pixels differing by more than 8/255 in a
//                        channel, at most --max-share) and the scene's statistics line with
//                        the first line of the page's STATS text (it must begin with it);
//                        writes the frame beside SHOT as SHOT.reference.png
//   --bench N            plays N more frames of 1/30 s and prints the CPU milliseconds a frame
//                        (update and draw calls, the page's "CPU" figure) and the whole frame's
//                        (to the read-back, which waits for the GPU): scripts/web_bench.sh
// Options: --palette FILE (required), --instances N (the first crowd size), --max-share S,
// --desktop (the same scene on a desktop OpenGL 4.5 context instead: the ES profile's cost
// against the desktop back-end's, both on the vertex-shader path, with --bench).
// Exits 1 when a check fails, 2 on an error.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "si/core/default_character.h"
#include "si/core/palette_file.h"
#include "si/gl/gl_context.h"
#include "si/headless/headless_context.h"
#include "web_scene.h"

namespace {

constexpr uint32_t kWidth = 960, kHeight = 540;
constexpr float kAspect = float(kWidth) / float(kHeight);

int fail(const std::string& what, const si::Status& s) {
  std::fprintf(stderr, "web_reference: %s: %s\n", what.c_str(), s.toString().c_str());
  return 2;
}

// The share of pixels of `reference` (kWidth x kHeight) differing from the top-left of `shot`
// by more than 8/255 in a colour channel, and the largest difference.
double differingShare(const std::vector<uint8_t>& reference, const std::vector<uint8_t>& shot,
                      uint32_t shot_width, int* max_channel) {
  size_t differing = 0;
  *max_channel = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const uint8_t* a = &reference[(size_t(y) * kWidth + x) * 4];
      const uint8_t* b = &shot[(size_t(y) * shot_width + x) * 4];
      int m = 0;
      for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[c]) - int(b[c])));
      *max_channel = std::max(*max_channel, m);
      differing += m > 8 ? 1 : 0;
    }
  return double(differing) / double(kWidth * kHeight);
}

// --check: 0 when SHOT and STATS match the last frame, 1 when not, 2 on an error.
int check(const si::web::Scene& scene, const std::vector<uint8_t>& frame, const std::string& shot,
          const std::string& stats_file, double max_share) {
  uint32_t w = 0, h = 0;
  std::vector<uint8_t> pixels;
  si::Status s = si::readPng(shot, &w, &h, &pixels);
  if (!s.isOk()) return fail(shot, s);
  if (w < kWidth || h < kHeight)
    return fail(shot, {si::StatusCode::kCountMismatch, "smaller than the canvas"});
  s = si::writePng(shot + ".reference.png", kWidth, kHeight, frame);
  if (!s.isOk()) return fail(shot + ".reference.png", s);
  int max_channel = 0;
  const double share = differingShare(frame, pixels, w, &max_channel);
  std::ifstream in(stats_file);
  std::string page_stats;
  std::getline(in, page_stats);
  const std::string stats = scene.statsLine();
  const bool same_stats = page_stats.compare(0, stats.size(), stats) == 0;
  std::printf(
      "web_reference: %s: %.3f %% of pixels differ by more than 8/255 (largest %d), allowed "
      "%.3f %%\n  statistics: %s\n  the page's:  %s\n",
      shot.c_str(), share * 100.0, max_channel, max_share * 100.0, stats.c_str(),
      page_stats.c_str());
  if (!same_stats) std::printf("web_reference: the page's statistics differ\n");
  return share <= max_share && same_stats ? 0 : 1;
}

// --bench N: N frames of 1/30 s, timed.
si::Status bench(si::web::Scene& scene, si::HeadlessContext& context, int frames,
                 const std::string& renderer) {
  double cpu_ms = 0.0, frame_ms = 0.0;
  std::vector<uint8_t> image;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    si::Status s = scene.frame(si::web::kTestStepSeconds, kAspect, nullptr);
    const auto t1 = std::chrono::steady_clock::now();
    if (s.isOk()) s = context.readPixels(&image);
    if (!s.isOk()) return s;
    const auto t2 = std::chrono::steady_clock::now();
    cpu_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    frame_ms += std::chrono::duration<double, std::milli>(t2 - t0).count();
  }
  std::printf(
      "web_reference: native %s, %u characters, %d frames: CPU %.2f ms a frame, frame %.2f ms "
      "(%.1f frames/s)\n",
      renderer.c_str(), scene.instances(), frames, cpu_ms / frames, frame_ms / frames,
      1000.0 * frames / frame_ms);
  return si::Status::ok();
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  std::string palette_path;
  uint32_t instances = si::web::kDefaultInstances;
  double max_share = 0.005;
  bool desktop = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--desktop") desktop = true;
    if (i + 1 == args.size()) break;
    if (args[i] == "--palette") palette_path = args[i + 1];
    if (args[i] == "--instances") instances = uint32_t(std::max(1, std::atoi(args[i + 1].c_str())));
    if (args[i] == "--max-share") max_share = std::atof(args[i + 1].c_str());
  }
  if (palette_path.empty())
    return fail("arguments", {si::StatusCode::kInvalidArgument, "--palette FILE is required"});
  std::ifstream in(palette_path, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  si::Character character;
  si::BakedPalette palette;
  si::Status s = si::makeDefaultCharacter({}, &character);
  if (s.isOk()) s = si::loadPalette(bytes, &palette);
  if (!s.isOk()) return fail(palette_path, s);
  si::HeadlessDesc hd;
  hd.width = kWidth;
  hd.height = kHeight;
  hd.es = !desktop;
  std::unique_ptr<si::HeadlessContext> context;
  s = si::HeadlessContext::create(hd, &context);
  si::GlInfo info;
  if (s.isOk()) s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail(desktop ? "an OpenGL context" : "an OpenGL ES context", s);
  si::web::Scene scene;
  si::RendererDesc rd;
  rd.skinning_path = si::SkinningPath::kVertexShader;  // The ES profile's path, on both.
  s = scene.init(info, rd, character, palette, instances);
  if (!s.isOk()) return fail("the scene", s);
  std::vector<uint8_t> frame;  // The last frame's pixels, read back at --out and --check.
  bool drawn = false;
  int result = 0;
  // The actions, in order; each takes its values from the arguments after it.
  auto value = [&](size_t i) { return i < args.size() ? args[i] : std::string(); };
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--palette" || a == "--instances" || a == "--max-share") {
      ++i;
    } else if (a == "--desktop") {
    } else if (a == "--step") {
      s = scene.frame(std::atof(value(++i).c_str()), kAspect, nullptr);
      drawn = true;
    } else if (a == "--drag") {
      const double dx = std::atof(value(++i).c_str());
      scene.drag(dx, std::atof(value(++i).c_str()));
    } else if (a == "--wheel") {
      scene.wheel(std::atof(value(++i).c_str()));
    } else if (a == "--set-instances") {
      s = scene.setInstances(uint32_t(std::max(1, std::atoi(value(++i).c_str()))));
    } else if (a == "--lod") {
      s = scene.setLodScale(std::atof(value(++i).c_str()));
    } else if ((a == "--out" || a == "--check") && !drawn) {
      s = {si::StatusCode::kInvalidArgument, a + " before the first --step"};
    } else if (a == "--out") {
      s = context->readPixels(&frame);
      if (s.isOk()) s = si::writePng(value(++i), kWidth, kHeight, frame);
    } else if (a == "--check") {
      s = context->readPixels(&frame);
      if (!s.isOk()) return fail(a, s);
      const std::string shot = value(++i), stats = value(++i);
      const int r = check(scene, frame, shot, stats, max_share);
      if (r == 2) return r;
      result = std::max(result, r);
    } else if (a == "--bench") {
      s = bench(scene, *context, std::max(1, std::atoi(value(++i).c_str())),
                info.renderer + ", " + info.version);
    } else {
      s = {si::StatusCode::kInvalidArgument, "unknown action " + a};
    }
    if (!s.isOk()) return fail(a, s);
  }
  std::printf("web_reference: %s, %u characters at the end\n", info.version.c_str(),
              scene.instances());
  return result;
}
