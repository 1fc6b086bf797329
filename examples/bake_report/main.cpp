// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// bake_report: speed against error for the baker. For the embedded character it bakes every
// format x sample rate (and the automatic frames, on one grid and with the default placement)
// and prints one table: palette bytes, bake time,
// max / P99 / shell error in model units and as a fraction of the character's height.
// Usage: bake_report [--csv PATH] [--quick] [--model FILE.gltf|FILE.glb]...
//   --quick: f32 at 30 Hz and automatic only, for smoke tests; each --model adds a glTF
//   character's table after the embedded character's.
#include <chrono>
#include <cstdio>
#include <string>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/gltf/gltf_import.h"

int main(int argc, char** argv) {
  std::string csv_path;
  bool quick = false;
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--csv" && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (arg == "--quick") {
      quick = true;
    } else if (arg == "--model" && i + 1 < argc) {
      models.push_back(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "bake_report: unknown option '%s'\nusage: bake_report [--csv PATH] [--quick] "
                   "[--model FILE]...\n",
                   arg.c_str());
      return 2;
    }
  }
  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (!csv_path.empty() && csv == nullptr) {
    std::fprintf(stderr, "bake_report: cannot write '%s'\n", csv_path.c_str());
    return 1;
  }
  if (csv)
    std::fprintf(csv, "model,format,rate,palette_bytes,bake_ms,max_units,p99_units,max_ratio,"
                      "p99_ratio,shell_max_units\n");
  models.insert(models.begin(), "");  // The embedded character first.
  for (const std::string& model : models) {
  si::Character character;
  si::Status s = model.empty() ? si::makeDefaultCharacter({}, &character)
                               : si::importGltfFile(model, {}, &character, nullptr);
  if (!s.isOk()) {
    std::fprintf(stderr, "bake_report: %s: %s\n", model.c_str(), s.toString().c_str());
    return 1;
  }
  const std::string model_name = model.empty() ? "embedded" : model.substr(model.find_last_of('/') + 1);
  std::printf("\nmodel: %s, height %.3f units, %zu joints, %zu vertices, %zu clips\n\n",
              model_name.c_str(), double(character.height()), character.skeleton.jointCount(),
              character.mesh.vertexCount(), character.clips.size());
  std::printf("%-22s %6s %10s %9s %11s %11s %10s %10s %11s\n", "format", "rate", "bytes",
              "bake ms", "max units", "P99 units", "max/h", "P99/h", "shell max");
  const si::PaletteFormat formats[] = {si::PaletteFormat::kMatrix3x4F32,
                                       si::PaletteFormat::kMatrix3x4F16,
                                       si::PaletteFormat::kQuatTranslationF32};
  // 0: automatic (the default: per clip the fewer of one grid and frames at the keys); -1:
  // automatic on one grid only (the placement before frames at keys), side by side.
  const float rates[] = {15.0f, 30.0f, 60.0f, -1.0f, 0.0f};
  for (si::PaletteFormat format : formats) {
    if (quick && format != si::PaletteFormat::kMatrix3x4F32) continue;
    for (float rate : rates) {
      if (quick && rate != 30.0f && rate != 0.0f) continue;
      const std::string rate_name = rate > 0.0f ? std::to_string(int(rate)) : rate < 0.0f ? "grid" : "auto";
      si::BakeDesc desc;
      desc.format = format;
      if (rate > 0.0f) {
        desc.rate_mode = si::RateMode::kFixed;
        desc.sample_rate_hz = rate;
      } else {
        desc.rate_mode = si::RateMode::kAutomatic;
        desc.accept_tolerance_miss = true;  // The table reports the error reached.
        if (rate < 0.0f) desc.placement = si::FramePlacement::kGrid;
      }
      si::BakedPalette palette;
      si::BakeReport report;
      const auto t0 = std::chrono::steady_clock::now();
      s = si::bakePalette(character, desc, &palette, &report);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (!s.isOk()) {  // E.g. the rotation format on a model with non-uniform scale.
        std::printf("%-22s %6s  %s\n", si::paletteFormatName(format), rate_name.c_str(),
                    s.message().c_str());
        continue;
      }
      double shell = 0.0;
      for (const auto& c : report.clips) shell = std::max(shell, c.shell_max_error_units);
      std::printf("%-22s %6s %10llu %9.1f %11.3g %11.3g %10.3g %10.3g %11.3g\n",
                  si::paletteFormatName(format), rate_name.c_str(),
                  static_cast<unsigned long long>(report.palette_bytes), ms,
                  report.max_error_units, report.p99_error_units, report.max_error_ratio,
                  report.p99_error_units / double(character.height()), shell);
      if (csv)
        std::fprintf(csv, "%s,%s,%s,%llu,%.3f,%.6g,%.6g,%.6g,%.6g,%.6g\n", model_name.c_str(),
                     si::paletteFormatName(format), rate_name.c_str(),
                     static_cast<unsigned long long>(report.palette_bytes), ms,
                     report.max_error_units, report.p99_error_units, report.max_error_ratio,
                     report.p99_error_units / double(character.height()), shell);
      if (rate <= 0.0f)
        for (const auto& c : report.clips)
          std::printf("    %s %-6s -> %6.1f Hz%s, %4u frames, max %.3g units%s\n",
                      rate_name.c_str(), c.name.c_str(), c.sample_rate_hz,
                      c.frames_at_keys ? " (at keys, average)" : "", c.frame_count,
                      c.max_error_units, c.tolerance_met ? "" : " (tolerance not reached)");
    }
  }
  }
  if (csv) std::fclose(csv);
  return 0;
}
