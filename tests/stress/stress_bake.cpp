// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// stress_bake: bakes the generated stress character (stress/stress_character.h) and prints the
// bake's time, peak memory and error per clip. Usage:
//   stress_bake [--duration S] [--rings N] [--format f32|f16|quat] [--interpolation linear|cubic|smaller]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "si/bake/animation_baker.h"
#include "stress/stress_character.h"

int main(int argc, char** argv) {
  si::test::StressDesc sd;
  si::BakeDesc d;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    if (a == "--duration" && v) {
      sd.duration_seconds = std::strtof(v, nullptr), ++i;
    } else if (a == "--rings" && v) {
      sd.rings = uint32_t(std::atoi(v)), ++i;
    } else if (a == "--format" && v) {
      const std::string f = v;
      d.format = f == "f16" ? si::PaletteFormat::kMatrix3x4F16
                 : f == "quat" ? si::PaletteFormat::kQuatTranslationF32
                               : si::PaletteFormat::kMatrix3x4F32;
      ++i;
    } else if (a == "--interpolation" && v) {
      const std::string f = v;
      d.interpolation = f == "cubic"     ? si::InterpolationChoice::kCubic
                        : f == "smaller" ? si::InterpolationChoice::kSmaller
                                         : si::InterpolationChoice::kLinear;
      ++i;
    } else {
      std::fprintf(stderr, "stress_bake: unknown option '%s'\n", a.c_str());
      return 2;
    }
  }
  const si::Character c = si::test::makeStressCharacter(sd);
  std::printf("stress character: %zu vertices, %zu joints, %zu sub-meshes, clip %.1f s, height %.3f\n",
              c.mesh.vertexCount(), c.skeleton.jointCount(), c.mesh.sub_meshes.size(),
              double(c.clips[0].duration_seconds), double(c.height()));
  const auto t0 = std::chrono::steady_clock::now();
  std::string stage;
  d.progress = [&](const si::BakeProgress& p) {
    if (stage != p.stage)
      std::printf("  %6.2f s: %s\n",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), p.stage);
    stage = p.stage;
  };
  si::BakedPalette p;
  si::BakeReport r;
  const si::Status s = si::bakePalette(c, d, &p, &r);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "\n");
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  std::printf("bake: %s; %.2f s, peak memory %.0f MB\n", s.isOk() ? "ok" : s.message().c_str(),
              seconds, double(u.ru_maxrss) / 1024.0);
  for (const si::ClipErrorReport& cr : r.clips)
    std::printf("  clip %s: %s, %u frames (%.1f Hz), %.2f MB, max %.3g units (%.3g of height) at %.3f s, "
                "joint %u, tolerance %s\n",
                cr.name.c_str(), cr.interpolation == si::FrameInterpolation::kCubic ? "cubic" : "linear",
                cr.frame_count, cr.sample_rate_hz, double(cr.palette_bytes) / 1e6, cr.max_error_units,
                cr.max_error_ratio, cr.max_error_time_seconds, cr.max_error_joint,
                cr.tolerance_met ? "met" : "NOT met");
  return s.isOk() ? 0 : 1;
}
