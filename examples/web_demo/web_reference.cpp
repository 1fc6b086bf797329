// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The browser page's test frame drawn natively: the same scene (web_scene.h) at the same time
// on an OpenGL ES 3 context of si::headless (EGL), the reference tests/web/browser_test.sh
// compares the page's screenshot with. With --compare, reads that screenshot, takes the
// canvas's pixels (its top-left 960 x 540) and prints the share of pixels differing by more than
// 8/255 in a channel; exits 1 when the share passes --max-share.
// With --bench N, then plays N more frames of 1/30 s as the page does and prints the CPU
// milliseconds a frame (update and draw calls, the page's "CPU" figure) and the whole frame's
// (to the read-back of the image, which waits for the GPU): scripts/web_bench.sh sets them
// beside the page's.
// Usage: web_reference --palette FILE --frames N --out REF.png [--instances N]
//                      [--compare SHOT.png] [--max-share S] [--bench N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "si/core/default_character.h"
#include "si/core/palette_file.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"
#include "web_scene.h"

namespace {

constexpr uint32_t kWidth = 960, kHeight = 540;

int fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "web_reference: %s: %s\n", what, s.toString().c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string palette_path, out, compare;
  int frames = 10, bench = 0;
  uint32_t instances = si::web::kDefaultInstances;
  double max_share = 0.02;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--palette")
      palette_path = v;
    else if (k == "--frames")
      frames = std::atoi(v.c_str());
    else if (k == "--out")
      out = v;
    else if (k == "--instances")
      instances = uint32_t(std::max(1, std::atoi(v.c_str())));
    else if (k == "--compare")
      compare = v;
    else if (k == "--max-share")
      max_share = std::atof(v.c_str());
    else if (k == "--bench")
      bench = std::max(0, std::atoi(v.c_str()));
    else
      return fail("arguments", {si::StatusCode::kInvalidArgument, "unknown option " + k});
  }
  if (palette_path.empty() || out.empty() || frames < 1)
    return fail("arguments", {si::StatusCode::kInvalidArgument,
                              "--palette FILE --frames N (>= 1) --out REF.png are required"});
  std::ifstream in(palette_path, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  si::Character character;
  si::BakedPalette palette;
  si::Status s = si::makeDefaultCharacter({}, &character);
  if (s.isOk()) s = si::loadPalette(bytes, &palette);
  if (!s.isOk()) return fail(palette_path.c_str(), s);
  si::HeadlessDesc hd;
  hd.width = kWidth;
  hd.height = kHeight;
  hd.es = true;
  std::unique_ptr<si::HeadlessContext> context;
  s = si::HeadlessContext::create(hd, &context);
  si::GlInfo info;
  if (s.isOk()) s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail("an OpenGL ES context", s);
  si::Renderer renderer;
  si::CharacterId id;
  si::InstanceBatcher batcher;
  si::CrowdManager crowd;
  s = renderer.init(info, {});
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (s.isOk()) s = si::web::buildCrowd(character, palette, instances, &crowd);
  const si::Camera camera = si::web::orbitCamera({}, instances, float(kWidth) / float(kHeight));
  // The page's frame `frames` (from 1) plays at (frames - 1) steps of the crowd clock.
  if (s.isOk()) s = crowd.update((frames - 1) * si::web::kTestStepSeconds, camera);
  renderer.clear(glm::vec4(0.55f, 0.62f, 0.7f, 1.0f));
  if (s.isOk()) s = renderer.drawCrowd(crowd, batcher, camera, nullptr);
  std::vector<uint8_t> reference;
  if (s.isOk()) s = context->readPixels(&reference);
  if (s.isOk()) s = si::writePng(out, kWidth, kHeight, reference);
  if (!s.isOk()) return fail("drawing the reference", s);
  std::printf("web_reference: %s (%s), frame %d, %u characters\n", out.c_str(),
              info.version.c_str(), frames, instances);
  if (bench > 0) {
    double cpu_ms = 0.0, frame_ms = 0.0;
    std::vector<uint8_t> image;
    for (int f = 0; f < bench && s.isOk(); ++f) {
      const auto t0 = std::chrono::steady_clock::now();
      s = crowd.update(si::web::kTestStepSeconds, camera);
      renderer.clear(glm::vec4(0.55f, 0.62f, 0.7f, 1.0f));
      if (s.isOk()) s = renderer.drawCrowd(crowd, batcher, camera, nullptr);
      const auto t1 = std::chrono::steady_clock::now();
      if (s.isOk()) s = context->readPixels(&image);
      const auto t2 = std::chrono::steady_clock::now();
      cpu_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
      frame_ms += std::chrono::duration<double, std::milli>(t2 - t0).count();
    }
    if (!s.isOk()) return fail("the benchmark frames", s);
    std::printf(
        "web_reference: native %s, %u characters, %d frames: CPU %.2f ms a frame, "
        "frame %.2f ms (%.1f frames/s)\n",
        info.renderer.c_str(), instances, bench, cpu_ms / bench, frame_ms / bench,
        1000.0 * bench / frame_ms);
  }
  if (compare.empty()) return 0;
  uint32_t w = 0, h = 0;
  std::vector<uint8_t> shot;
  s = si::readPng(compare, &w, &h, &shot);
  if (!s.isOk()) return fail(compare.c_str(), s);
  if (w < kWidth || h < kHeight)
    return fail(compare.c_str(), {si::StatusCode::kCountMismatch, "smaller than the canvas"});
  size_t differing = 0;
  int max_channel = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const uint8_t* a = &reference[(size_t(y) * kWidth + x) * 4];
      const uint8_t* b = &shot[(size_t(y) * w + x) * 4];
      int m = 0;
      for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[c]) - int(b[c])));
      max_channel = std::max(max_channel, m);
      differing += m > 8 ? 1 : 0;
    }
  const double share = double(differing) / double(kWidth * kHeight);
  std::printf(
      "web_reference: %s against the reference: %.3f %% of pixels differ by more than "
      "8/255 (largest %d), allowed %.3f %%\n",
      compare.c_str(), share * 100.0, max_channel, max_share * 100.0);
  return share <= max_share ? 0 : 1;
}
