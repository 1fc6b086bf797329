// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_bench: the instanced path against its baselines, in the same run on the same scenes,
// with each LOD mode; the image error each LOD choice costs against LOD 0; and GPU time
// against bake error. Prints tables, writes a CSV and, when gnuplot is installed, PNG plots.
// See docs/performance.md for how the published figures were produced.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "common/example_options.h"
#include "crowd_bench/bake_error_table.h"
#include "crowd_bench/bench_character.h"
#include "crowd_bench/bench_plots.h"
#include "crowd_bench/bench_scene.h"
#include "crowd_bench/blend_props_table.h"
#include "crowd_bench/layers_table.h"
#include "crowd_bench/lod_quality.h"
#include "crowd_bench/materials_table.h"
#include "crowd_bench/mixed_scene.h"
#include "crowd_bench/motion_vectors_table.h"
#include "crowd_bench/restore_state_table.h"
#include "crowd_bench/root_motion_table.h"
#include "crowd_bench/uploads_table.h"
#include "crowd_bench/views_table.h"
#include "si/bake/animation_baker.h"

namespace {

using si::bench::LodChoice;
using si::bench::Row;

struct Options {
  std::vector<uint32_t> sizes = {1000, 4000};
  std::vector<std::string> scenes = {"field", "stadium"};
  std::vector<std::string> paths = {"instanced", "compute",     "gpu-culled", "gpu-driven",
                                    "traditional", "cpu",       "rigid"};
  std::vector<std::string> lods = {"distance", "screen"};
  float pixel_budget = 1.0f;
  std::string lod_chain = "deep";
  uint32_t lod_min_triangles = 0;  // LodChainDesc::min_triangles; 0: the library's default.  // deep: buildLodChain's 6 levels; technique: the 3 embedded.
  bool part_lod = false;  // --part-lod: si::buildPartLods (each part its own level, parts dropped).
  bool impostor = false;  // --impostor: an impostor level past the meshes (Renderer::buildImpostor).
  std::string impostor_atlas = "full";  // --impostor-atlas: full (ImpostorDesc's defaults) or small.
  // --lod-errors: what the screen-error mode selects by, the geometric errors (default) or the
  // image errors (si::measureImageLodErrors); --image-errors prints the latter either way.
  std::string lod_errors = "geometric";
  bool image_errors = false;
  std::vector<float> quality_budgets = {0.5f, 1.0f, 2.0f, 4.0f};  // Empty: no quality table.
  uint32_t quality_size = 10000;
  uint32_t quality_frames = 3;
  uint32_t quality_ss = 1;  // Box filter of the quality images (render at this multiple).
  std::string quality_path = "instanced";
  std::string quality_images;  // Folder for each LOD choice's first quality frame, or empty.
  uint32_t frames = 5;
  uint32_t width = 1280, height = 720;
  uint32_t max_baseline = 20000;  // Traditional and CPU skinning are skipped above this.
  uint32_t error_table_size = 2000;
  std::string error_path = "instanced";  // The path the speed-against-error table draws with.
  std::string placement;  // --placement: the main bake automatic with these frames (fewer, grid, keys).
  std::string csv = "crowd_bench.csv";
  std::string plots;  // Folder for PNG plots (gnuplot), empty for none.
  bool quick = false;  // Fixed-rate bakes only (smoke tests under sanitizers).
  bool gpu_timer = true;  // Timer queries (they block each frame); off: CPU figures only.
  si::HeadlessBackend backend = si::HeadlessBackend::kAuto;
  std::vector<std::string> mix;  // glTF kinds of the mixed table; empty: no mixed table.
  bool root_motion = false;      // The root motion table.
  bool motion_vectors = false;   // The motion vectors table.
  bool restore_state = false;    // The state contract table.
  bool materials = false;        // The materials table.
  std::vector<double> moving;    // The state uploads table's shares moved; empty: no table.
  bool layers = false;           // The layered animation table.
  bool blend = false;            // The blend spaces and props table.
  std::vector<uint32_t> views;   // The views table's view counts; empty: no views table.
  uint32_t views_lod_bias = 1;   // Its cascades' CrowdViewDesc::lod_bias.
};

void usage(std::FILE* f) {
  std::fprintf(
      f,
      "Times per path are medians over the measured frames (after 2 warm-up frames).\n"
      "Paths: instanced (vertex-shader skinning), compute (compute pre-skinning), gpu-culled\n"
      "(culling, LOD and records on the GPU, one multi-draw with vertex-shader skinning; the CPU\n"
      "only advances the clock), gpu-driven (GPU culling feeding indirect compute pre-skinning\n"
      "and one multi-draw), gpu-culled-occlusion and gpu-driven-occlusion (the same with\n"
      "two-phase occlusion culling against a depth pyramid), traditional (one draw per\n"
      "character), cpu (CPU skinning), rigid (no\n"
      "skinning: the floor). LOD modes: distance (the technique's lines in radii), screen (the\n"
      "coarsest LOD within --pixel-budget pixels of projected error).\n"
      "The quality table draws --quality-size instances with every instance at LOD 0 and with\n"
      "each LOD choice (each level alone, distance, screen at each budget) and compares images.\n"
      "usage: crowd_bench [--sizes N,N,...] [--scenes field,stadium,plaza] [--frames N]\n"
      "                   [--paths instanced,compute,gpu-culled,gpu-driven,gpu-culled-occlusion,\n"
      "                    gpu-driven-occlusion,traditional,cpu,rigid]\n"
      "                   [--lods distance,screen] [--pixel-budget PX] [--lod-chain "
      "deep|technique]\n"
      "                   [--lod-min-triangles N]\n"
      "                   [--lod-errors geometric|image] (what the screen-error LOD mode selects\n"
      "                   by: si::lodErrorsByLevel, or the measured image errors of\n"
      "                   si::measureImageLodErrors) [--image-errors] (print those either way)\n"
      "                   [--part-lod] (each sub-mesh at its own level within the character's\n"
      "                   error, parts dropped where that is within it: si::buildPartLods)\n"
      "                   [--impostor] (an animated impostor past the last mesh level, chosen by\n"
      "                   its image error; not with the baselines, --mix, --root-motion or\n"
      "                   --motion-vectors) [--impostor-atlas full|small] (small: 8 azimuths,\n"
      "                   2 elevations, 4 frames per clip; full: si::ImpostorDesc's defaults)\n"
      "                   [--quality-budgets PX,PX,... | none] [--quality-size N]\n"
      "                   [--quality-frames N] [--quality-path PATH] [--quality-images DIR]\n"
      "                   [--quality-ss N] (compare images box-filtered N x N: give --size at\n"
      "                   N times the display size for an antialiased comparison; pixel\n"
      "                   budgets then count display pixels in every table)\n"
      "                   [--size WxH]\n"
      "                   [--max-baseline N] [--error-table-size N (0: no bake table)]\n"
      "                   [--csv PATH]\n"
      "                   [--error-path instanced|compute]\n"
      "                   [--plots DIR] [--backend auto|egl-device|egl-surfaceless|osmesa]\n"
      "                   [--quick]   (fixed-rate bakes and a small image-error measurement,\n"
      "                   for smoke tests)\n"
      "                   [--placement fewer|grid|keys] (the main bake automatic with these\n"
      "                   frames, --quick or not: grid against keys costs side by side)\n"
      "                   [--mix FILE,...|samples] (the mixed table: the embedded character and\n"
      "                   these glTF kinds share the field; one renderer against one per kind)\n"
      "                   [--root-motion] (the root motion table: travelling clips played in\n"
      "                   place against moved by their root motion, side by side)\n"
      "                   [--motion-vectors] (the motion vectors table: the instanced,\n"
      "                   compute, gpu-culled and gpu-driven paths without and with motion\n"
      "                   vectors, side by side)\n"
      "                   [--restore-state] (the GL state contract table: each frame drawn\n"
      "                   with RendererDesc::restore_state off and on, side by side)\n"
      "                   [--materials] (the materials table: each frame drawn with the\n"
      "                   built-in material and a host material computing the same, side by\n"
      "                   side)\n"
      "                   [--moving F,F,...] (the state uploads table: a share F of the crowd\n"
      "                   moved each frame, the GPU-driven path uploading what changed against\n"
      "                   everything, side by side)\n"
      "                   [--layers] (the layered animation table: the instanced, compute and\n"
      "                   GPU-driven paths with no overlay, at weight 1 and 0.5, side by side)\n"
      "                   [--blend] (the blend spaces and props table: every instance playing\n"
      "                   its clip, blending the walk and the run, blending four clips (2D),\n"
      "                   holding a staff, and the two-clip blend with the staff, side by side)\n"
      "                   [--views N,M,...] (the views table: 1 main view and N - 1 shadow\n"
      "                   cascades per frame, for each count, side by side)\n"
      "                   [--views-lod-bias B] (its cascades' LOD bias, 0 to 7; default 1)\n"
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
    else if (a == "--lods" && has) o->lods = si::examples::splitList(argv[++i]);
    else if (a == "--pixel-budget" && has) o->pixel_budget = std::stof(argv[++i]);
    else if (a == "--lod-chain" && has) o->lod_chain = argv[++i];
    else if (a == "--lod-min-triangles" && has) o->lod_min_triangles = uint32_t(std::stoul(argv[++i]));
    else if (a == "--part-lod") o->part_lod = true;
    else if (a == "--impostor") o->impostor = true;
    else if (a == "--impostor-atlas" && has) o->impostor_atlas = argv[++i];
    else if (a == "--lod-errors" && has) o->lod_errors = argv[++i];
    else if (a == "--image-errors") o->image_errors = true;
    else if (a == "--quality-budgets" && has) {
      o->quality_budgets.clear();
      const std::string v = argv[++i];
      if (v != "none")
        for (const std::string& x : si::examples::splitList(v)) o->quality_budgets.push_back(std::stof(x));
    } else if (a == "--quality-size" && has) o->quality_size = uint32_t(std::stoul(argv[++i]));
    else if (a == "--quality-frames" && has) o->quality_frames = uint32_t(std::stoul(argv[++i]));
    else if (a == "--quality-path" && has) o->quality_path = argv[++i];
    else if (a == "--quality-images" && has) o->quality_images = argv[++i];
    else if (a == "--quality-ss" && has) o->quality_ss = uint32_t(std::stoul(argv[++i]));
    else if (a == "--frames" && has) o->frames = uint32_t(std::stoul(argv[++i]));
    else if (a == "--size" && has) {
      if (std::sscanf(argv[++i], "%ux%u", &o->width, &o->height) != 2) return false;
    } else if (a == "--max-baseline" && has) o->max_baseline = uint32_t(std::stoul(argv[++i]));
    else if (a == "--error-table-size" && has) o->error_table_size = uint32_t(std::stoul(argv[++i]));
    else if (a == "--error-path" && has) o->error_path = argv[++i];
    else if (a == "--csv" && has) o->csv = argv[++i];
    else if (a == "--plots" && has) o->plots = argv[++i];
    else if (a == "--quick") o->quick = true;
    else if (a == "--placement" && has) o->placement = argv[++i];
    else if (a == "--mix" && has) {
      o->mix = si::examples::splitList(argv[++i]);
      if (o->mix.size() == 1 && o->mix[0] == "samples")
        o->mix = {std::string(SI_BENCH_ASSETS) + "/Fox/glTF-Binary/Fox.glb",
                  std::string(SI_BENCH_ASSETS) + "/CesiumMan/glTF-Binary/CesiumMan.glb"};
    }
    else if (a == "--no-gpu-time") o->gpu_timer = false;
    else if (a == "--root-motion") o->root_motion = true;
    else if (a == "--motion-vectors") o->motion_vectors = true;
    else if (a == "--restore-state") o->restore_state = true;
    else if (a == "--materials") o->materials = true;
    else if (a == "--moving" && has) {
      o->moving.clear();
      for (const std::string& v : si::examples::splitList(argv[++i])) o->moving.push_back(std::stod(v));
    }
    else if (a == "--layers") o->layers = true;
    else if (a == "--blend")
      o->blend = true;
    else if (a == "--views" && has) {
      o->views.clear();
      for (const std::string& v : si::examples::splitList(argv[++i])) {
        const unsigned long n = std::stoul(v);
        if (n < 1 || n > 8) return false;  // 1 main view and up to 7 cascades.
        o->views.push_back(uint32_t(n));
      }
    }
    else if (a == "--views-lod-bias" && has) {
      const unsigned long n = std::stoul(argv[++i]);
      if (n > 7) return false;
      o->views_lod_bias = uint32_t(n);
    }
    else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else return false;
  }
  for (const std::string& s : o->scenes)
    if (s != "field" && s != "stadium" && s != "plaza") return false;
  const auto known_path = [](const std::string& p) {
    return p == "instanced" || p == "compute" || p == "gpu-culled" || p == "gpu-driven" ||
           p == "gpu-culled-occlusion" || p == "gpu-driven-occlusion" || p == "traditional" ||
           p == "cpu" || p == "rigid";
  };
  for (const std::string& p : o->paths)
    if (!known_path(p)) return false;
  if (!known_path(o->quality_path) || o->quality_path == "rigid") return false;
  for (const std::string& l : o->lods)
    if (l != "distance" && l != "screen") return false;
  for (double m : o->moving)
    if (!(m >= 0.0 && m <= 1.0)) return false;
  for (float b : o->quality_budgets)
    if (!(b > 0.0f) || !std::isfinite(b)) return false;
  if (!(o->pixel_budget > 0.0f) || !std::isfinite(o->pixel_budget)) return false;
  if (o->lod_chain != "deep" && o->lod_chain != "technique") return false;
  if (o->lod_errors != "geometric" && o->lod_errors != "image") return false;
  if (o->lods.empty() || o->quality_frames == 0) return false;
  if (o->quality_ss == 0 || o->quality_ss > 8) return false;
  if (o->impostor_atlas != "full" && o->impostor_atlas != "small") return false;
  if (o->impostor) {  // The baselines and the mixed, root motion and motion vector tables draw
                      // meshes only.
    for (const std::string& p : o->paths)
      if (p == "traditional" || p == "cpu" || p == "rigid") return false;
    if (o->quality_path == "traditional" || o->quality_path == "cpu") return false;
    if (!o->mix.empty() || o->root_motion || o->motion_vectors) return false;
  }
  if (o->error_path != "instanced" && o->error_path != "compute") return false;
  if (!o->placement.empty() && o->placement != "fewer" && o->placement != "grid" &&
      o->placement != "keys")
    return false;
  return !o->sizes.empty() && o->frames > 0;
}

struct Bench {
  Options o;
  si::bench::Setup setup;
};

int fail(const char* what, const si::Status& s) {
  std::fprintf(stderr, "crowd_bench: %s: %s\n", what, s.toString().c_str());
  return 1;
}

LodChoice lodChoice(const std::string& name, float budget) {
  LodChoice c;
  c.mode = name == "screen" ? si::LodMode::kScreenError : si::LodMode::kDistance;
  c.pixel_budget = budget;
  return c;
}

// Writes the gnuplot script next to the plots and runs gnuplot on it; false when it cannot.
// The paths table: each scene, size, path and LOD mode; returns max(CPU, GPU) ms per frame of
// the first scene's rows by "path/lod" and size for the plot.
bool pathsTable(Bench& b, si::Renderer& renderer, const si::BakedPalette& palette, std::FILE* csv,
                std::map<std::string, std::map<uint32_t, double>>* frame_ms) {
  std::printf("\n%-8s %-11s %-11s %9s %9s %6s %12s %7s %9s %9s %9s %8s %8s\n", "scene", "path",
              "lod", "instances", "visible", "draws", "triangles", "tri/px", "update", "submit",
              "GPU ms", "CPU x", "GPU x");
  for (const std::string& scene : b.o.scenes) {
    for (uint32_t count : b.o.sizes) {
      std::vector<Row> rows;
      for (const std::string& lod : b.o.lods) {
        for (const std::string& path : b.o.paths) {
          if ((path == "traditional" || path == "cpu") && count > b.o.max_baseline) continue;
          Row row;
          const si::Status s = si::bench::runPath(b.setup, renderer, palette, scene, count, path,
                                                  lodChoice(lod, b.o.pixel_budget), &row);
          if (!s.isOk()) return fail(path.c_str(), s) == 0;
          rows.push_back(row);
        }
      }
      for (const Row& r : rows) {
        const Row* base = nullptr;  // The instanced row of the same LOD mode.
        for (const Row& q : rows)
          if (q.path == "instanced" && q.lod == r.lod) base = &q;
        const double cpu = r.update_ms + r.submit_ms;
        const double cpu_x = base ? cpu / std::max(1e-9, base->update_ms + base->submit_ms) : 0.0;
        const double gpu_x = base ? r.gpu_ms / std::max(1e-9, base->gpu_ms) : 0.0;
        const double tri_px = r.covered_pixels ? r.triangles / double(r.covered_pixels) : 0.0;
        std::printf("%-8s %-11s %-11s %9u %9u %6u %12.0f %7.2f %9.3f %9.3f %9.3f %8.2f %8.2f\n",
                    r.scene.c_str(), r.path.c_str(), r.lod.c_str(), r.instances, r.visible,
                    r.draws, r.triangles, tri_px, r.update_ms, r.submit_ms, r.gpu_ms, cpu_x,
                    gpu_x);
        std::fprintf(csv, "paths,%s,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,,,,,%s,%llu,,\n",
                     r.scene.c_str(), r.path.c_str(), r.instances, r.visible, r.draws,
                     r.triangles, r.update_ms, r.submit_ms, r.gpu_ms, r.lod.c_str(),
                     static_cast<unsigned long long>(r.covered_pixels));
        if (r.scene == b.o.scenes.front())
          (*frame_ms)[r.path + "/" + r.lod][r.instances] = std::max(cpu, r.gpu_ms);
      }
    }
  }
  return true;
}

// The LOD quality table: image error of each LOD choice against LOD 0, on each scene.
bool qualityTable(Bench& b, si::Renderer& renderer, const si::BakedPalette& palette,
                  std::FILE* csv) {
  if (b.o.quality_budgets.empty()) return true;
  std::vector<LodChoice> choices;
  for (int l = 1; l < int(b.setup.character.mesh.maxLodCount()); ++l) {  // Each level alone.
    LodChoice fixed;
    fixed.fixed_lod = l;
    choices.push_back(fixed);
  }
  choices.push_back(lodChoice("distance", 1.0f));
  for (float budget : b.o.quality_budgets) choices.push_back(lodChoice("screen", budget));
  std::printf("\nLOD quality against every instance at LOD 0 (%u instances, %u frames, %s path, "
              "%ux%u compared after a %ux%u box filter; a pixel differs when a channel is off by "
              "more than %d/255)\n",
              b.o.quality_size, b.o.quality_frames, b.o.quality_path.c_str(),
              b.o.width / b.o.quality_ss, b.o.height / b.o.quality_ss, b.o.quality_ss,
              b.o.quality_ss, si::bench::kQualityChannelTolerance);
  std::printf("%-8s %-11s %12s %8s %12s %9s %8s %8s\n", "scene", "lod", "triangles", "tri/px",
              "differing %", "PSNR dB", "SSIM", "max ch");
  for (const std::string& scene : b.o.scenes) {
    std::vector<si::bench::QualityRow> rows;
    const si::Status s = si::bench::measureLodQuality(b.setup, renderer, palette, scene,
                                                      b.o.quality_size, b.o.quality_path,
                                                      b.o.quality_frames, b.o.quality_ss,
                                                      choices,
                                                      b.o.quality_images, &rows);
    if (!s.isOk()) return fail("quality", s) == 0;
    for (const si::bench::QualityRow& r : rows) {
      std::printf("%-8s %-11s %12.0f %8.2f %12.3f %9.2f %8.5f %8d\n", r.scene.c_str(),
                  r.lod.c_str(), r.triangles, r.triangles_per_pixel, r.differing_share * 100.0,
                  r.psnr_db, r.ssim, r.max_channel);
      std::fprintf(csv, "quality,%s,%s,%u,,,%.0f,,,,,,,,%s,,%.6f,%.3f,%.6f\n", r.scene.c_str(),
                   b.o.quality_path.c_str(), r.instances, r.triangles, r.lod.c_str(),
                   r.differing_share, r.psnr_db, r.ssim);
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Bench b;
  if (!parse(argc, argv, &b.o)) {
    usage(stderr);
    return 2;
  }
  si::bench::CharacterChoice choice;
  choice.lod_chain = b.o.lod_chain;
  choice.lod_min_triangles = b.o.lod_min_triangles;
  choice.part_lod = b.o.part_lod;
  choice.impostor = b.o.impostor;
  choice.small_atlas = b.o.impostor_atlas == "small";
  si::Status s = si::bench::makeCharacter(choice, &b.setup);
  if (!s.isOk()) return fail("character", s);
  si::HeadlessDesc hd;
  hd.width = b.setup.width = b.o.width;
  hd.height = b.setup.height = b.o.height;
  hd.backend = b.o.backend;
  b.setup.frames = b.o.frames;
  b.setup.supersample = b.o.quality_ss;  // LOD budgets count display pixels.
  s = si::HeadlessContext::create(hd, &b.setup.context);
  if (s.isOk())
    s = si::loadGl(&si::HeadlessContext::getProcAddress, b.setup.context.get(), &b.setup.info);
  if (!s.isOk()) return fail("context", s);
  std::printf("crowd_bench on %s (%s), %ux%u, %u measured frames per configuration\n",
              b.setup.info.renderer.c_str(), si::headlessBackendName(b.setup.context->backend()),
              b.o.width, b.o.height, b.o.frames);
  const si::Character& character = b.setup.character;

  si::BakedPalette palette;
  si::BakeReport report;
  si::BakeDesc main_bake;  // The default (automatic) bake, or 30 Hz with --quick.
  if (b.o.quick) main_bake.rate_mode = si::RateMode::kFixed;
  if (!b.o.placement.empty()) {  // Automatic rates with these frames, --quick or not.
    main_bake.rate_mode = si::RateMode::kAutomatic;
    main_bake.placement = b.o.placement == "grid"   ? si::FramePlacement::kGrid
                          : b.o.placement == "keys" ? si::FramePlacement::kKeys
                                                    : si::FramePlacement::kFewer;
  }
  s = si::bakePalette(character, main_bake, &palette, &report);
  if (s.isOk() && (b.o.image_errors || b.o.lod_errors == "image" || b.o.impostor)) {
    s = si::bench::imageErrors(b.setup, palette, b.o.lod_errors == "image", b.o.quick);
    if (!s.isOk()) return fail("image errors", s);
  }
  si::Renderer renderer;
  si::RendererDesc rd;
  rd.measure_gpu_time = b.o.gpu_timer;
  rd.debug_checks = 2;
  if (s.isOk()) s = renderer.init(b.setup.info, rd);
  si::CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  if (s.isOk() && b.o.impostor) s = si::bench::buildImpostor(b.setup, renderer, id);
  if (!s.isOk()) return fail("setup", s);
  std::printf("Automatic skinning path choice: %s (%s)\n",
              si::skinningPathName(renderer.skinningPath()), renderer.skinningPathReason().c_str());

  std::FILE* csv = std::fopen(b.o.csv.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "crowd_bench: cannot write '%s'\n", b.o.csv.c_str());
    return 1;
  }
  std::fprintf(csv, "table,scene,path,instances,visible,draws,triangles,update_ms,submit_ms,"
                    "gpu_ms,format,rate,max_error,p99_error,lod,covered_pixels,differing_share,"
                    "psnr_db,ssim\n");
  std::map<std::string, std::map<uint32_t, double>> frame_ms;  // path/lod -> size -> ms.
  if (!pathsTable(b, renderer, palette, csv, &frame_ms)) return 1;
  if (renderer.computeRingBytes() > 0)
    std::printf("Compute path: pre-skinned vertex ring of %.1f MiB\n",
                double(renderer.computeRingBytes()) / 1048576.0);
  if (!qualityTable(b, renderer, palette, csv)) return 1;
  if (!b.o.mix.empty()) {
    std::vector<si::bench::MixedKind> kinds;
    si::RendererDesc mixed_rd = rd;
    mixed_rd.skinning_path = si::SkinningPath::kVertexShader;  // Each path says its own.
    s = si::bench::loadMixedKinds(character, palette, b.o.mix, b.o.lod_chain == "deep",
                                  b.o.quick, &kinds);
    if (s.isOk())
      s = si::bench::mixedTable(b.setup, kinds, mixed_rd, b.o.sizes, b.o.paths, b.o.max_baseline,
                                csv);
    if (!s.isOk()) return fail("mixed", s);
  }
  if (b.o.root_motion) {
    si::RendererDesc motion_rd = rd;
    motion_rd.skinning_path = si::SkinningPath::kVertexShader;  // Each path says its own.
    s = si::bench::rootMotionTable(b.setup, motion_rd, b.o.sizes, b.o.paths, b.o.max_baseline, csv);
    if (!s.isOk()) return fail("root motion", s);
  }
  if (b.o.motion_vectors) {
    s = si::bench::motionVectorsTable(b.setup, palette, rd, b.o.sizes, b.o.paths, csv);
    if (!s.isOk()) return fail("motion vectors", s);
  }
  if (!b.o.views.empty()) {
    s = si::bench::viewsTable(b.setup, palette, rd, b.o.sizes, b.o.views, b.o.views_lod_bias,
                              b.o.paths, b.o.max_baseline, csv);
    if (!s.isOk()) return fail("views", s);
  }
  if (b.o.restore_state) {
    s = si::bench::restoreStateTable(b.setup, palette, rd, b.o.sizes, b.o.paths, csv);
    if (!s.isOk()) return fail("restore state", s);
  }
  if (b.o.materials) {
    s = si::bench::materialsTable(b.setup, palette, rd, b.o.sizes, b.o.paths, csv);
    if (!s.isOk()) return fail("materials", s);
  }
  if (!b.o.moving.empty()) {
    s = si::bench::uploadsTable(b.setup, palette, rd, b.o.sizes, b.o.moving, csv);
    if (!s.isOk()) return fail("uploads", s);
  }
  if (b.o.layers) {
    s = si::bench::layersTable(b.setup, renderer, palette, b.o.sizes, b.o.paths, csv);
    if (!s.isOk()) return fail("layers", s);
  }
  if (b.o.blend) {
    s = si::bench::blendPropsTable(b.setup, palette, rd, b.o.sizes, b.o.paths, csv);
    if (!s.isOk()) return fail("blend", s);
  }

  // Speed against error: each bake configuration, on the field, drawn by --error-path (none
  // with --error-table-size 0). The renderer is re-made with an explicit path so each upload
  // does not re-measure.
  std::string error_data;
  if (b.o.error_table_size > 0) {
    rd.skinning_path = si::SkinningPath::kVertexShader;
    s = renderer.init(b.setup.info, rd);
    if (!s.isOk()) return fail("renderer", s);
    s = si::bench::bakeErrorTable(b.setup, renderer, character, b.o.error_table_size,
                                  b.o.error_path, lodChoice(b.o.lods.front(), b.o.pixel_budget),
                                  b.o.quick, csv, &error_data);
    if (!s.isOk()) return fail("bake configurations", s);
  }
  std::fclose(csv);
  std::printf("\nWrote %s\n", b.o.csv.c_str());

  if (!b.o.plots.empty() &&
      si::bench::writePlots(b.o.plots, b.o.scenes.front(), frame_ms, error_data))
    std::printf("Plots in %s (frame_time.png, gpu_vs_error.png)\n", b.o.plots.c_str());
  return 0;
}
