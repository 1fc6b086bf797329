// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/bench_character.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "common/face_targets.h"
#include "si/bake/lod_chain.h"
#include "si/core/default_character.h"
#include "si/core/impostor_level.h"
#include "si/core/lod_error.h"
#include "si/core/part_lod.h"
#include "si/gl/image_lod_error.h"

namespace si::bench {

Status makeCharacter(const CharacterChoice& choice, Setup* setup) {
  Status s = makeDefaultCharacter({}, &setup->character);
  if (s.isOk() && choice.vertex_colors) {
    SkinnedMesh& mesh = setup->character.mesh;
    for (const glm::vec3& p : mesh.positions) {
      const float shade = glm::clamp(0.5f + 0.3f * p.y, 0.5f, 1.0f);
      mesh.colors.push_back(glm::vec4(shade, shade, shade, 1.0f));
      mesh.texcoords1.push_back(glm::vec2(p.x, p.y));
    }
    std::printf("Vertex colours and texture coordinates 1 on every vertex (--vertex-colors)\n");
  }
  if (s.isOk() && choice.eight_influences) {
    SkinnedMesh& mesh = setup->character.mesh;
    mesh.joints1 = mesh.joints;
    mesh.weights1.resize(mesh.weights.size());
    for (size_t v = 0; v < mesh.weights.size(); ++v) {
      mesh.weights1[v] = 0.25f * mesh.weights[v];
      mesh.weights[v] *= 0.75f;
    }
    std::printf("Each vertex's influences split over two sets of 4 (--eight-influences)\n");
  }
  if (s.isOk() && choice.morph_targets > 0) {
    examples::addFaceTargets(&setup->character, choice.morph_targets);
    size_t entries = 0;
    for (const MorphTarget& t : setup->character.mesh.morph_targets) entries += t.vertices.size();
    std::printf(
        "%u face-like morph targets on the head (--morph-targets): %zu entries, %.1f "
        "vertices moved per target\n",
        choice.morph_targets, entries, double(entries) / choice.morph_targets);
  }
  LodChainDesc chain;
  chain.min_triangles = choice.lod_min_triangles;
  if (s.isOk() && choice.lod_chain == "deep")
    s = buildLodChain(&setup->character.mesh, chain, nullptr);
  std::vector<LodLevelSummary> bind;
  if (s.isOk()) s = summarizeLodLevels(setup->character.mesh, &bind);
  // Errors over the clips' poses: what the screen-error mode selects by.
  if (s.isOk()) s = measureAnimatedLodErrors(&setup->character, {});
  PartLodReport parts;
  if (s.isOk() && choice.part_lod) s = buildPartLods(&setup->character, {}, &parts);
  if (s.isOk() && choice.impostor) s = appendImpostorLevel(&setup->character.mesh);
  if (s.isOk()) s = lodErrorsByLevel(setup->character.mesh, &setup->lod_errors);
  if (!s.isOk()) return s;
  setup->impostor = choice.impostor;
  if (choice.atlas == "small") {  // ImpostorDesc's defaults otherwise.
    setup->impostor_desc.azimuths = 8;
    setup->impostor_desc.elevations_degrees = {0.0f, 30.0f};
    setup->impostor_desc.frames_per_clip = 4;
  } else if (choice.atlas == "fine") {
    setup->impostor_desc.azimuths = 32;
  }
  setup->impostor_desc.capture_supersample = choice.capture_supersample;
  setup->impostor_desc.cell_pixels = choice.cell_pixels;
  setup->impostor_desc.lod_bias = choice.lod_bias;
  if (choice.part_lod) {
    std::printf("Per-part LOD (si::buildPartLods): per character level, each part's own level "
                "(- where dropped); drop error = distance to the kept parts (model units)\n");
    for (const PartLodReport::Part& p : parts.parts) {
      std::printf("  %-10s %s", p.name.c_str(), p.kept ? "kept      " : "");
      if (!p.kept) std::printf("drop %5.3f", double(p.drop_error_units));
      for (int level : p.level_of) level < 0 ? std::printf("    -") : std::printf(" %4d", level);
      std::printf("\n");
    }
    std::printf("  triangles  before    ");
    for (uint64_t t : parts.triangles_before)
      std::printf(" %llu", static_cast<unsigned long long>(t));
    std::printf("\n  triangles  after     ");
    for (uint64_t t : parts.triangles_after)
      std::printf(" %llu", static_cast<unsigned long long>(t));
    std::printf("\n");
  }
  std::vector<LodLevelSummary> drawn;  // After per-part LOD, which may add a level.
  s = summarizeLodLevels(setup->character.mesh, &drawn);
  if (!s.isOk()) return s;
  std::printf("LOD chain (%s%s): level, triangles drawn (all sub-meshes; one with fewer levels "
              "draws its last), max error (model units) in the bind pose (- for a level per-part "
              "LOD added) and over the clips' poses\n",
              choice.lod_chain.c_str(), choice.part_lod ? ", per-part LOD" : "");
  for (size_t l = 0; l < drawn.size(); ++l) {
    if (choice.impostor && l + 1 == drawn.size()) {
      std::printf("  LOD %zu impostor (one quad; its error is measured in image space)\n", l);
      continue;
    }
    std::printf("  LOD %zu %8llu ", l, static_cast<unsigned long long>(drawn[l].triangles));
    l < bind.size() ? std::printf("%10.4g", double(bind[l].error_units)) : std::printf("%10s", "-");
    std::printf(" %10.4g\n", double(setup->lod_errors[l]));
  }
  return s;
}

Status imageErrors(Setup& setup, const BakedPalette& palette, bool select, bool quick,
                   float budget_pixels) {
  // Every level between the impostor atlas's views and frames, with impostors or without (so
  // that runs with and without them select their mesh levels alike).
  ImageLodErrorDesc desc;
  const uint32_t azimuths = setup.impostor_desc.azimuths ? setup.impostor_desc.azimuths : 16u;
  desc.azimuth_offset_degrees = 180.0f / float(azimuths);  // Half the atlas's step.
  desc.pose_phase = 0.5f;
  if (setup.impostor) desc.impostor = &setup.impostor_desc;
  if (quick) desc.heights_pixels = {4, 8, 16};
  ImageLodErrorReport r;
  const Status s = measureImageLodErrors(setup.info, setup.character, palette, desc, &r);
  if (!s.isOk()) return s;
  std::printf("Image error per LOD level (si::measureImageLodErrors: %u poses x %u views, "
              "4x4 supersampled; pixels of one character differing by > 8/255 from LOD 0, mean "
              "at each height in pixels; 1px at: the height where it changes one pixel; the "
              "character is %.3g units tall)\n",
              r.poses, r.views, double(r.character_height_units));
  std::printf("  level  geometric units  image units  1px at");
  for (uint32_t h : r.heights_pixels) std::printf(" %7upx", h);
  std::printf("\n");
  for (size_t l = 0; l < r.levels.size(); ++l) {
    if (setup.impostor && l + 1 == r.levels.size())
      std::printf("  impostor %15s %12.4g %7.3g", "-", double(r.levels[l].image_units),
                  r.levels[l].one_pixel_height);
    else
      std::printf("  LOD %zu %16.4g %12.4g %7.3g", l, double(r.levels[l].geometric_units),
                  double(r.levels[l].image_units), r.levels[l].one_pixel_height);
    for (double px : r.levels[l].mean_differing_pixels) std::printf(" %9.2f", px);
    std::printf("\n");
  }
  if (select) {
    setup.lod_errors = imageLodErrorsUnits(r);
    std::printf("  the screen-error mode selects by the image errors (--lod-errors image)\n");
  } else if (setup.impostor) {
    setup.lod_errors = impostorLodErrorsUnits(setup.lod_errors, r, budget_pixels);
    const size_t last = setup.lod_errors.size() - 1;
    size_t first = last;
    while (first > 1 && setup.lod_errors[first - 1] == setup.lod_errors[last]) --first;
    const double handover = setup.lod_errors[last];
    std::printf(
        "  the mesh levels are selected by their geometric errors; the impostor (LOD %zu) "
        "takes over at %.4g units: the characters up to %.3g px tall at a %g-pixel "
        "budget (si::impostorLodErrorsUnits: its measured curve against the levels')",
        last, handover, double(budget_pixels) * r.character_height_units / handover,
        double(budget_pixels));
    if (first + 1 == last) std::printf("; LOD %zu skipped", first);
    if (first + 1 < last) std::printf("; LOD %zu to %zu skipped", first, last - 1);
    std::printf("\n");
  }
  return s;
}

Status buildImpostor(const Setup& setup, Renderer& renderer, CharacterId id, bool print) {
  ImpostorInfo info;
  const Status s = renderer.buildImpostor(id, setup.impostor_desc, &info);
  if (s.isOk() && print)
    std::printf(
        "Impostor atlas (Renderer::buildImpostor): %u views x %u frames, %u x %u texels, "
        "%.1f MiB with mip levels, cells of %u texels, %s, captured %u x %u texels each, "
        "read at a LOD bias of %g\n",
        info.views, info.frames, info.width, info.height, double(info.bytes) / 1048576.0,
        info.cell_pixels,
        info.uniform_surface ? "one surface value (fragments read 2 layers)"
                             : "surface layer read per fragment",
        info.capture_supersample, info.capture_supersample, double(setup.impostor_desc.lod_bias));
  return s;
}
}  // namespace si::bench
