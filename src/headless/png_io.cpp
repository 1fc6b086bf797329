// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// PNG reading and writing through Debian's libstb (stb_image, stb_image_write).
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cstring>

#include "core/str_cat.h"
#include "si/headless/headless_context.h"

namespace si {
using detail::strCat;

Status writePng(const std::string& path, uint32_t width, uint32_t height,
                Span<const uint8_t> rgba) {
  if (width == 0 || height == 0 || rgba.size() != size_t(width) * height * 4)
    return {StatusCode::kCountMismatch,
            strCat("writePng: ", rgba.size(), " bytes for a ", width, "x", height, " RGBA8 image")};
  if (!stbi_write_png(path.c_str(), int(width), int(height), 4, rgba.data(), int(width * 4)))
    return {StatusCode::kIo, strCat("writePng: cannot write '", path, "'")};
  return Status::ok();
}

Status readPng(const std::string& path, uint32_t* width, uint32_t* height,
               std::vector<uint8_t>* rgba) {
  if (width == nullptr || height == nullptr || rgba == nullptr)
    return {StatusCode::kInvalidArgument, "readPng: outputs must not be null"};
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (data == nullptr)
    return {StatusCode::kIo, strCat("readPng: cannot read '", path, "': ", stbi_failure_reason())};
  rgba->assign(data, data + size_t(w) * size_t(h) * 4);
  stbi_image_free(data);
  *width = uint32_t(w);
  *height = uint32_t(h);
  return Status::ok();
}

}  // namespace si
