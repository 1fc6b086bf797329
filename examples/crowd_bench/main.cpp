// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_bench: the instanced path against its baselines, in the same run on the same scenes,
// and GPU time against bake error. Prints tables, writes a CSV and, when gnuplot is installed,
// PNG plots. See docs/performance.md for how the published figures were produced.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"
#include "common/example_options.h"

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

struct Options {
  std::vector<uint32_t> sizes = {1000, 4000};
  std::vector<std::string> scenes = {"field", "stadium"};
  std::vector<std::string> paths = {"instanced", "compute", "gpu-culled", "traditional", "cpu",
                                    "rigid"};
  uint32_t frames = 5;
  uint32_t width = 1280, height = 720;
  uint32_t max_baseline = 20000;  // Traditional and CPU skinning are skipped above this.
  uint32_t error_table_size = 2000;
  std::string error_path = "instanced";  // The path the speed-against-error table draws with.
  std::string csv = "crowd_bench.csv";
  std::string plots;  // Folder for PNG plots (gnuplot), empty for none.
  bool quick = false;  // Fixed-rate bakes only (smoke tests under sanitizers).
  bool gpu_timer = true;  // Timer queries (they block each frame); off: CPU figures only.
  si::HeadlessBackend backend = si::HeadlessBackend::kAuto;
};

void usage(std::FILE* f) {
  std::fprintf(f,
      "Times per path are medians over the measured frames (after 2 warm-up frames).\n"
      "Paths: instanced (vertex-shader skinning), compute (compute pre-skinning), gpu-culled\n"
      "(culling, LOD and records on the GPU, one multi-draw; the CPU only advances the clock),\n"
      "traditional (one draw per character), cpu (CPU skinning), rigid (no skinning: the floor).\n"
      "usage: crowd_bench [--sizes N,N,...] [--scenes field,stadium] [--frames N]\n"
      "                   [--paths instanced,compute,gpu-culled,traditional,cpu,rigid]\n"
      "                   [--size WxH]\n"
      "                   [--max-baseline N] [--error-table-size N] [--csv PATH]\n"
      "                   [--error-path instanced|compute]\n"
      "                   [--plots DIR] [--backend auto|egl-device|egl-surfaceless|osmesa]\n"
      "                   [--quick]   (fixed-rate bakes only, for smoke tests)\n"
      "                   [--no-gpu-time] (no blocking timer queries: CPU columns only;\n"
      "                   GPU ms and the GPU-culled path's visible count read -1 / 0)\n");
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--help") { usage(stdout); std::exit(0); }
    else if (a == "--sizes" && has) {
      o->sizes.clear();
      for (const std::string& v : si::examples::splitList(argv[++i]))
        o->sizes.push_back(uint32_t(std::stoul(v)));
    } else if (a == "--scenes" && has) o->scenes = si::examples::splitList(argv[++i]);
    else if (a == "--paths" && has) o->paths = si::examples::splitList(argv[++i]);
    else if (a == "--frames" && has) o->frames = uint32_t(std::stoul(argv[++i]));
    else if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2) return false;
    } else if (a == "--max-baseline" && has) o->max_baseline = uint32_t(std::stoul(argv[++i]));
    else if (a == "--error-table-size" && has) o->error_table_size = uint32_t(std::stoul(argv[++i]));
    else if (a == "--error-path" && has) o->error_path = argv[++i];
    else if (a == "--csv" && has) o->csv = argv[++i];
    else if (a == "--plots" && has) o->plots = argv[++i];
    else if (a == "--quick") o->quick = true;
    else if (a == "--no-gpu-time") o->gpu_timer = false;
    else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else return false;
  }
  for (const std::string& s : o->scenes)
    if (s != "field" && s != "stadium") return false;
  for (const std::string& p : o->paths)
    if (p != "instanced" && p != "compute" && p != "gpu-culled" && p != "traditional" &&
        p != "cpu" && p != "rigid")
      return false;
  if (o->error_path != "instanced" && o->error_path != "compute") return false;
  return !o->sizes.empty() && o->frames > 0;
}

