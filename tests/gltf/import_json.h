// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A glTF document the tests wrote (gltf_writer.h), imported from memory: no folder, so
// external URIs are refused.

#include <cstdint>
#include <string>

#include "si/gltf/gltf_import.h"

namespace si::test {

inline Status importJson(const std::string& json, Character* c, GltfImportReport* r = nullptr,
                         const GltfImportDesc& d = {}) {
  return importGltfMemory(
      Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "", d, c, r);
}

}  // namespace si::test
