// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// deferred_host's own GL programs (the host's part of the frame): compiling and linking.

#include <cstdint>

#include "si/core/status.h"

namespace deferred {

/// Compiles `vertex` and `fragment` and links them into `*program`; kBackend with the driver's
/// log naming `name` when either fails.
si::Status linkProgram(const char* name, const char* vertex, const char* fragment,
                       uint32_t* program);

}  // namespace deferred
