// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/bake_error_table.h"
#include "crowd_bench/bench_character.h"

#include "si/bake/animation_baker.h"

namespace si::bench {

Status bakeErrorTable(Setup& setup, Renderer& renderer, const Character& character,
                      uint32_t instances, const std::string& path, const LodChoice& lod,
                      bool quick, std::FILE* csv, std::string* plot_data) {
  CharacterId id;
  std::printf("\nGPU time against bake error (field, %u instances, %s path)\n",
              instances, path.c_str());
  std::printf("%-22s %-6s %6s %6s %10s %10s %9s %12s %12s\n", "format", "interp", "rate",
              "stride", "texels", "bytes", "GPU ms", "max error", "P99 error");
  using Interp = InterpolationChoice;
  struct Config {
    PaletteFormat format;
    float rate;
    uint32_t stride;  // Joint stride in texels; 0: the default (4, or 2 for quaternions).
    Interp interpolation = Interp::kLinear;
    FramePlacement placement = FramePlacement::kDefault;  // Automatic rates: fewer of grid, keys.
  };
  const Config configs[] = {{PaletteFormat::kMatrix3x4F32, 15, 0},
                            {PaletteFormat::kMatrix3x4F32, 30, 0},
                            {PaletteFormat::kMatrix3x4F32, 60, 0},
                            {PaletteFormat::kMatrix3x4F32, 0, 0, Interp::kLinear, FramePlacement::kGrid},
                            {PaletteFormat::kMatrix3x4F32, 0, 0},
                            {PaletteFormat::kMatrix3x4F32, 0, 3},
                            {PaletteFormat::kMatrix3x4F16, 30, 0},
                            {PaletteFormat::kMatrix3x4F16, 0, 0},
                            {PaletteFormat::kQuatTranslationF32, 30, 0},
                            {PaletteFormat::kQuatTranslationF32, 0, 0},
                            {PaletteFormat::kMatrix3x4F32, 30, 0, Interp::kCubic},
                            {PaletteFormat::kMatrix3x4F32, 0, 0, Interp::kCubic, FramePlacement::kGrid},
                            {PaletteFormat::kMatrix3x4F32, 0, 0, Interp::kCubic},
                            {PaletteFormat::kQuatTranslationF32, 30, 0, Interp::kCubic},
                            {PaletteFormat::kQuatTranslationF32, 0, 0, Interp::kCubic}};
  for (const Config& c : configs) {
    if (quick && c.rate == 0.0f) continue;
    BakeDesc d;
    d.format = c.format;
    d.joint_stride_texels = c.stride;
    d.interpolation = c.interpolation;
    d.placement = c.placement;
    d.accept_tolerance_miss = true;  // The table reports the error reached.
    if (c.rate > 0.0f) {
      d.rate_mode = RateMode::kFixed;
      d.sample_rate_hz = c.rate;
    }
    BakedPalette p;
    BakeReport r;
    Status s = bakePalette(character, d, &p, &r);
    // The re-made renderer's character 0: added by the first configuration, replaced after.
    if (s.isOk())
      s = renderer.characterCount() == 0 ? renderer.addCharacter(character, p, &id)
                                         : renderer.replaceCharacter(id, character, p);
    if (s.isOk()) s = addImpostor(setup, renderer, id);
    if (!s.isOk()) return {s.code(), "bake configuration: " + s.message()};
    Row row;
    s = runPath(setup, renderer, p, "field", instances, path,
                           lod, &row);
    if (!s.isOk()) return {s.code(), path + ": " + s.message()};
    // Automatic rates: "auto" frames at keys where fewer, "grid" on one grid per clip.
    const std::string rate = c.rate > 0.0f ? std::to_string(int(c.rate))
                             : c.placement == FramePlacement::kGrid ? "grid" : "auto";
    const std::string texels = std::to_string(p.layout.width) + "x" + std::to_string(p.layout.height);
    const char* interp = interpolationChoiceName(c.interpolation);
    std::printf("%-22s %-6s %6s %6u %10s %10llu %9.3f %12.3g %12.3g\n",
                paletteFormatName(c.format), interp, rate.c_str(),
                p.layout.joint_stride_texels, texels.c_str(),
                static_cast<unsigned long long>(r.palette_bytes), row.gpu_ms, r.max_error_units,
                r.p99_error_units);
    std::fprintf(csv, "error,field,%s,%u,%u,%u,%.0f,%.4f,%.4f,%.4f,%s%s%s,%s,%.6g,%.6g,%s,,,\n",
                 path.c_str(), row.instances, row.visible, row.draws, row.triangles,
                 row.update_ms, row.submit_ms, row.gpu_ms, paletteFormatName(c.format),
                 p.layout.joint_stride_texels == 3 ? "_stride3" : "",
                 c.interpolation == Interp::kCubic ? "_cubic" : "", rate.c_str(),
                 r.max_error_units, r.p99_error_units, row.lod.c_str());
    *plot_data += std::to_string(r.max_error_units) + " " + std::to_string(row.gpu_ms) + " \"" +
                  paletteFormatName(c.format) + "@" + rate +
                  (c.interpolation == Interp::kCubic ? " cubic" : "") + "\"\n";
  }
  return Status::ok();
}

}  // namespace si::bench
