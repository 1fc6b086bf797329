// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target for the glTF importer (from memory, no folder: external URIs refused):
// any bytes give an error or a character that validates; never a crash or sanitizer report.
// Run with scripts/fuzz.sh, seeded with ../shared/assets.
#include <cstdint>
#include <cstdlib>

#include "si/gltf/gltf_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  si::Character c;
  si::GltfImportDesc d;
  d.load_images = false;  // stb_image is fuzzed by its own project; keep the focus here.
  const si::Status s = si::importGltfMemory(si::Span<const uint8_t>(data, size), "", d, &c, nullptr);
  if (s.isOk() && !c.validate().isOk()) std::abort();
  return 0;
}
