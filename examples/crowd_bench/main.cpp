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
#include "crowd_bench/bench_options.h"
#include "crowd_bench/bench_plots.h"
#include "crowd_bench/bench_scene.h"
#include "crowd_bench/blend_props_table.h"
#include "crowd_bench/churn_table.h"
#include "crowd_bench/crowds_table.h"
#include "crowd_bench/gpu_passes_table.h"
#include "crowd_bench/layers_table.h"
#include "crowd_bench/live_poses_table.h"
#include "crowd_bench/lod_quality.h"
#include "crowd_bench/materials_table.h"
#include "crowd_bench/mixed_scene.h"
#include "crowd_bench/motion_vectors_table.h"
#include "crowd_bench/restore_state_table.h"
#include "crowd_bench/root_motion_table.h"
#include "crowd_bench/uploads_table.h"
#include "crowd_bench/views_table.h"
#include "crowd_bench/vulkan_table.h"
#include "si/bake/animation_baker.h"
#include "si/core/shader_inputs.h"

namespace {

using si::bench::LodChoice;
using si::bench::Options;
using si::bench::Row;

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
// A pass table's CSV beside the main one: name.csv -> name + `suffix`.
std::string passesCsvPath(const std::string& csv, const char* suffix = "_passes.csv") {
  const size_t dot = csv.rfind(".csv");
  return (dot != std::string::npos && dot + 4 == csv.size() ? csv.substr(0, dot) : csv) + suffix;
}

// The paths table: each scene, size, path and LOD mode; returns max(CPU, GPU) ms per frame of
// the first scene's rows by "path/lod" and size for the plot.
bool pathsTable(Bench& b, si::Renderer& renderer, const si::BakedPalette& palette, std::FILE* csv,
                std::map<std::string, std::map<uint32_t, double>>* frame_ms) {
  std::printf("\n%-8s %-11s %-11s %9s %9s %6s %12s %7s %9s %9s %9s %8s %8s\n", "scene", "path",
              "lod", "instances", "visible", "draws", "triangles", "tri/px", "update", "submit",
              "GPU ms", "CPU x", "GPU x");
  std::vector<Row> all;  // Every row, for the pass table.
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
      all.insert(all.end(), rows.begin(), rows.end());
    }
  }
  if (b.o.gpu_passes) si::bench::printPassTable(all, passesCsvPath(b.o.csv).c_str());
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
  std::printf("%-8s %-11s %12s %8s %12s %9s %8s %8s %11s\n", "scene", "lod", "triangles", "tri/px",
              "differing %", "PSNR dB", "SSIM", "max ch", "temporal %");
  for (const std::string& scene : b.o.scenes) {
    std::vector<si::bench::QualityRow> rows;
    const si::Status s = si::bench::measureLodQuality(b.setup, renderer, palette, scene,
                                                      b.o.quality_size, b.o.quality_path,
                                                      b.o.quality_frames, b.o.quality_ss,
                                                      choices,
                                                      b.o.quality_images, &rows);
    if (!s.isOk()) return fail("quality", s) == 0;
    for (const si::bench::QualityRow& r : rows) {
      std::printf("%-8s %-11s %12.0f %8.2f %12.3f %9.2f %8.5f %8d %11.3f\n", r.scene.c_str(),
                  r.lod.c_str(), r.triangles, r.triangles_per_pixel, r.differing_share * 100.0,
                  r.psnr_db, r.ssim, r.max_channel, r.temporal_share * 100.0);
      std::fprintf(csv, "quality,%s,%s,%u,,,%.0f,,,,,,,,%s,,%.6f,%.3f,%.6f,%.6f\n", r.scene.c_str(),
                   b.o.quality_path.c_str(), r.instances, r.triangles, r.lod.c_str(),
                   r.differing_share, r.psnr_db, r.ssim, r.temporal_share);
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Bench b;
  if (!si::bench::parseOptions(argc, argv, &b.o)) {
    si::bench::printUsage(stderr);
    return 2;
  }
  si::bench::CharacterChoice choice;
  choice.lod_chain = b.o.lod_chain;
  choice.lod_min_triangles = b.o.lod_min_triangles;
  choice.part_lod = b.o.part_lod;
  choice.impostor = b.o.impostor;
  choice.atlas = b.o.impostor_atlas;
  choice.capture_supersample = b.o.impostor_capture;
  choice.cell_pixels = b.o.impostor_cell;
  choice.lod_bias = b.o.impostor_bias;
  choice.vertex_colors = b.o.vertex_colors;
  choice.eight_influences = b.o.eight_influences;
  choice.morph_targets = b.o.morph_targets;
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
    s = si::bench::imageErrors(b.setup, palette, b.o.lod_errors == "image", b.o.quick,
                               b.o.pixel_budget);
    if (!s.isOk()) return fail("image errors", s);
  }
  si::Renderer renderer;
  si::RendererDesc rd;
  rd.measure_gpu_time = b.o.gpu_timer;
  rd.measure_gpu_passes = b.o.gpu_passes;
  rd.debug_checks = 2;
  rd.morph_lod_share = b.o.morph_lod_share;
  if (s.isOk()) s = renderer.init(b.setup.info, rd);
  si::CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  if (s.isOk() && b.o.impostor) s = si::bench::buildImpostor(b.setup, renderer, id);
  if (!s.isOk()) return fail("setup", s);
  if (!character.mesh.morph_targets.empty()) {  // What the targets take, per target.
    si::MorphStream morphs;
    if (!si::buildMorphStream(character.mesh, palette, 0, &morphs).isOk()) return 1;
    const si::PaletteLayout& l = palette.layout;
    uint64_t frames = 0;
    for (uint32_t f : l.clip_frame_count) frames += f + 2 * l.border_frames;
    const double targets = double(l.morph_target_count);
    const double weight_bytes = double(frames) * (l.frame_stride_texels - l.morph_first_texel) *
                                si::bytesPerTexel(palette.format);
    const double delta_bytes =
        double(morphs.entry_count) * morphs.texels_per_entry * 16.0;  // RGBA32UI texels.
    std::printf(
        "Morph targets: %.0f; palette weights %.0f bytes (%.0f per target, %llu frames), "
        "deltas %.0f bytes (%.0f per target, %u entries of %u texels)\n",
        targets, weight_bytes, weight_bytes / targets, static_cast<unsigned long long>(frames),
        delta_bytes, delta_bytes / targets, morphs.entry_count, morphs.texels_per_entry);
  }
  std::printf("Automatic skinning path choice: %s (%s)\n",
              si::skinningPathName(renderer.skinningPath(si::CharacterId{})),
              renderer.skinningPathReason(si::CharacterId{}).c_str());

  std::FILE* csv = std::fopen(b.o.csv.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "crowd_bench: cannot write '%s'\n", b.o.csv.c_str());
    return 1;
  }
  std::fprintf(csv,
               "table,scene,path,instances,visible,draws,triangles,update_ms,submit_ms,"
               "gpu_ms,format,rate,max_error,p99_error,lod,covered_pixels,differing_share,"
               "psnr_db,ssim,temporal_share\n");
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
                              lodChoice(b.o.lods.front(), b.o.pixel_budget), b.o.paths,
                              b.o.max_baseline, csv, passesCsvPath(b.o.csv, "_views_passes.csv"));
    if (!s.isOk()) return fail("views", s);
  }
  if (!b.o.churn.empty()) {
    s = si::bench::churnTable(b.setup, palette, rd, b.o.sizes, b.o.churn, csv);
    if (!s.isOk()) return fail("churn", s);
  }
  if (!b.o.crowds.empty()) {
    s = si::bench::crowdsTable(b.setup, palette, rd, b.o.sizes, b.o.crowds, csv);
    if (!s.isOk()) return fail("crowds", s);
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
  if (!b.o.live.empty()) {
    s = si::bench::livePosesTable(b.setup, palette, rd, b.o.sizes, b.o.live, b.o.paths, csv);
    if (!s.isOk()) return fail("live", s);
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
  // The Vulkan table last: once its device is destroyed, NVIDIA's EGL display is gone with it
  // (eglMakeCurrent fails with EGL_NOT_INITIALIZED), so no GL table can follow it.
  if (b.o.vulkan) {
    s = si::bench::vulkanTable(b.setup, palette, rd, b.o.scenes, b.o.sizes, b.o.paths,
                               lodChoice(b.o.lods.front(), b.o.pixel_budget), csv);
    if (!s.isOk()) return fail("vulkan", s);
  }
  std::fclose(csv);
  std::printf("\nWrote %s\n", b.o.csv.c_str());

  if (!b.o.plots.empty() &&
      si::bench::writePlots(b.o.plots, b.o.scenes.front(), frame_ms, error_data))
    std::printf("Plots in %s (frame_time.png, gpu_vs_error.png)\n", b.o.plots.c_str());
  return 0;
}
