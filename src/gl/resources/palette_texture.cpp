// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Uploading the palette texture.
#include "gl/resources/palette_texture.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/shader_inputs.h"
#include "si/crowd/crowd_export.h"

namespace si::detail {

namespace {
// A texture `rows` rows tall (at least the palette's) holding `palette`'s texels in its first
// rows, read with texelFetch (nearest filters); `what` names it in errors. Writes the unpack
// alignment.
Status createPaletteTexture(const BakedPalette& palette, uint32_t rows, const char* what,
                            GLuint* out) {
  const PaletteLayout& l = palette.layout;
  const bool half = palette.format == PaletteFormat::kMatrix3x4F16;
  const Status s = createTexture2D(out, 1, half ? GL_RGBA16F : GL_RGBA32F, GLsizei(l.width),
                                   GLsizei(rows), what);
  if (!s.isOk()) return s;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(*out, 0, 0, 0, GLsizei(l.width), GLsizei(l.height), GL_RGBA,
                      half ? GL_HALF_FLOAT : GL_FLOAT, palette.texel_bytes.data());
  glTextureParameteri(*out, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(*out, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return Status::ok();
}
}  // namespace

Status PaletteTexture::upload(const BakedPalette& palette, const GlInfo& info,
                              const PaletteMorphs& morphs) {
  const PaletteLayout& l = palette.layout;
  const Status valid = palette.validate();  // Never draws from an inconsistent palette.
  if (!valid.isOk()) return {StatusCode::kInvalidArgument, "the palette: " + valid.message()};
  if (l.width > info.max_texture_size || l.height > info.max_texture_size)
    return {StatusCode::kLimitExceeded,
            strCat("the palette is ", l.width, "x", l.height,
                   ", GL_MAX_TEXTURE_SIZE is ", info.max_texture_size,
                   " (bake with BakeDesc::max_texture_size)")};
  release();
  Status s = createPaletteTexture(palette, l.height, "the palette texture", &texture_);
  if (!s.isOk()) return s;
  const glm::uvec4 info_value = paletteShaderInfo(palette);
  // SiPaletteInfo: si_palette_info, si_morph_info, si_morph_cuts[2] (std140: 4 x 16 bytes).
  glm::uvec4 block[4] = {info_value, morphs.info, glm::uvec4(0u), glm::uvec4(0u)};
  static_assert(sizeof(morphs.cuts) == 2 * sizeof(glm::uvec4), "two vec4 of cuts");
  std::memcpy(&block[2], morphs.cuts.data(), sizeof(morphs.cuts));
  s = createBuffer(&info_buffer_, sizeof(block), &block[0][0], 0, "the palette's info block");
  if (!s.isOk()) {
    release();
    return s;
  }
  shader_info_ = info_value;
  palette_ = &palette;
  height_ = l.height;
  live_held_.forget();
  live_staging_.configure(16, 256, kLiveRegions);  // Its buffer made by the first live upload.
  morph_texture_ = morphs.texture;
  return Status::ok();
}

Status PaletteTexture::uploadLive(const CrowdExport& live, uint64_t crowd_identity,
                                  const GlInfo& info) {
  const Span<const uint8_t> texels = live.livePoseTexels();
  if (texels.empty() || palette_ == nullptr) return Status::ok();
  const PaletteLayout& l = palette_->layout;
  const bool half = palette_->format == PaletteFormat::kMatrix3x4F16;
  const GLenum type = half ? GL_HALF_FLOAT : GL_FLOAT;
  const size_t bytes = bytesPerTexel(palette_->format);
  const uint64_t count = texels.size() / bytes;
  const uint64_t height = l.height + (count + l.width - 1) / l.width;
  if (height > info.max_texture_size)
    return {StatusCode::kLimitExceeded,
            strCat("the palette with its live poses is ", l.width, "x", height,
                   ", GL_MAX_TEXTURE_SIZE is ", info.max_texture_size,
                   " (fewer CrowdDesc::live_pose_capacity)")};
  if (height > height_) {  // Grown once: the palette's rows copied, the live rows after them.
    GLuint grown = kNoObject;
    const Status s = createPaletteTexture(*palette_, uint32_t(height),
                                          "the palette texture with live poses", &grown);
    if (!s.isOk()) return s;
    glDeleteTextures(1, &texture_);
    texture_ = grown;
    height_ = uint32_t(height);
    live_held_.forget();
  }
  // What changed since the version these rows hold: all of it for another crowd.
  uint32_t first = 0, changed = 0;
  if (!live_held_.update(live, crowd_identity, &first, &changed)) return Status::ok();
  // From the staging ring on desktop GL: one copy, the texture written by the GPU. (From
  // memory, 10,000 poses of 21 joints, 10 MB, added 5.1-5.4 ms to the H200's GPU-driven submit;
  // through the ring 2.2-2.6: docs/performance.md.)
  const uint8_t* source = texels.data() + size_t(first) * bytes;
  const size_t span_bytes = size_t(changed) * bytes;
  size_t base = 0;
  if (!esProfile()) {
    Status s = live_staging_.reserve(span_bytes);
    if (s.isOk()) s = live_staging_.acquire(&base);
    if (!s.isOk()) {
      live_held_.forget();  // Nothing written: all of it next time.
      return {s.code(), "the live poses' staging: " + s.message()};
    }
    // On the crowd's workers past 256 KiB (1,000 poses of 60 joints: 2.9 MB).
    live.copyLivePoseTexels(first, changed, live_staging_.mapped(base));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, live_staging_.buffer());
    source = reinterpret_cast<const uint8_t*>(uintptr_t(base));  // An offset in the buffer.
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // The span [first, first + changed) of the rows after the palette's: a part row, whole rows,
  // a part row.
  uint64_t at = first;
  const uint64_t end = uint64_t(first) + changed;
  while (at < end) {
    const uint64_t x = at % l.width, y = l.height + at / l.width;
    const uint64_t rows = x == 0 ? (end - at) / l.width : 0;
    const uint64_t width = rows > 0 ? l.width : std::min<uint64_t>(l.width - x, end - at);
    glTextureSubImage2D(texture_, 0, GLint(x), GLint(y), GLsizei(width),
                        GLsizei(std::max<uint64_t>(rows, 1)), GL_RGBA, type,
                        source + (at - first) * bytes);
    at += width * std::max<uint64_t>(rows, 1);
  }
  if (!esProfile()) {
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    live_staging_.finishFrame();  // Fenced: written again only after the GPU's copy.
  }
  return Status::ok();
}

void PaletteTexture::bind() const {
  glBindTextureUnit(0, texture_);
  glBindBufferBase(GL_UNIFORM_BUFFER, 4, info_buffer_);
  if (morph_texture_ != kNoObject) glBindTextureUnit(5, morph_texture_);
}

void PaletteTexture::release() {
  if (texture_ != kNoObject) glDeleteTextures(1, &texture_);
  if (info_buffer_ != kNoObject) glDeleteBuffers(1, &info_buffer_);
  texture_ = info_buffer_ = morph_texture_ = kNoObject;
  live_staging_.release();
  palette_ = nullptr;
}

uint64_t PaletteTexture::gpuBytes() const {
  return textureBytes(texture_) + bufferBytes(info_buffer_) + live_staging_.bytes();
}

}  // namespace si::detail