// Seeded, deterministic scenes. Field: a square grid 1.5 m apart. Stadium: a bowl of tiers
// rising around a pitch, seats 0.9 m apart, tiers 1.0 m deeper and 0.5 m higher each.
std::vector<glm::dvec3> scenePositions(const std::string& scene, uint32_t count) {
  std::vector<glm::dvec3> p;
  p.reserve(count);
  if (scene == "field") {
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(count))));
    for (uint32_t i = 0; i < count; ++i) p.push_back(glm::dvec3(i % side, 0, i / side) * 1.5);
    return p;
  }
  for (uint32_t tier = 0; p.size() < count; ++tier) {
    const double radius = 40.0 + tier * 1.0;
    const uint32_t seats = uint32_t(2.0 * 3.14159265358979 * radius / 0.9);
    for (uint32_t s = 0; s < seats && p.size() < count; ++s) {
      const double a = 2.0 * 3.14159265358979 * s / seats;
      p.push_back(glm::dvec3(radius * std::cos(a), tier * 0.5, radius * std::sin(a)));
    }
  }
  return p;
}

// The fixed camera path of frame f of n. Field: orbiting high enough to see the whole field.
// Stadium: standing on the pitch, turning round.
si::Camera cameraAt(const std::string& scene, const std::vector<glm::dvec3>& positions,
                    uint32_t f, uint32_t n, float aspect) {
  const double t = n > 1 ? double(f) / double(n - 1) : 0.0;
  if (scene == "field") {
    glm::dvec3 lo(1e30), hi(-1e30);
    for (const glm::dvec3& q : positions) lo = glm::min(lo, q), hi = glm::max(hi, q);
    const glm::dvec3 c = 0.5 * (lo + hi);
    const double r = std::max(10.0, glm::length(hi - lo) * 0.75);
    const double a = 0.3 + 0.5 * t;
    return si::Camera::lookAt(c + glm::dvec3(r * std::cos(a), r * 0.8, r * std::sin(a)), c,
                              glm::vec3(0, 1, 0), 0.9f, aspect, 1.0f, float(r * 4));
  }
  const double a = 6.28318530718 * t * 0.25;
  return si::Camera::lookAt({0, 6, 0}, {std::cos(a) * 40, 8, std::sin(a) * 40}, glm::vec3(0, 1, 0),
                            1.2f, aspect, 0.5f, 1000.0f);
}

struct Row {
  std::string scene, path;
  uint32_t instances = 0, visible = 0, draws = 0;
  double triangles = 0, update_ms = 0, submit_ms = 0, gpu_ms = 0;  // Medians over the frames.
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct Bench {
  Options o;
  std::unique_ptr<si::HeadlessContext> context;
  si::GlInfo info;
  si::Character character;
};

int fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "crowd_bench: %s: %s\n", what, s.toString().c_str());
  return 1;
}

