// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Shared by the render tests.

#include <cstdlib>
#include <string>

#include "si/headless/headless_context.h"

namespace si::test {

/// Whether SI_REQUIRE_GL (a comma-separated list of back-end names, set by scripts/test.sh in
/// CI) names `b`: then a missing context is a failure, not a skip.
inline bool requireGl(HeadlessBackend b) {
  const char* v = std::getenv("SI_REQUIRE_GL");
  if (v == nullptr) return false;
  const std::string list = std::string(",") + v + ",";
  return list.find(std::string(",") + headlessBackendName(b) + ",") != std::string::npos;
}

}  // namespace si::test
