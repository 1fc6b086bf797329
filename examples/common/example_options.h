// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Command-line pieces shared by the example programs.

#include <string>

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

}  // namespace si::examples
