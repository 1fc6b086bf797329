// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Shared by the render tests.

#include <gtest/gtest.h>

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

/// The back-ends every render test runs on.
inline ::testing::internal::ValueArray<HeadlessBackend, HeadlessBackend, HeadlessBackend>
allBackends() {
  return ::testing::Values(HeadlessBackend::kEglSurfaceless, HeadlessBackend::kOsMesa,
                           HeadlessBackend::kEglDevice);
}

/// The back-ends of the OpenGL ES profile's render tests (EGL: OSMesa makes no ES context).
inline ::testing::internal::ValueArray<HeadlessBackend, HeadlessBackend> esBackends() {
  return ::testing::Values(HeadlessBackend::kEglSurfaceless, HeadlessBackend::kEglDevice);
}

/// "egl_surfaceless" for kEglSurfaceless: the back-end's name as a test-name suffix.
inline std::string backendTestName(const ::testing::TestParamInfo<HeadlessBackend>& info) {
  std::string n = headlessBackendName(info.param);
  for (char& c : n)
    if (c == '-') c = '_';
  return n;
}

}  // namespace si::test
