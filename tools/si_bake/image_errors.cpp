// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "image_errors.h"

#include <memory>

#include "si/gl/gl_context.h"
#include "si/gl/image_lod_error.h"
#include "si/headless/headless_context.h"

namespace si::tools {

bool printImageErrors(std::FILE* f, const Character& character, const BakedPalette& palette,
                      std::string* why) {
  std::unique_ptr<HeadlessContext> context;
  HeadlessDesc hd;
  hd.width = hd.height = 64;  // Drawn offscreen at its own size.
  Status s = HeadlessContext::create(hd, &context);
  GlInfo info;
  if (s.isOk()) s = loadGl(&HeadlessContext::getProcAddress, context.get(), &info);
  ImageLodErrorReport r;
  if (s.isOk()) s = measureImageLodErrors(info, character, palette, {}, &r);
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
    std::fprintf(f, "LOD %-2zu %12.4g %12.4g %8.3g", l, double(level.geometric_units),
                 double(level.image_units), level.one_pixel_height);
    for (double px : level.mean_differing_pixels) std::fprintf(f, " %8.2f", px);
    std::fprintf(f, "\n");
  }
  return true;
}

}  // namespace si::tools
