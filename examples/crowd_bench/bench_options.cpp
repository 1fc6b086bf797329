// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_bench's command line (bench_options.h).
#include "crowd_bench/bench_options.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include "common/example_options.h"
#include "si/crowd/crowd_desc.h"

namespace si::bench {

void printUsage(std::FILE* f) {
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
      "                   [--vertex-colors] (the character's mesh gets vertex colours and\n"
      "                   texture coordinates 1: what the optional vertex words cost)\n"
      "                   [--eight-influences] (each vertex's influences split over two sets,\n"
      "                   the same skinning through 8: what the second set costs)\n"
      "                   [--morph-targets N] (N face-like morph targets on the head, every\n"
      "                   clip animating their weights: what morph targets cost)\n"
      "                   [--morph-lod-share S] (RendererDesc::morph_lod_share: each coarse LOD\n"
      "                   leaves out the targets moving a vertex within S of its error; 0.5)\n"
      "                   [--impostor] (an animated impostor past the last mesh level, chosen by\n"
      "                   its image error; not with the baselines, --mix, --root-motion or\n"
      "                   --motion-vectors) [--impostor-atlas full|small|fine] (small: 8\n"
      "                   azimuths, 2 elevations, 4 frames per clip; full: si::ImpostorDesc's\n"
      "                   defaults; fine: the defaults with 32 azimuths, twice the memory)\n"
      "                   [--impostor-capture N] (ImpostorDesc::capture_supersample: 1, 2 or 4;\n"
      "                   0, the default: 2 where it fits) [--impostor-cell N]\n"
      "                   (ImpostorDesc::cell_pixels: a cell's side in texels, a power of\n"
      "                   two; 0, the default: 32) [--impostor-bias B]\n"
      "                   (ImpostorDesc::lod_bias: added to the mip level impostors read,\n"
      "                   within [-2, 2]; 0, the default)\n"
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
      "                   cascades per frame, for each count, side by side; LODs by the\n"
      "                   first --lods choice)\n"
      "                   [--views-lod-bias B] (its cascades' LOD bias, 0 to 7; default 1)\n"
      "                   [--crowds N,M,...] (the several-crowds table: N crowds of each size\n"
      "                   of one character, GPU-driven, frame time and GPU memory)\n"
      "                   [--live N,M,...] (the live poses table: N instances posed every\n"
      "                   frame by setLivePoses, against none, on the --paths that skin)\n"
      "                   [--churn F,F,...] (the churn table: a share F removed and added each\n"
      "                   frame, GPU-driven in 4 views, against none)\n"
      "                   [--vulkan] (the Vulkan table: the --paths si::vk draws, instanced,\n"
      "                   gpu-culled and gpu-driven, in a headless Vulkan host against\n"
      "                   si::gl, each frame both, GPU times)\n"
      "                   [--no-gpu-time] (no blocking timer queries: CPU columns only;\n"
      "                   GPU ms and the GPU-culled path's visible count read -1 / 0)\n"
      "                   [--gpu-passes] (the paths and views tables' GPU time per pass, read a\n"
      "                   frame late, with the bytes moved; CSVs beside --csv as NAME_passes.csv\n"
      "                   and NAME_views_passes.csv; with --no-gpu-time the paths table's GPU\n"
      "                   ms is the passes' total: no frame waits for the GPU; with --vulkan\n"
      "                   each pair of rows' GPU time split: GL's compute passes and draws,\n"
      "                   Vulkan's before the host's rendering and the rest)\n");
}

bool parseOptions(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--help") { printUsage(stdout); std::exit(0); }
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
    else if (a == "--vertex-colors")
      o->vertex_colors = true;
    else if (a == "--eight-influences")
      o->eight_influences = true;
    else if (a == "--morph-targets" && has)
      o->morph_targets = uint32_t(std::stoul(argv[++i]));
    else if (a == "--morph-lod-share" && has)
      o->morph_lod_share = std::stof(argv[++i]);
    else if (a == "--impostor") o->impostor = true;
    else if (a == "--impostor-atlas" && has) o->impostor_atlas = argv[++i];
    else if (a == "--impostor-capture" && has)
      o->impostor_capture = uint32_t(std::stoul(argv[++i]));
    else if (a == "--impostor-cell" && has)
      o->impostor_cell = uint32_t(std::stoul(argv[++i]));
    else if (a == "--impostor-bias" && has)
      o->impostor_bias = std::stof(argv[++i]);
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
    else if (a == "--gpu-passes")
      o->gpu_passes = true;
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
    } else if (a == "--vulkan") {
      o->vulkan = true;
    } else if (a == "--churn" && has) {
      o->churn = {0.0};  // The row without churn first.
      for (const std::string& v : si::examples::splitList(argv[++i])) {
        const double share = std::stod(v);
        if (!(share > 0.0 && share <= 1.0)) return false;
        o->churn.push_back(share);
      }
    } else if (a == "--crowds" && has) {
      o->crowds.clear();
      for (const std::string& v : si::examples::splitList(argv[++i])) {
        const unsigned long n = std::stoul(v);
        if (n < 1 || n > 16) return false;  // GpuCulledCrowds keeps 16 per character.
        o->crowds.push_back(uint32_t(n));
      }
    } else if (a == "--live" && has) {
      o->live.clear();
      for (const std::string& v : si::examples::splitList(argv[++i])) {
        const unsigned long n = std::stoul(v);
        if (n < 1 || n > si::CrowdDesc::kMaxLivePoses) return false;
        o->live.push_back(uint32_t(n));
      }
    } else if (a == "--views-lod-bias" && has) {
      const unsigned long n = std::stoul(argv[++i]);
      if (n > 7) return false;
      o->views_lod_bias = uint32_t(n);
    } else if (a == "--backend" && has) {
      if (!si::examples::parseBackend(argv[++i], &o->backend)) return false;
    } else
      return false;
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
  if (o->impostor_atlas != "full" && o->impostor_atlas != "small" && o->impostor_atlas != "fine")
    return false;
  if (o->impostor_capture != 0 && o->impostor_capture != 1 && o->impostor_capture != 2 &&
      o->impostor_capture != 4)
    return false;
  if ((o->impostor_cell & (o->impostor_cell - 1)) != 0) return false;  // 0 or a power of two.
  if (!(o->impostor_bias >= -2.0f && o->impostor_bias <= 2.0f)) return false;
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

}  // namespace si::bench
