// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/gltf/asset_path.h"

#include <cctype>
#include <vector>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {
int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

Status resolveAssetUri(const std::string& asset_dir, const std::string& uri,
                       std::string* out_path) {
  if (out_path == nullptr) return {StatusCode::kInvalidArgument, "resolveAssetUri: out is null"};
  const auto fail = [&](const char* why) {
    return Status(StatusCode::kInvalidArgument, strCat("glTF URI '", uri, "': ", why));
  };
  if (uri.empty()) return fail("is empty");
  // Scheme: letters, digits, + - . followed by ':' before any '/'.
  const size_t colon = uri.find(':');
  if (colon != std::string::npos && uri.find('/') > colon) {
    if (colon == 1 && std::isalpha(static_cast<unsigned char>(uri[0])))
      return fail("is an absolute Windows path");
    return fail(uri.compare(0, 5, "data:") == 0 ? "is a data URI, not a file"
                                               : "has a scheme; only relative paths are allowed");
  }
  std::string decoded;
  for (size_t i = 0; i < uri.size(); ++i) {
    char c = uri[i];
    if (c == '%') {
      const int hi = i + 2 < uri.size() ? hexValue(uri[i + 1]) : -1;
      const int lo = i + 2 < uri.size() ? hexValue(uri[i + 2]) : -1;
      if (hi < 0 || lo < 0) return fail("has a malformed percent-escape");
      c = static_cast<char>(hi * 16 + lo);
      i += 2;
    }
    if (c == '\0') return fail("contains a NUL byte");
    if (c == '\\') return fail("contains a backslash");
    decoded.push_back(c);
  }
  if (decoded[0] == '/') return fail("is an absolute path");
  std::vector<std::string> segments;
  size_t start = 0;
  while (start <= decoded.size()) {
    size_t end = decoded.find('/', start);
    if (end == std::string::npos) end = decoded.size();
    const std::string seg = decoded.substr(start, end - start);
    if (seg == "..") {
      if (segments.empty()) return fail("climbs above the asset's folder");
      segments.pop_back();
    } else if (!seg.empty() && seg != ".") {
      segments.push_back(seg);
    }
    start = end + 1;
  }
  if (segments.empty()) return fail("names no file");
  std::string path = asset_dir;
  if (!path.empty() && path.back() != '/') path.push_back('/');
  for (size_t i = 0; i < segments.size(); ++i) path += (i ? "/" : "") + segments[i];
  *out_path = std::move(path);
  return Status::ok();
}

}  // namespace si
