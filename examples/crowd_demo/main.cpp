// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo, the main job: bakes the embedded character, renders a crowd of it headless
// (EGL or OSMesa), writes a PNG and prints the frame statistics.
// Usage: crowd_demo [--instances N] [--frames N] [--size WxH] [--out PATH]
//                   [--backend auto|egl-device|egl-surfaceless|osmesa]
//                   [--format f32|f16|quat] [--rate HZ] [--seed N] [--summary]
//                   [--model FILE.gltf|FILE.glb] [--clips NAME,...]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "si/bake/animation_baker.h"
#include "si/core/core.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"
#include "si/gltf/gltf_import.h"
#include "si/headless/headless_context.h"
#include "common/example_options.h"

namespace {

struct Options {
  uint32_t instances = 4000;
  uint32_t frames = 3;
  float rate_hz = 0.0f;  // 0: the baker's automatic rates.
  uint32_t width = 1280, height = 720;
  std::string out = "crowd.png";
  si::HeadlessBackend backend = si::HeadlessBackend::kAuto;
  si::PaletteFormat format = si::PaletteFormat::kDefault;
  uint64_t seed = 7;
  bool summary = false;
  std::string model;  // glTF file; empty: the embedded character.
  std::vector<std::string> clips;
};

void usage(std::FILE* f) {
  std::fprintf(f,
               "usage: crowd_demo [--instances N] [--frames N] [--size WxH] [--out PATH]\n"
               "                  [--backend auto|egl-device|egl-surfaceless|osmesa]\n"
               "                  [--format f32|f16|quat] [--rate HZ] [--seed N] [--summary]\n"
               "                  [--model FILE.gltf|FILE.glb] [--clips NAME,NAME,...]\n"
               "Renders a crowd of the embedded character headless (N frames, 1/60 s apart;\n"
               "default 4000 characters, 3 frames, 1280x720), writes a PNG and prints frame\n"
               "statistics. --rate bakes every clip at a fixed rate instead of the automatic\n"
               "one. --summary prints the character and its palette instead. --model renders a glTF\n"
               "character (its clips, or those --clips names) instead of the embedded one.\n");
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      usage(stdout);
      std::exit(0);
    } else if (a == "--instances" && has) {
      o->instances = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--frames" && has) {
      o->frames = uint32_t(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2) return false;
    } else if (a == "--out" && has) {
      o->out = argv[++i];
    } else if (a == "--rate" && has) {
      o->rate_hz = std::strtof(argv[++i], nullptr);
      if (!(o->rate_hz > 0.0f)) return false;
    } else if (a == "--seed" && has) {
      o->seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--model" && has) {
      o->model = argv[++i];
    } else if (a == "--clips" && has) {
      std::string list = argv[++i];
      for (size_t at = 0; at <= list.size();) {
        const size_t comma = std::min(list.find(',', at), list.size());
        if (comma > at) o->clips.push_back(list.substr(at, comma - at));
        at = comma + 1;
      }
    } else if (a == "--summary") {
      o->summary = true;
    } else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else if (a == "--format" && has) {
      const std::string f = argv[++i];
      if (f == "f32") o->format = si::PaletteFormat::kMatrix3x4F32;
      else if (f == "f16") o->format = si::PaletteFormat::kMatrix3x4F16;
      else if (f == "quat") o->format = si::PaletteFormat::kQuatTranslationF32;
      else return false;
    } else {
      return false;
    }
  }
  return o->instances > 0 && o->width > 0 && o->height > 0;
}

int fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "crowd_demo: %s: %s\n", what, s.toString().c_str());
  return 1;
}

