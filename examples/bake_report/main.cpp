// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// bake_report: speed against error for the baker. For the embedded character it bakes every
// format x sample rate (and the automatic rate) and prints one table: palette bytes, bake time,
// max / P99 / shell error in model units and as a fraction of the character's height.
// Usage: bake_report [--csv PATH] [--quick]   (--quick: f32 at 30 Hz and automatic only,
// for smoke tests)
#include <chrono>
#include <cstdio>
#include <string>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"

int main(int argc, char** argv) {
  std::string csv_path;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--csv" && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (arg == "--quick") {
      quick = true;
    } else {
      std::fprintf(stderr,
                   "bake_report: unknown option '%s'\nusage: bake_report [--csv PATH] [--quick]\n",
                   arg.c_str());
      return 2;
    }
  }
  si::Character character;
  si::Status s = si::makeDefaultCharacter({}, &character);
  if (!s.isOk()) {
    std::fprintf(stderr, "bake_report: %s\n", s.toString().c_str());
    return 1;
  }
  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (!csv_path.empty() && csv == nullptr) {
    std::fprintf(stderr, "bake_report: cannot write '%s'\n", csv_path.c_str());
    return 1;
  }
  if (csv)
    std::fprintf(csv, "model,format,rate,palette_bytes,bake_ms,max_units,p99_units,max_ratio,"
                      "p99_ratio,shell_max_units\n");
  std::printf("model: embedded character, height %.3f units, %zu joints, %zu vertices\n\n",
              double(character.height()), character.skeleton.jointCount(),
              character.mesh.vertexCount());
  std::printf("%-22s %6s %10s %9s %11s %11s %10s %10s %11s\n", "format", "rate", "bytes",
              "bake ms", "max units", "P99 units", "max/h", "P99/h", "shell max");
  const si::PaletteFormat formats[] = {si::PaletteFormat::kMatrix3x4F32,
                                       si::PaletteFormat::kMatrix3x4F16,
                                       si::PaletteFormat::kQuatTranslationF32};
  const float rates[] = {15.0f, 30.0f, 60.0f, 0.0f};  // 0: automatic.
  for (si::PaletteFormat format : formats) {
    if (quick && format != si::PaletteFormat::kMatrix3x4F32) continue;
    for (float rate : rates) {
      if (quick && rate != 30.0f && rate != 0.0f) continue;
      si::BakeDesc desc;
      desc.format = format;
      if (rate > 0.0f) {
        desc.rate_mode = si::RateMode::kFixed;
        desc.sample_rate_hz = rate;
      } else {
        desc.rate_mode = si::RateMode::kAutomatic;
      }
      si::BakedPalette palette;
      si::BakeReport report;
      const auto t0 = std::chrono::steady_clock::now();
      s = si::bakePalette(character, desc, &palette, &report);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (!s.isOk()) {
        std::fprintf(stderr, "bake_report: %s\n", s.toString().c_str());
        return 1;
      }
      double shell = 0.0;
      for (const auto& c : report.clips) shell = std::max(shell, c.shell_max_error_units);
      const std::string rate_name = rate > 0.0f ? std::to_string(int(rate)) : "auto";
      std::printf("%-22s %6s %10llu %9.1f %11.3g %11.3g %10.3g %10.3g %11.3g\n",
                  si::paletteFormatName(format), rate_name.c_str(),
                  static_cast<unsigned long long>(report.palette_bytes), ms,
                  report.max_error_units, report.p99_error_units, report.max_error_ratio,
                  report.p99_error_units / double(character.height()), shell);
      if (csv)
        std::fprintf(csv, "embedded,%s,%s,%llu,%.3f,%.6g,%.6g,%.6g,%.6g,%.6g\n",
                     si::paletteFormatName(format), rate_name.c_str(),
                     static_cast<unsigned long long>(report.palette_bytes), ms,
                     report.max_error_units, report.p99_error_units, report.max_error_ratio,
                     report.p99_error_units / double(character.height()), shell);
      if (rate == 0.0f)
        for (const auto& c : report.clips)
          std::printf("    auto %-6s -> %6.1f Hz, %4u frames, max %.3g units%s\n", c.name.c_str(),
                      c.sample_rate_hz, c.frame_count, c.max_error_units,
                      c.tolerance_met ? "" : " (tolerance not reached)");
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}
