// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target: palette load (as is and with the checksum repaired) followed by a crowd
// playing every clip through a few updates. A palette that loads must init a crowd, and every
// record must be finite with frame texels inside the palette; never a crash or a sanitizer
// report. Seeded with the palette seeds and tests/regressions/inputs; run with scripts/fuzz.sh.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "si/bake/palette_file.h"
#include "si/crowd/crowd_manager.h"

namespace {

void play(const si::BakedPalette& palette) {
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = 2;
  cd.lod_count = 2;
  si::CrowdManager crowd;
  if (!crowd.init(cd).isOk()) std::abort();  // A loaded palette is valid: init must take it.
  const uint32_t clips = uint32_t(std::min<size_t>(palette.clips.size(), 64));
  for (uint32_t c = 0; c < clips; ++c) {
    si::InstanceDesc d;
    d.clip = c;
    d.position = glm::dvec3(0.3 * c, 0.0, -4.0);
    d.time_seconds = 0.37 * c;
    d.speed = 1.0f + 0.5f * float(c % 3);
    si::InstanceHandle h;
    if (!crowd.add(d, &h).isOk()) std::abort();
    if (c % 2 == 1 && !crowd.crossfade(h, (c + 1) % clips, 0.25).isOk()) std::abort();
  }
  const uint64_t texels = palette.layout.textureTexelCount();
  const si::Camera camera;
  for (double dt : {0.0, 1.0 / 60.0, 0.1, 3.7, 1e6}) {
    if (!crowd.update(dt, camera).isOk()) std::abort();
    for (const si::InstanceRecord& r : crowd.view().records()) {
      for (const auto& row : r.world_rows)
        for (float v : row)
          if (!std::isfinite(v)) std::abort();
      for (uint32_t f : r.frames)
        if (uint64_t(f) + uint64_t(palette.layout.frame_stride_texels) > texels) std::abort();
      for (int k = 0; k < 3; ++k) {
        float v = si::unpackFraction(r.blend[k], nullptr);
        if (k == 2) std::memcpy(&v, &r.blend[k], 4);  // The weight carries no mode.
        if (!(v >= 0.0f && v <= 1.0f)) std::abort();
      }
    }
  }
}

void loadAndPlay(const uint8_t* data, size_t size) {
  si::BakedPalette palette;
  if (si::loadPalette(si::Span<const uint8_t>(data, size), &palette).isOk()) play(palette);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loadAndPlay(data, size);
  if (size >= 4) {  // Repair the checksum so the checks behind it are reached.
    std::vector<uint8_t> copy(data, data + size);
    const uint32_t crc = si::crc32(si::Span<const uint8_t>(copy.data(), size - 4));
    std::memcpy(copy.data() + size - 4, &crc, 4);
    loadAndPlay(copy.data(), size);
  }
  return 0;
}