// Runs one path on one scene; returns false (after printing) on an error.
bool runPath(Bench& b, si::Renderer& renderer, const si::BakedPalette& palette,
             const std::string& scene, uint32_t count, const std::string& path, Row* row) {
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(b.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(b.character.mesh.maxLodCount());
  cd.max_distance_radii = -1.0f;  // Measure everything in view, however far.
  si::CrowdManager crowd;
  si::Status s = crowd.init(cd);
  const std::vector<glm::dvec3> positions = scenePositions(scene, count);
  si::RandomCrowdDesc rc;
  rc.positions = positions;
  rc.seed = 2026;
  rc.optional_mask = 0xE;
  if (s.isOk()) s = crowd.addRandom(rc, nullptr);
  si::InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return fail("scene", s) == 0;
  const float aspect = float(b.o.width) / float(b.o.height);
  row->scene = scene;
  row->path = path;
  row->instances = count;
  const uint32_t warmup = 2, n = b.o.frames;
  std::vector<double> update_ms_v, submit_ms_v, gpu_ms_v;
  for (uint32_t f = 0; f < warmup + n; ++f) {
    const si::Camera cam = cameraAt(scene, positions, f < warmup ? 0 : f - warmup, n, aspect);
    const auto t0 = Clock::now();
    const bool gpu_culled = path == "gpu-culled";
    s = gpu_culled ? crowd.advanceClock(1.0 / 60.0) : crowd.update(1.0 / 60.0, cam);
    const double update_ms = msSince(t0);
    renderer.clear(glm::vec4(0.6f, 0.65f, 0.6f, 1.0f));
    si::DrawStats st;
    if (s.isOk()) {
      if (gpu_culled)
        s = renderer.drawCrowdGpuCulled(crowd, cam, &st);
      else if (path == "instanced")
        s = renderer.drawCrowd(crowd, batcher, cam, &st, si::DrawMode::kSkinned);
      else if (path == "compute")
        s = renderer.drawCrowd(crowd, batcher, cam, &st, si::DrawMode::kComputeSkinned);
      else if (path == "rigid") s = renderer.drawCrowd(crowd, batcher, cam, &st, si::DrawMode::kRigid);
      else if (path == "traditional") s = renderer.drawTraditional(crowd, cam, &st);
      else s = renderer.drawCpuSkinned(crowd, cam, &st);
    }
    if (!s.isOk()) return fail(path.c_str(), s) == 0;
    if (f < warmup) continue;
    update_ms_v.push_back(update_ms);
    submit_ms_v.push_back(st.cpu_submit_ms);
    gpu_ms_v.push_back(st.gpu_ms);
    row->visible = gpu_culled ? st.gpu_visible : crowd.stats().visible;
    row->draws = st.draw_calls;
    row->triangles = double(st.triangles);
  }
  // Medians: one stalled frame on a shared machine must not move the figure.
  row->update_ms = median(update_ms_v);
  row->submit_ms = median(submit_ms_v);
  row->gpu_ms = median(gpu_ms_v);
  return true;
}

// Writes the gnuplot script next to the plots and runs gnuplot on it; false when it cannot.
bool plot(const Options& o, const std::string& script) {
  const std::string file = o.plots + "/plot.gp";
  std::FILE* f = std::fopen(file.c_str(), "w");
  if (f == nullptr) {
    std::printf("(cannot write %s: no plots)\n", file.c_str());
    return false;
  }
  std::fputs(script.c_str(), f);
  std::fclose(f);
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::printf("(gnuplot not found: wrote %s only; install gnuplot-nox)\n", file.c_str());
    return false;
  }
  return std::system(("gnuplot " + file).c_str()) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  Bench b;
  if (!parse(argc, argv, &b.o)) {
    usage(stderr);
    return 2;
  }
  si::Status s = si::makeDefaultCharacter({}, &b.character);
  if (!s.isOk()) return fail("character", s);
  si::HeadlessDesc hd;
  hd.width = b.o.width;
  hd.height = b.o.height;
  hd.backend = b.o.backend;
  s = si::HeadlessContext::create(hd, &b.context);
  if (s.isOk()) s = si::loadGl(&si::HeadlessContext::getProcAddress, b.context.get(), &b.info);
  if (!s.isOk()) return fail("context", s);
  std::printf("crowd_bench on %s (%s), %ux%u, %u measured frames per configuration\n",
              b.info.renderer.c_str(), si::headlessBackendName(b.context->backend()), b.o.width,
              b.o.height, b.o.frames);

  si::BakedPalette palette;
  si::BakeReport report;
  si::BakeDesc main_bake;  // The default (automatic) bake, or 30 Hz with --quick.
  if (b.o.quick) main_bake.rate_mode = si::RateMode::kFixed;
  s = si::bakePalette(b.character, main_bake, &palette, &report);
  si::Renderer renderer;
  si::RendererDesc rd;
  rd.measure_gpu_time = b.o.gpu_timer;
  rd.debug_checks = 2;
  if (s.isOk()) s = renderer.init(b.info, rd);
  if (s.isOk()) s = renderer.uploadPalette(palette);
  if (s.isOk()) s = renderer.uploadCharacter(b.character, palette);
  if (!s.isOk()) return fail("setup", s);
  std::printf("Automatic skinning path choice: %s (%s)\n",
              si::skinningPathName(renderer.skinningPath()), renderer.skinningPathReason().c_str());

  std::FILE* csv = std::fopen(b.o.csv.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "crowd_bench: cannot write '%s'\n", b.o.csv.c_str());
    return 1;
  }
  std::fprintf(csv, "table,scene,path,instances,visible,draws,triangles,update_ms,submit_ms,"
                    "gpu_ms,format,rate,max_error,p99_error\n");
  std::printf("\n%-8s %-12s %9s %9s %6s %12s %9s %9s %9s %9s %9s\n", "scene", "path",
              "instances", "visible", "draws", "triangles", "update", "submit", "GPU ms",
              "CPU x", "GPU x");
  std::map<std::string, std::map<uint32_t, double>> frame_ms;  // path -> size -> CPU+GPU ms.
  for (const std::string& scene : b.o.scenes) {
    for (uint32_t count : b.o.sizes) {
      std::vector<Row> rows;
      for (const std::string& path : b.o.paths) {
        if ((path == "traditional" || path == "cpu") && count > b.o.max_baseline) continue;
        Row row;
        if (!runPath(b, renderer, palette, scene, count, path, &row)) return 1;
        rows.push_back(row);
      }
      const Row* base = nullptr;
      for (const Row& r : rows)
        if (r.path == "instanced") base = &r;
      for (const Row& r : rows) {
        const double cpu = r.update_ms + r.submit_ms;
        const double cpu_x = base ? cpu / std::max(1e-9, base->update_ms + base->submit_ms) : 0.0;
        const double gpu_x = base ? r.gpu_ms / std::max(1e-9, base->gpu_ms) : 0.0;
        std::printf("%-8s %-12s %9u %9u %6u %12.0f %9.3f %9.3f %9.3f %9.2f %9.2f\n",
                    r.scene.c_str(), r.path.c_str(), r.instances, r.visible, r.draws, r.triangles,
                    r.update_ms, r.submit_ms, r.gpu_ms, cpu_x, gpu_x);
        std::fprintf(csv, "paths,%s,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,,,,\n", r.scene.c_str(),
                     r.path.c_str(), r.instances, r.visible, r.draws, r.triangles, r.update_ms,
                     r.submit_ms, r.gpu_ms);
        if (r.scene == b.o.scenes.front())
          frame_ms[r.path][r.instances] = std::max(cpu, r.gpu_ms);
      }
    }
  }

  if (renderer.computeRingBytes() > 0)
    std::printf("Compute path: pre-skinned vertex ring of %.1f MiB\n",
                double(renderer.computeRingBytes()) / 1048576.0);

  // Speed against error: each bake configuration, on the field, drawn by --error-path. The
  // renderer is re-made with an explicit path so each upload does not re-measure.
  rd.skinning_path = si::SkinningPath::kVertexShader;
  s = renderer.init(b.info, rd);
  if (!s.isOk()) return fail("renderer", s);
  std::printf("\nGPU time against bake error (field, %u instances, %s path)\n",
              b.o.error_table_size, b.o.error_path.c_str());
  std::printf("%-22s %6s %6s %10s %10s %9s %12s %12s\n", "format", "rate", "stride", "texels",
              "bytes", "GPU ms", "max error", "P99 error");
  struct Config {
    si::PaletteFormat format;
    float rate;
    uint32_t stride;  // Joint stride in texels; 0: the default (4, or 2 for quaternions).
  };
  const Config configs[] = {{si::PaletteFormat::kMatrix3x4F32, 15, 0},
                            {si::PaletteFormat::kMatrix3x4F32, 30, 0},
                            {si::PaletteFormat::kMatrix3x4F32, 60, 0},
                            {si::PaletteFormat::kMatrix3x4F32, 0, 0},
                            {si::PaletteFormat::kMatrix3x4F32, 0, 3},
                            {si::PaletteFormat::kMatrix3x4F16, 30, 0},
                            {si::PaletteFormat::kMatrix3x4F16, 0, 0},
                            {si::PaletteFormat::kQuatTranslationF32, 30, 0},
                            {si::PaletteFormat::kQuatTranslationF32, 0, 0}};
  std::string error_data;
  for (const Config& c : configs) {
    if (b.o.quick && c.rate == 0.0f) continue;
    si::BakeDesc d;
    d.format = c.format;
    d.joint_stride_texels = c.stride;
    if (c.rate > 0.0f) {
      d.rate_mode = si::RateMode::kFixed;
      d.sample_rate_hz = c.rate;
    }
    si::BakedPalette p;
    si::BakeReport r;
    s = si::bakePalette(b.character, d, &p, &r);
    if (s.isOk()) s = renderer.uploadPalette(p);
    if (s.isOk()) s = renderer.uploadCharacter(b.character, p);
    if (!s.isOk()) return fail("bake configuration", s);
    Row row;
    if (!runPath(b, renderer, p, "field", b.o.error_table_size, b.o.error_path, &row)) return 1;
    const std::string rate = c.rate > 0.0f ? std::to_string(int(c.rate)) : "auto";
    const std::string texels = std::to_string(p.layout.width) + "x" + std::to_string(p.layout.height);
    std::printf("%-22s %6s %6u %10s %10llu %9.3f %12.3g %12.3g\n", si::paletteFormatName(c.format),
                rate.c_str(), p.layout.joint_stride_texels, texels.c_str(),
                static_cast<unsigned long long>(r.palette_bytes), row.gpu_ms, r.max_error_units,
                r.p99_error_units);
    std::fprintf(csv, "error,field,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,%s%s,%s,%.6g,%.6g\n",
                 b.o.error_path.c_str(), row.instances, row.visible, row.draws, row.triangles,
                 row.update_ms, row.submit_ms, row.gpu_ms, si::paletteFormatName(c.format),
                 p.layout.joint_stride_texels == 3 ? "_stride3" : "", rate.c_str(),
                 r.max_error_units, r.p99_error_units);
    error_data += std::to_string(r.max_error_units) + " " + std::to_string(row.gpu_ms) + " \"" +
                  si::paletteFormatName(c.format) + "@" + rate + "\"\n";
  }
  std::fclose(csv);
  std::printf("\nWrote %s\n", b.o.csv.c_str());

  if (!b.o.plots.empty()) {
    std::string script = "set terminal png size 900,560\nset grid\n";
    script += "set output '" + b.o.plots + "/frame_time.png'\nset logscale xy\n"
              "set xlabel 'characters'\nset ylabel 'max(CPU, GPU) ms per frame'\n"
              "set title 'Frame time against crowd size (" + b.o.scenes.front() + ")'\nplot ";
    bool first = true;
    for (const auto& [path, points] : frame_ms) {
      script += std::string(first ? "" : ", ") + "'-' with linespoints title '" + path + "'";
      first = false;
    }
    script += "\n";
    for (const auto& [path, points] : frame_ms) {
      for (const auto& [n, ms] : points) script += std::to_string(n) + " " + std::to_string(ms) + "\n";
      script += "e\n";
    }
    script += "set output '" + b.o.plots + "/gpu_vs_error.png'\nunset logscale y\n"
              "set logscale x\nset xlabel 'max vertex error (model units)'\n"
              "set ylabel 'GPU ms per frame'\nset title 'GPU time against bake error'\n"
              "plot '-' using 1:2 with points pt 7 notitle, '-' using 1:2:3 with labels offset 1,1 "
              "notitle\n" + error_data + "e\n" + error_data + "e\n";
    if (plot(b.o, script))
      std::printf("Plots in %s (frame_time.png, gpu_vs_error.png)\n", b.o.plots.c_str());
  }
  return 0;
}
