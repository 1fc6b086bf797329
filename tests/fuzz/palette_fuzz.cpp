// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target for the palette loader: any bytes give an error or a palette that saves back
// to the same bytes; never a crash or a sanitizer report. Run with scripts/fuzz.sh.
#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "si/bake/palette_file.h"

namespace {
int loadAndCheck(const uint8_t* data, size_t size);
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loadAndCheck(data, size);
  // Most mutations break the checksum; repair it on a copy so the structural checks behind it
  // are fuzzed too.
  if (size >= 4) {
    std::vector<uint8_t> copy(data, data + size);
    const uint32_t crc = si::crc32(si::Span<const uint8_t>(copy.data(), size - 4));
    std::memcpy(copy.data() + size - 4, &crc, 4);
    loadAndCheck(copy.data(), size);
  }
  return 0;
}

namespace {
int loadAndCheck(const uint8_t* data, size_t size) {
  si::BakedPalette palette;
  const si::Status s = si::loadPalette(si::Span<const uint8_t>(data, size), &palette);
  if (!s.isOk()) return 0;
  // A palette that loads is consistent: it saves back to exactly the same bytes, and every
  // frame of every clip samples inside the texture.
  std::vector<uint8_t> again;
  if (!si::savePalette(palette, &again).isOk()) std::abort();
  if (again.size() != size || !std::equal(again.begin(), again.end(), data)) std::abort();
  for (uint32_t c = 0; c < palette.clips.size(); ++c) {
    const si::FrameSample f = si::sampleFrames(palette.clips[c], 1e9);
    (void)si::emulateSkinningMatrix(palette, c, f, 0);
  }
  return 0;
}
}  // namespace