void printSummary(const si::Character& c, const si::BakedPalette& p, const si::BakeReport& r) {
  std::printf("Character '%s': %zu joints, %zu vertices, height %.3f units\n", c.name.c_str(),
              c.skeleton.jointCount(), c.mesh.vertexCount(), double(c.height()));
  std::printf("%-10s %10s %10s %10s\n", "sub-mesh", "LOD0 tris", "LOD1 tris", "LOD2 tris");
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm) {
    std::printf("%-10s", c.mesh.sub_meshes[sm].name.c_str());
    for (size_t l = 0; l < c.mesh.sub_meshes[sm].lods.size(); ++l)
      std::printf(" %10zu", c.mesh.triangleCount(sm, l));
    std::printf("\n");
  }
  std::printf("%-8s %10s %6s %9s %8s %12s\n", "clip", "duration s", "loop", "rate Hz", "frames",
              "max error");
  for (size_t i = 0; i < p.clips.size(); ++i)
    std::printf("%-8s %10.3f %6s %9.1f %8u %12.3g\n", p.clips[i].name.c_str(),
                double(p.clips[i].duration_seconds),
                p.clips[i].loop_mode == si::LoopMode::kLoop ? "yes" : "no",
                p.clips[i].sampleRateHz(), p.clips[i].frame_count, r.clips[i].max_error_units);
  std::printf("Palette %s: %ux%u texels, %.1f KiB, %zu of %zu joints stored; max error %.3g "
              "units (%.2g of the height)\n",
              si::paletteFormatName(p.format), p.layout.width, p.layout.height,
              double(r.palette_bytes) / 1024.0, p.palette_joints.size(), c.skeleton.jointCount(),
              r.max_error_units, r.max_error_ratio);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, &o)) {
    usage(stderr);
    return 2;
  }
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };

  si::Character character;
  si::Status s;
  if (o.model.empty()) {
    s = si::makeDefaultCharacter({}, &character);
  } else {
    si::GltfImportReport gr;
    s = si::importGltfFile(o.model, {}, &character, &gr);
    for (const std::string& w : gr.warnings) std::printf("warning: %s\n", w.c_str());
    if (s.isOk() && character.clips.empty())
      s = si::Status(si::StatusCode::kUnsupported, "the model has no animation clips");
  }
  if (!s.isOk()) return fail("character", s);
  si::BakeDesc bake;
  bake.format = o.format;
  bake.clip_names = o.clips;
  if (o.rate_hz > 0.0f) {
    bake.rate_mode = si::RateMode::kFixed;
    bake.sample_rate_hz = o.rate_hz;
  }
  si::BakedPalette palette;
  si::BakeReport report;
  const auto bake_start = Clock::now();
  s = si::bakePalette(character, bake, &palette, &report);
  if (!s.isOk()) return fail("bake", s);
  const double bake_ms = ms(bake_start, Clock::now());
  printSummary(character, palette, report);
  if (o.summary) return 0;

  si::HeadlessDesc hd;
  hd.width = o.width;
  hd.height = o.height;
  hd.backend = o.backend;
  hd.samples = 4;
  std::unique_ptr<si::HeadlessContext> context;
  s = si::HeadlessContext::create(hd, &context);
  if (!s.isOk()) return fail("offscreen context", s);
  si::GlInfo info;
  s = si::loadGl(&si::HeadlessContext::getProcAddress, context.get(), &info);
  if (!s.isOk()) return fail("GL", s);
  si::Renderer renderer;
  si::RendererDesc rd;
  rd.measure_gpu_time = true;
  s = renderer.init(info, rd);
  if (s.isOk()) s = renderer.uploadPalette(palette);
  if (s.isOk()) s = renderer.uploadCharacter(character, palette);
  if (!s.isOk()) return fail("renderer", s);

  // A field of characters on a jittered grid, 1.6 m apart, looking every which way.
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character.mesh.maxLodCount());
  si::CrowdManager crowd;
  s = crowd.init(cd);
  if (!s.isOk()) return fail("crowd", s);
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(o.instances))));
  std::vector<glm::dvec3> positions;
  uint64_t state = o.seed * 0x9E3779B97F4A7C15ull + 1;
  const auto jitter = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (double((state >> 33) & 0xFFFF) / 65535.0 - 0.5) * 0.6;
  };
  // Lay the crowd out in units of the character's size (the embedded one is 2.05 units tall).
  const double unit = std::max(1e-3, double(character.height())) / 2.05;
  for (uint32_t i = 0; i < o.instances; ++i)
    positions.push_back(glm::dvec3((i % side) * 1.6 + jitter(), 0.0, (i / side) * 1.6 + jitter()) *
                        unit);
  si::RandomCrowdDesc rc;
  rc.positions = positions;
  rc.seed = o.seed;
  // The embedded character: the body always, helmet, shield and spear at random. A model:
  // every sub-mesh.
  const uint32_t all = cd.sub_mesh_count >= 32 ? 0xFFFFFFFFu : (1u << cd.sub_mesh_count) - 1u;
  rc.required_mask = o.model.empty() ? 1u : all;
  rc.optional_mask = o.model.empty() ? 0xEu : 0u;
  s = crowd.addRandom(rc, nullptr);
  if (!s.isOk()) return fail("crowd", s);
  si::InstanceBatcher batcher;
  s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return fail("batcher", s);

  // At the field's edge, 9 m up, looking in: the far line (100 character radii) bounds what a
  // large crowd shows, as the technique's LOD scheme intends.
  const double extent = side * 1.6;
  const si::Camera camera = si::Camera::lookAt(
      glm::dvec3(extent * 0.5, 9.0, -7.0) * unit,
      glm::dvec3(extent * 0.5, 0.0, std::min(extent * 0.45, 45.0)) * unit, glm::vec3(0, 1, 0),
      0.9f, float(o.width) / float(o.height), float(0.2 * unit), float(2000.0 * unit));
  double update_ms = 0.0, submit_ms = 0.0, gpu_ms = 0.0;
  si::DrawStats stats;
  for (uint32_t f = 0; f < std::max(1u, o.frames); ++f) {
    const auto t0 = Clock::now();
    s = crowd.update(1.0 / 60.0, camera);
    if (!s.isOk()) return fail("update", s);
    update_ms += ms(t0, Clock::now());
    renderer.clear(glm::vec4(0.62f, 0.66f, 0.58f, 1.0f));
    s = renderer.drawCrowd(crowd, batcher, camera, &stats);
    if (!s.isOk()) return fail("draw", s);
    submit_ms += stats.cpu_submit_ms;
    gpu_ms += stats.gpu_ms;
  }
  std::vector<uint8_t> rgba;
  s = context->readPixels(&rgba);
  if (s.isOk()) s = si::writePng(o.out, o.width, o.height, rgba);
  if (!s.isOk()) return fail("writing the image", s);

  const double n = std::max(1u, o.frames);
  const si::CrowdFrameStats& cs = crowd.stats();
  std::printf("\nRendered %ux%u through %s (%s, GL %s); bake %.0f ms\n", o.width, o.height,
              si::headlessBackendName(context->backend()), context->renderer().c_str(),
              info.version.c_str(), bake_ms);
  std::printf("%-28s %12s\n", "statistic (last frame)", "value");
  std::printf("%-28s %12u\n", "instances", cs.instances);
  std::printf("%-28s %12u\n", "visible", cs.visible);
  for (uint32_t l = 0; l < cd.lod_count; ++l)
    std::printf("%-28s %12u\n", ("visible at LOD" + std::to_string(l)).c_str(), cs.per_lod[l]);
  std::printf("%-28s %12u\n", "culled (frustum)", cs.culled_frustum);
  std::printf("%-28s %12u\n", "culled (distance)", cs.culled_distance);
  std::printf("%-28s %12u\n", "draw calls", stats.draw_calls);
  std::printf("%-28s %12llu\n", "triangles", static_cast<unsigned long long>(stats.triangles));
  std::printf("%-28s %12u\n", "instances per draw (max)", batcher.capacityPerDraw());
  std::printf("%-28s %12.3f\n", "CPU update ms (mean)", update_ms / n);
  std::printf("%-28s %12.3f\n", "CPU batch+submit ms (mean)", submit_ms / n);
  std::printf("%-28s %12.3f\n", "GPU ms (mean)", gpu_ms / n);
  std::printf("Wrote %s\n", o.out.c_str());
  return 0;
}
