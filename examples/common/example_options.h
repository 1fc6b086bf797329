// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Command-line pieces shared by the example programs.

#include <algorithm>
#include <string>
#include <vector>

#include "si/headless/headless_context.h"

namespace si::examples {

/// Parses a --backend value (auto, egl-device, egl-surfaceless, osmesa); false if unknown.
inline bool parseBackend(const std::string& name, HeadlessBackend* out) {
  for (HeadlessBackend b : {HeadlessBackend::kAuto, HeadlessBackend::kEglDevice,
                            HeadlessBackend::kEglSurfaceless, HeadlessBackend::kOsMesa})
    if (name == headlessBackendName(b)) {
      *out = b;
      return true;
    }
  return false;
}

/// Splits "a,b,,c" into {"a", "b", "c"} (empty items dropped).
inline std::vector<std::string> splitList(const std::string& list) {
  std::vector<std::string> items;
  for (size_t at = 0; at <= list.size();) {
    const size_t comma = std::min(list.find(',', at), list.size());
    if (comma > at) items.push_back(list.substr(at, comma - at));
    at = comma + 1;
  }
  return items;
}

}  // namespace si::examples
