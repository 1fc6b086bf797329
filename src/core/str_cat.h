// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Internal: message building for Status and log text.

#include <sstream>
#include <string>

namespace si::detail {

/// Concatenates the streamed form of every argument.
template <typename... Args>
std::string strCat(const Args&... args) {
  std::ostringstream s;
  (s << ... << args);
  return s.str();
}

}  // namespace si::detail
