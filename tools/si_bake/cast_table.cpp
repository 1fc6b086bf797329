// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "cast_table.h"

#include <map>
#include <utility>

#include "si/bake/animation_baker.h"

namespace si_bake {

bool printCastTable(std::FILE* f, const std::vector<CastMember>& cast, const si::BakeDesc& base) {
  const si::PaletteFormat formats[] = {si::PaletteFormat::kMatrix3x4F32,
                                       si::PaletteFormat::kMatrix3x4F16,
                                       si::PaletteFormat::kQuatTranslationF32};
  const si::InterpolationChoice choices[] = {si::InterpolationChoice::kLinear,
                                             si::InterpolationChoice::kCubic,
                                             si::InterpolationChoice::kSmaller};
  struct Total {
    uint64_t bytes = 0;
    uint32_t characters = 0;
    bool all_met = true;
  };
  std::map<std::pair<int, int>, Total> totals;
  bool any = false;
  const double tolerance = double(si::resolveDefaults(base).error_tolerance_ratio);
  std::fprintf(f, "cast memory at max error <= %.3g of each character's height (automatic rates)\n",
               tolerance);
  std::fprintf(f, "%-24s %-22s %-8s %7s %12s %11s %10s %4s\n", "character", "format", "interp",
               "frames", "bytes", "max units", "max/h", "ok");
  for (const CastMember& m : cast)
    for (size_t fi = 0; fi < 3; ++fi)
      for (size_t ci = 0; ci < 3; ++ci) {
        si::BakeDesc d = base;
        d.format = formats[fi];
        d.interpolation = choices[ci];
        d.progress = nullptr;
        d.accept_tolerance_miss = true;  // The table says which meet it.
        si::BakedPalette palette;
        si::BakeReport report;
        const si::Status s = si::bakePalette(m.character, d, &palette, &report);
        if (!s.isOk()) {
          std::fprintf(f, "%-24s %-22s %-8s refused: %s\n", m.name.c_str(),
                       si::paletteFormatName(formats[fi]), si::interpolationChoiceName(choices[ci]),
                       s.message().c_str());
          totals[{int(fi), int(ci)}].all_met = false;
          continue;
        }
        any = true;
        uint32_t frames = 0;
        bool met = true;
        for (const si::ClipErrorReport& e : report.clips) {
          frames += e.frame_count;
          met = met && e.tolerance_met;
        }
        std::fprintf(f, "%-24s %-22s %-8s %7u %12llu %11.3g %10.3g %4s\n", m.name.c_str(),
                     si::paletteFormatName(formats[fi]), si::interpolationChoiceName(choices[ci]),
                     frames, static_cast<unsigned long long>(report.palette_bytes),
                     report.max_error_units, report.max_error_ratio, met ? "yes" : "NO");
        Total& t = totals[{int(fi), int(ci)}];
        t.bytes += report.palette_bytes;
        ++t.characters;
        t.all_met = t.all_met && met;
      }
  std::fprintf(f, "%-24s %-22s %-8s %7s %12s %27s\n", "total", "format", "interp", "chars",
               "bytes", "every clip ok");
  for (const auto& [key, t] : totals)
    std::fprintf(f, "%-24s %-22s %-8s %7u %12llu %27s\n", "(cast)",
                 si::paletteFormatName(formats[key.first]),
                 si::interpolationChoiceName(choices[key.second]), t.characters,
                 static_cast<unsigned long long>(t.bytes), t.all_met ? "yes" : "NO");
  return any;
}

}  // namespace si_bake
