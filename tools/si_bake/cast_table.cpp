// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "cast_table.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <utility>

#include "si/bake/animation_baker.h"

namespace si_bake {

namespace {

// Peak resident memory of this process in MiB since the last resetPeakMemory(), or -1 where
// the system does not say (Linux: VmHWM in /proc/self/status, reset through clear_refs).
void resetPeakMemory() {
  if (std::FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", f);
    std::fclose(f);
  }
}
double peakMemoryMiB() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return -1.0;
  char line[256];
  double kib = -1.0;
  while (std::fgets(line, sizeof line, f) != nullptr)
    if (std::strncmp(line, "VmHWM:", 6) == 0) kib = std::atof(line + 6);
  std::fclose(f);
  return kib < 0.0 ? -1.0 : kib / 1024.0;
}

// One bake of a cast member: what the table prints of it.
struct Cell {
  bool ok = false;
  std::string refusal;
  uint32_t frames = 0;
  uint64_t bytes = 0;
  double max_ratio = 0.0;
  bool met = true;
  double seconds = 0.0;
  double peak_mib = -1.0;
};

Cell bake(const si::Character& character, const si::BakeDesc& d) {
  Cell c;
  si::BakedPalette palette;
  si::BakeReport report;
  resetPeakMemory();
  const auto start = std::chrono::steady_clock::now();
  const si::Status s = si::bakePalette(character, d, &palette, &report);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.peak_mib = peakMemoryMiB();
  if (!s.isOk()) {
    c.refusal = s.message();
    return c;
  }
  c.ok = true;
  for (const si::ClipErrorReport& e : report.clips) {
    c.frames += e.frame_count;
    c.met = c.met && e.tolerance_met;
  }
  c.bytes = report.palette_bytes;
  c.max_ratio = report.max_error_ratio;
  return c;
}

}  // namespace

bool printCastTable(std::FILE* f, const std::vector<CastMember>& cast, const si::BakeDesc& base) {
  const si::PaletteFormat formats[] = {si::PaletteFormat::kMatrix3x4F32,
                                       si::PaletteFormat::kMatrix3x4F16,
                                       si::PaletteFormat::kQuatTranslationF32};
  const si::InterpolationChoice choices[] = {si::InterpolationChoice::kLinear,
                                             si::InterpolationChoice::kCubic,
                                             si::InterpolationChoice::kSmaller};
  // Each row: the frames on one uniform grid (the placement before frames at keys) and the
  // default placement (per clip the fewer of grid and keys), side by side.
  const si::FramePlacement placements[] = {si::FramePlacement::kGrid, si::FramePlacement::kFewer};
  struct Total {
    uint64_t bytes[2] = {0, 0};
    uint32_t characters = 0;
    bool all_met[2] = {true, true};
  };
  std::map<std::pair<int, int>, Total> totals;
  bool any = false;
  const double tolerance = double(si::resolveDefaults(base).error_tolerance_ratio);
  std::fprintf(f, "cast memory at max error <= %.3g of each character's height (automatic rates); "
               "grid: one rate per clip, fewer: per clip the fewer of grid and frames at keys\n",
               tolerance);
  std::fprintf(f, "%-20s %-20s %-7s | %-6s %6s %10s %9s %3s %7s %7s | %-6s %6s %10s %9s %3s %7s %7s\n",
               "character", "format", "interp", "place", "frames", "bytes", "max/h", "ok", "s",
               "MiB", "place", "frames", "bytes", "max/h", "ok", "s", "MiB");
  for (const CastMember& m : cast)
    for (size_t fi = 0; fi < 3; ++fi)
      for (size_t ci = 0; ci < 3; ++ci) {
        Total& t = totals[{int(fi), int(ci)}];
        std::fprintf(f, "%-20s %-20s %-7s", m.name.c_str(), si::paletteFormatName(formats[fi]),
                     si::interpolationChoiceName(choices[ci]));
        bool row_ok = true;
        for (int p = 0; p < 2; ++p) {
          si::BakeDesc d = base;
          d.format = formats[fi];
          d.interpolation = choices[ci];
          d.placement = placements[p];
          d.progress = nullptr;
          d.accept_tolerance_miss = true;  // The table says which meet it.
          const Cell c = bake(m.character, d);
          if (!c.ok) {
            std::fprintf(f, " | refused: %s", c.refusal.c_str());
            t.all_met[p] = false;
            row_ok = false;
            continue;
          }
          std::fprintf(f, " | %-6s %6u %10llu %9.3g %3s %7.2f %7.0f",
                       si::framePlacementName(placements[p]), c.frames,
                       static_cast<unsigned long long>(c.bytes), c.max_ratio, c.met ? "yes" : "NO",
                       c.seconds, c.peak_mib);
          t.bytes[p] += c.bytes;
          t.all_met[p] = t.all_met[p] && c.met;
          any = true;
        }
        if (row_ok) ++t.characters;
        std::fprintf(f, "\n");
      }
  std::fprintf(f, "%-20s %-20s %-7s | %6s %10s %-8s | %10s %-8s %s\n", "total", "format", "interp",
               "chars", "grid B", "all ok", "fewer B", "all ok", "grid/fewer");
  for (const auto& [key, t] : totals)
    std::fprintf(f, "%-20s %-20s %-7s | %6u %10llu %-8s | %10llu %-8s %.2fx\n", "(cast)",
                 si::paletteFormatName(formats[key.first]),
                 si::interpolationChoiceName(choices[key.second]), t.characters,
                 static_cast<unsigned long long>(t.bytes[0]), t.all_met[0] ? "yes" : "NO",
                 static_cast<unsigned long long>(t.bytes[1]), t.all_met[1] ? "yes" : "NO",
                 t.bytes[1] ? double(t.bytes[0]) / double(t.bytes[1]) : 0.0);
  return any;
}

}  // namespace si_bake
