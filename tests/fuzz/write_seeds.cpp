// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Writes seed inputs for the fuzzers into a folder: palette files of the embedded character in
// every format. Usage: si_write_fuzz_seeds DIR
#include <cstdio>
#include <string>

#include "si/bake/palette_file.h"
#include "si/core/default_character.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: si_write_fuzz_seeds DIR\n");
    return 2;
  }
  si::Character c;
  si::DefaultCharacterDesc cd;
  cd.lod_count = 1;
  if (!si::makeDefaultCharacter(cd, &c).isOk()) return 1;
  const si::PaletteFormat formats[] = {si::PaletteFormat::kMatrix3x4F32,
                                       si::PaletteFormat::kMatrix3x4F16,
                                       si::PaletteFormat::kQuatTranslationF32};
  for (si::PaletteFormat f : formats) {
    si::BakeDesc d;
    d.format = f;
    d.rate_mode = si::RateMode::kFixed;
    d.sample_rate_hz = 5.0f;
    d.clip_names = {"wave"};  // Has STEP frame times.
    si::BakedPalette p;
    si::Status s = si::bakePalette(c, d, &p, nullptr);
    if (s.isOk())
      s = si::savePaletteFile(p, std::string(argv[1]) + "/" + si::paletteFormatName(f) + ".sipal");
    if (!s.isOk()) {
      std::fprintf(stderr, "si_write_fuzz_seeds: %s\n", s.toString().c_str());
      return 1;
    }
  }
  return 0;
}
