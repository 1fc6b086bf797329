// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Safe resolution of the URIs a glTF file names (buffers, images): no path expansion, no escape
/// from the asset's folder (tinygltf's own callback expanded paths with wordexp: CVE-2022-3008).

#include <string>

#include "si/core/status.h"

namespace si {

/// Resolves `uri` (relative, as found in a glTF file) against `asset_dir`, the folder of the
/// .gltf file, writing the path to open to `out_path`. Percent-escapes (%20) are decoded. Fails,
/// leaving `out_path` untouched, with kInvalidArgument naming the URI when it is empty, absolute
/// (leading '/', '\\' or a drive letter), has a scheme other than a data URI (http:, file:),
/// contains a NUL, a backslash, a malformed percent-escape, or a `..` segment that would climb
/// above `asset_dir`; data: URIs are not paths and also fail here (decode them instead).
Status resolveAssetUri(const std::string& asset_dir, const std::string& uri,
                       std::string* out_path);

}  // namespace si
