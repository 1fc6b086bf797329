// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "lod_table.h"

#include <algorithm>
#include <vector>

#if SI_BAKE_IMAGE_ERRORS
#include "image_errors.h"
#endif
#include "si/core/lod_error.h"

namespace si_bake {

bool printLodTable(std::FILE* f, const si::Character& character, const si::BakedPalette& palette,
                   bool image_errors, const si::ImpostorDesc* impostor, std::string* why) {
  si::Character posed = character;
  si::AnimatedLodErrorDesc poses;
  poses.poses_per_clip = 4;
  poses.max_poses = 64;
  std::vector<si::LodLevelSummary> bind, animated;
  si::Status s = si::summarizeLodLevels(character.mesh, &bind);
  if (s.isOk()) s = si::measureAnimatedLodErrors(&posed, poses, nullptr);
  if (s.isOk()) s = si::summarizeLodLevels(posed.mesh, &animated);
  if (!s.isOk()) {
    std::fprintf(f, "LOD errors not measured: %s\n", s.toString().c_str());
    *why = s.toString();
    return !image_errors;
  }
  const double height = std::max(1e-30, double(character.height()));
  std::fprintf(f, "%-6s %10s %12s %12s %12s\n", "LOD", "triangles", "bind units", "posed units",
               "posed/h");
  for (size_t l = 0; l < bind.size(); ++l)
    std::fprintf(f, "LOD %-2zu %10llu %12.4g %12.4g %12.4g\n", l,
                 static_cast<unsigned long long>(bind[l].triangles), double(bind[l].error_units),
                 double(animated[l].error_units), double(animated[l].error_units) / height);
#if SI_BAKE_IMAGE_ERRORS
  if (image_errors) return si::tools::printImageErrors(f, posed, palette, impostor, why);
#else
  (void)palette;
  (void)impostor;
#endif
  return true;
}

}  // namespace si_bake
