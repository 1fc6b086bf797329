// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "image_errors.h"

#include <memory>
#include <vector>

#include "si/core/impostor_level.h"
#include "si/gl/gl_context.h"
#include "si/gl/image_lod_error.h"
#include "si/headless/headless_context.h"

namespace si::tools {

bool printImageErrors(std::FILE* f, const Character& character, const BakedPalette& palette,
                      const ImpostorDesc* impostor, std::string* why) {
  Character measured = character;
  ImageLodErrorDesc desc;
  if (impostor) {
    desc.impostor = impostor;
    const uint32_t azimuths = impostor->azimuths ? impostor->azimuths : 16u;
    desc.azimuth_offset_degrees = 180.0f / float(azimuths);  // Half the atlas's step,
    desc.pose_phase = 0.5f;                                  // and between its frames.
  }
  std::unique_ptr<HeadlessContext> context;
  HeadlessDesc hd;
  hd.width = hd.height = 64;  // Drawn offscreen at its own size.
  Status s = HeadlessContext::create(hd, &context);
  GlInfo info;
  if (s.isOk()) s = loadGl(&HeadlessContext::getProcAddress, context.get(), &info);
  if (s.isOk() && impostor) s = appendImpostorLevel(&measured.mesh);
  ImageLodErrorReport r;
  if (s.isOk()) s = measureImageLodErrors(info, measured, palette, desc, &r);
  if (!s.isOk()) {
    *why = s.toString();
    return false;
  }
  std::fprintf(f,
               "Image error per LOD level (si::measureImageLodErrors on %s: %u poses x %u views, "
               "4x4 supersampled; pixels of one character differing by > 8/255 from LOD 0, mean "
               "at each height in pixels; 1px at: the height where it changes one pixel)\n",
               info.renderer.c_str(), r.poses, r.views);
  std::fprintf(f, "%-6s %12s %12s %8s", "LOD", "geom units", "image units", "1px at");
  for (uint32_t h : r.heights_pixels) std::fprintf(f, " %6upx", h);
  std::fprintf(f, "\n");
  for (size_t l = 0; l < r.levels.size(); ++l) {
    const ImageLodLevel& level = r.levels[l];
    if (impostor && l + 1 == r.levels.size())
      std::fprintf(f, "%-6s %12s %12.4g %8.3g", "imp.", "-", double(level.image_units),
                   level.one_pixel_height);
    else
      std::fprintf(f, "LOD %-2zu %12.4g %12.4g %8.3g", l, double(level.geometric_units),
                   double(level.image_units), level.one_pixel_height);
    for (double px : level.mean_differing_pixels) std::fprintf(f, " %8.2f", px);
    std::fprintf(f, "\n");
  }
  if (impostor) {  // Where the impostor takes over from levels selected by geometric error.
    std::vector<float> geometric;
    for (const ImageLodLevel& level : r.levels) geometric.push_back(level.geometric_units);
    const std::vector<float> units = impostorLodErrorsUnits(geometric, r);
    const size_t last = units.size() - 1;
    size_t first = last;
    while (first > 1 && units[first - 1] == units[last]) --first;
    std::fprintf(f,
                 "The impostor takes over at %.4g units (si::impostorLodErrorsUnits, a 1-pixel "
                 "budget, mesh levels selected by their geometric errors): the characters up to "
                 "%.3g px tall",
                 double(units[last]), double(r.character_height_units / units[last]));
    if (first + 1 == last) std::fprintf(f, ", LOD %zu skipped", first);
    if (first + 1 < last) std::fprintf(f, ", LOD %zu to %zu skipped", first, last - 1);
    std::fprintf(f, "\n");
  }
  return true;
}

}  // namespace si::tools
