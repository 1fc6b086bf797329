// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Where the tests find the repository's sample glTF assets (assets/, with their licences and
// checksums) and the inputs that once broke the library (tests/regressions/inputs/). Both are
// part of every checkout, so a test that needs one fails, naming the path, when it is missing:
// it never skips.

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#ifndef SI_ASSETS_DIR
#error "SI_ASSETS_DIR must name the repository's assets/ folder (tests/CMakeLists.txt sets it)"
#endif
#ifndef SI_REGRESSIONS_DIR
#error "SI_REGRESSIONS_DIR must name tests/regressions/inputs (tests/CMakeLists.txt sets it)"
#endif

namespace si::test {

/// The sample asset at `relative` (e.g. "Fox/glTF-Binary/Fox.glb") inside assets/.
inline std::string assetPath(const std::string& relative) {
  return std::string(SI_ASSETS_DIR) + "/" + relative;
}

/// The folder of the regression inputs.
inline std::string regressionsDir() { return SI_REGRESSIONS_DIR; }

/// A gtest failure naming the missing file, or success when it can be opened.
inline ::testing::AssertionResult assetExists(const std::string& path) {
  if (std::ifstream(path).good()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "sample asset missing: " << path
         << " (the repository's assets/ folder holds it; see assets/README.md)";
}

}  // namespace si::test
