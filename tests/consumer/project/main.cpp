// Links every layer through the exported targets and runs a little of each; then draws one
// crowd twice, with si::Renderer and with an engine's own renderer built on the installed GLSL
// include (own_renderer.cpp), and requires the same image. Without an offscreen GL context the
// drawing part is skipped, unless SI_REQUIRE_GL is set (CI): then it fails.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "own_renderer.h"
#include "si/bake/animation_baker.h"
#include "si/bake/bake_desc.h"
#include "si/core/core.h"
#include "si/crowd/handle_pool.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"
#include "si/gltf/asset_path.h"
#include "si/headless/headless_context.h"

#ifndef SI_CONSUMER_GLSL_DIR
#error "SI_CONSUMER_GLSL_DIR must name the folder of si_skinning.glsl"
#endif

namespace {

constexpr uint32_t kSize = 192;
constexpr float kClear[3] = {0.1f, 0.1f, 0.1f};

int fail(const std::string& what) {
  std::fprintf(stderr, "consumer: %s\n", what.c_str());
  return 1;
}

// A few characters close to the camera, each with its own clip, time, tint and armour.
si::Status makeCrowd(const si::BakedPalette& palette, si::CrowdManager* crowd,
                     si::Camera* camera) {
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = 4;
  cd.lod_count = 3;
  si::Status s = crowd->init(cd);
  for (int k = 0; k < 5 && s.isOk(); ++k) {
    si::InstanceDesc d;
    d.position = glm::dvec3(-2.0 + k, 0.0, -1.5 * (k % 2));
    d.clip = uint32_t(k) % uint32_t(palette.clips.size());
    d.time_seconds = 0.17 * k;
    d.variation_mask = 1u | (uint32_t(k) << 1);
    d.color = glm::u8vec4(uint8_t(60 + 40 * k), uint8_t(220 - 30 * k), 90, 255);
    si::InstanceHandle h;
    s = crowd->add(d, &h);
  }
  *camera = si::Camera::lookAt({0.0, 1.6, 5.0}, {0.0, 0.9, -0.5}, glm::vec3(0, 1, 0), 0.9f, 1.0f,
                               0.1f, 100.0f);
  return s.isOk() ? crowd->update(0.4, *camera) : s;
}

}  // namespace

int main() {
  si::Character c;
  si::Status s = si::makeDefaultCharacter({}, &c);
  si::PalettePlan plan;
  if (s.isOk()) s = si::planPalette(c, {}, &plan);
  si::HandlePool pool;
  si::InstanceHandle h;
  if (s.isOk()) s = pool.allocate(&h);
  std::string path;
  if (s.isOk()) s = si::resolveAssetUri("/a", "b.bin", &path);
  if (!s.isOk()) return fail(s.toString());
  std::printf("consumer ok: %zu joints, palette %ux%u, %s, %s\n", c.skeleton.jointCount(),
              plan.layout.width, plan.layout.height, path.c_str(),
              si::headlessBackendName(si::HeadlessBackend::kAuto));

  // ---- The same crowd through si::Renderer and through the engine's own renderer.
  si::HeadlessDesc hd;
  hd.width = hd.height = kSize;
  hd.backend = si::HeadlessBackend::kEglSurfaceless;  // Mesa's: the one CI has.
  std::unique_ptr<si::HeadlessContext> context;
  s = si::HeadlessContext::create(hd, &context);
  if (!s.isOk()) {
    if (std::getenv("SI_REQUIRE_GL") != nullptr) return fail("no GL context: " + s.toString());
    std::printf("consumer: no offscreen GL context, drawing skipped (%s)\n", s.message().c_str());
    return 0;
  }
  si::BakeDesc bd;
  bd.rate_mode = si::RateMode::kFixed;
  bd.sample_rate_hz = 30.0f;
  si::BakedPalette palette;
  s = si::bakePalette(c, bd, &palette, nullptr);
  si::CrowdManager crowd;
  si::Camera camera;
  if (s.isOk()) s = makeCrowd(palette, &crowd, &camera);
  si::GlInfo info;
  if (s.isOk()) s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail(s.toString());

  std::vector<uint8_t> library_image, own_image;
  {
    si::Renderer renderer;
    si::RendererDesc rd;
    rd.skinning_path = si::SkinningPath::kVertexShader;
    s = renderer.init(info, rd);
    if (s.isOk()) s = renderer.uploadPalette(palette);
    if (s.isOk()) s = renderer.uploadCharacter(c, palette);
    si::InstanceBatcher batcher;
    if (s.isOk()) s = batcher.init(renderer.batchLimits());
    renderer.clear(glm::vec4(kClear[0], kClear[1], kClear[2], 1.0f));
    si::DrawStats stats;
    if (s.isOk()) s = renderer.drawCrowd(crowd, batcher, camera, &stats);
    if (s.isOk()) s = context->readPixels(&library_image);
    if (!s.isOk()) return fail("library renderer: " + s.toString());
  }
  const glm::mat4 vp = camera.viewProjection();
  const glm::vec3 light = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));  // The renderer's.
  const std::string error = consumer::drawWithOwnRenderer(
      &si::HeadlessContext::getProcAddress, context.get(), SI_CONSUMER_GLSL_DIR, c, palette,
      crowd, &vp[0][0], &light[0], kClear, info.max_uniform_block_size_bytes,
      info.uniform_buffer_offset_alignment);
  if (!error.empty()) return fail("own renderer: " + error);
  s = context->readPixels(&own_image);
  if (!s.isOk()) return fail(s.toString());

  // Same image: no channel off by more than 2/255 (the same arithmetic on the same GPU), and
  // the crowd covers part of it (an empty frame would also be equal).
  size_t differing = 0, covered = 0;
  for (size_t p = 0; p < own_image.size(); p += 4) {
    int m = 0;
    for (int ch = 0; ch < 3; ++ch)
      m = std::max(m, std::abs(int(own_image[p + ch]) - int(library_image[p + ch])));
    if (m > 2) ++differing;
    if (library_image[p] != library_image[0] || library_image[p + 1] != library_image[1])
      ++covered;  // The top-left pixel is background.
  }
  std::printf("consumer: own renderer on %s: %zu of %zu pixels differ, %zu covered by the crowd\n",
              context->renderer().c_str(), differing, own_image.size() / 4, covered);
  if (covered < 1000) return fail("the crowd covers too little of the frame to compare");
  if (differing > 0) {
    (void)si::writePng("consumer_library.png", kSize, kSize, library_image);
    (void)si::writePng("consumer_own.png", kSize, kSize, own_image);
    return fail("the own renderer's image differs (consumer_library.png, consumer_own.png)");
  }
  return 0;
}
