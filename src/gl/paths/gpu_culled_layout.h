// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The GPU-driven path's buffer layouts as its shaders read them (the counters, the indirect
// commands), and how its buffers are (re)created; shared by the passes (gpu_culled_path.cpp)
// and the uploads (gpu_state_upload.cpp).

#include <glad/gl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "gl/programs/cull_layout.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/status.h"

namespace si::detail {

// SiCommands: vertex-shader draws at 0, pre-skinned draws from command 256 on (20 bytes each).
inline constexpr GLintptr kPreskinnedCommands = GLintptr(kMaxBuckets) * 20;
// The impostor bucket's glDrawArraysIndirect command (cull_commands.comp.glsl's word 2560).
inline constexpr GLintptr kImpostorCommand = kPreskinnedCommands * 2;

// (Re)creates `buffer` with `bytes` of storage, at least 16 (and its first `bytes` from `data`
// when given), dynamic.
inline Status recreate(GLuint* buffer, size_t bytes, const void* data, const char* what) {
  uint8_t padded[16] = {};
  if (data != nullptr && bytes < sizeof(padded)) {  // Never read past the caller's bytes.
    std::memcpy(padded, data, bytes);
    data = padded;
  }
  return createBuffer(buffer, std::max<size_t>(bytes, 16), data, GL_DYNAMIC_STORAGE_BIT, what);
}

}  // namespace si::detail
