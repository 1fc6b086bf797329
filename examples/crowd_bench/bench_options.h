// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// crowd_bench's command line: every option with its default, the usage text and the parser.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "si/headless/headless_context.h"

namespace si::bench {

struct Options {
  std::vector<uint32_t> sizes = {1000, 4000};
  std::vector<std::string> scenes = {"field", "stadium"};
  std::vector<std::string> paths = {"instanced", "compute",     "gpu-culled", "gpu-driven",
                                    "traditional", "cpu",       "rigid"};
  std::vector<std::string> lods = {"distance", "screen"};
  float pixel_budget = 1.0f;
  std::string lod_chain = "deep";
  uint32_t lod_min_triangles = 0;  // LodChainDesc::min_triangles; 0: the library's default.  // deep: buildLodChain's 6 levels; technique: the 3 embedded.
  bool vertex_colors = false;      // --vertex-colors: the character gets colours and uv1 too.
  bool eight_influences = false;   // --eight-influences: the same skinning through 8 influences.
  uint32_t morph_targets = 0;      // --morph-targets N: N face-like targets on the head.
  float morph_lod_share = 0.5f;    // --morph-lod-share S: RendererDesc::morph_lod_share.
  bool part_lod = false;  // --part-lod: si::buildPartLods (each part its own level, parts dropped).
  bool impostor = false;  // --impostor: an impostor level past the meshes (Renderer::buildImpostor).
  std::string impostor_atlas =
      "full";                     // --impostor-atlas: full (ImpostorDesc's defaults), small, fine.
  uint32_t impostor_capture = 0;  // --impostor-capture: ImpostorDesc::capture_supersample.
  uint32_t impostor_cell = 0;     // --impostor-cell: ImpostorDesc::cell_pixels.
  float impostor_bias = 0.0f;     // --impostor-bias: ImpostorDesc::lod_bias.
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
  bool gpu_passes = false;  // --gpu-passes: the paths table's GPU time per pass, a frame late.
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
  std::vector<uint32_t> crowds;  // The several-crowds table's crowd counts; empty: no table.
  std::vector<uint32_t> live;    // The live poses table's posed counts; empty: no table.
  std::vector<double> churn;     // The churn table's shares; empty: no table.
  bool vulkan = false;           // The Vulkan table (si::vk against si::gl).
};

/// Prints the usage text to `f`.
void printUsage(std::FILE* f);
/// Fills `o` from the command line; false for an unknown option or a bad value (--help prints
/// the usage and exits).
bool parseOptions(int argc, char** argv, Options* o);

}  // namespace si::bench
