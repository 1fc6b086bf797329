// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Writes generated seed inputs for the fuzzers. Usage: si_write_fuzz_seeds KIND DIR with KIND
//   palette:   palette files of the embedded character's STEP clip and of a clip with root
//              motion, in every format
//   crowd-api: byte strings for the CrowdManager call-sequence fuzzer (a fixed generator: the
//              same seeds every time), each a few hundred calls; random ones, and ones whose
//              bytes make valid instances
//   gltf:      hostile glTF files, each breaking one rule of a small skinned file
//              (hostile_gltf.h), and well-formed morph target files (gltf/morph_asset.h)
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "hostile_gltf.h"
#include "si/bake/palette_file.h"
#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"

namespace {

int writePalettes(const std::string& dir) {
  si::Character c;
  si::DefaultCharacterDesc cd;
  cd.lod_count = 1;
  cd.moving_clips = true;
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
    if (s.isOk()) s = si::savePaletteFile(p, dir + "/" + si::paletteFormatName(f) + ".sipal");
    d.clip_names = {"walk_turn_left"};  // Root motion samples.
    if (s.isOk()) s = si::bakePalette(c, d, &p, nullptr);
    if (s.isOk())
      s = si::savePaletteFile(p, dir + "/" + si::paletteFormatName(f) + "_root_motion.sipal");
    if (!s.isOk()) {
      std::fprintf(stderr, "si_write_fuzz_seeds: %s\n", s.toString().c_str());
      return 1;
    }
  }
  return 0;
}

int writeCrowdApi(const std::string& dir) {
  std::mt19937 rng(20261123);
  for (int k = 0; k < 12; ++k) {
    std::vector<char> bytes(size_t(512) << (k % 4));
    for (char& b : bytes) b = char(rng() & 0xFF);
    std::ofstream out(dir + "/crowd_api_" + std::to_string(k) + ".bin", std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) {
      std::fprintf(stderr, "si_write_fuzz_seeds: cannot write into %s\n", dir.c_str());
      return 1;
    }
  }
  // Random bytes almost never make a valid instance (a NaN, a zero scale or a translucent tint
  // somewhere), so the replay would test little past init. These draw from bytes that read as
  // finite values of the fuzzer's table (index b % 14: 0, -0, -1, 0.5, 1), alphas of 255 and
  // every kind of call: a dozen instances live in each.
  // Seeds 6 and 7: the same with an impostor level (the desc byte's bit 5), 2 and 3 levels.
  const uint8_t benign[] = {73, 80, 81, 74, 76, 94};
  for (int k = 0; k < 8; ++k) {
    std::vector<char> bytes(2048);
    for (char& b : bytes) b = char(benign[rng() % sizeof(benign)]);
    if (k >= 6) bytes[1] = char(k == 6 ? 34 : 35);
    std::ofstream out(dir + "/crowd_api_benign_" + std::to_string(k) + ".bin", std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) {
      std::fprintf(stderr, "si_write_fuzz_seeds: cannot write into %s\n", dir.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string kind = argc == 3 ? argv[1] : "";
  if (kind == "palette") return writePalettes(argv[2]);
  if (kind == "crowd-api") return writeCrowdApi(argv[2]);
  if (kind == "gltf") return si::fuzz::writeHostileGltfs(argv[2]);
  std::fprintf(stderr, "usage: si_write_fuzz_seeds palette|crowd-api|gltf DIR\n");
  return 2;
}
