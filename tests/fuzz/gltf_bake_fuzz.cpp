// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target: glTF import (from memory, no folder) followed by baking with a fixed and an
// automatic rate. Any bytes give an error or a palette that passes BakedPalette::validate();
// never a crash, a sanitizer report, gigabytes or minutes (the baker refuses palettes past
// BakeDesc::max_palette_bytes, here 8 MiB, and bakes past max_evaluations, here 2^22, before
// allocating or evaluating). Seeded with assets; run with scripts/fuzz.sh.
#include <cstdint>
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "si/bake/animation_baker.h"
#include "si/gltf/gltf_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  si::Character c;
  si::GltfImportDesc d;
  d.load_images = false;  // stb_image is fuzzed by its own project; keep the focus here.
  const si::Status s = si::importGltfMemory(si::Span<const uint8_t>(data, size), "", d, &c, nullptr);
  if (!s.isOk()) return 0;
  if (!c.validate().isOk()) std::abort();
  // The bake's work grows with the drawn triangles: keep LOD 0 of each sub-mesh and at most
  // 64 of its triangles, so inputs that pass the work limit still bake in well under a second.
  for (si::SubMesh& sm : c.mesh.sub_meshes) {
    sm.lods.resize(1);
    sm.lods[0].index_count = std::min<uint32_t>(sm.lods[0].index_count, 64 * 3);
  }
  if (!c.validate().isOk()) std::abort();
  // Fixed rates; automatic frames (grid or keys); frames at the keys, cubic. A miss of the
  // tolerance is kept, so every palette the search makes is validated.
  const si::RateMode modes[] = {si::RateMode::kFixed, si::RateMode::kAutomatic, si::RateMode::kAutomatic};
  for (int config = 0; config < 3; ++config) {
    const si::RateMode mode = modes[config];
    si::BakeDesc b;
    b.rate_mode = mode;
    b.accept_tolerance_miss = true;
    if (config == 2) {
      b.placement = si::FramePlacement::kKeys;
      b.interpolation = si::InterpolationChoice::kCubic;
    }
    b.max_palette_bytes = uint64_t(8) << 20;
    b.max_evaluations = uint64_t(1) << 22;
    b.max_sample_rate_hz = 60.0f;  // Bounds the automatic search's work per clip.
    si::BakedPalette p;
    si::BakeReport r;
    const si::Status bs = si::bakePalette(c, b, &p, &r);
    if (bs.isOk()) {
      const si::Status v = p.validate();
      if (!v.isOk() || p.texel_bytes.size() > b.max_palette_bytes) {
        std::fprintf(stderr, "baked palette (%s rate) fails validation: %s (%zu texel bytes)\n",
                     mode == si::RateMode::kFixed ? "fixed" : "automatic", v.toString().c_str(),
                     p.texel_bytes.size());
        std::abort();
      }
    }
    if (!bs.isOk() && bs.message().empty()) std::abort();
  }
  return 0;
}
