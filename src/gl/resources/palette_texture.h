// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The palette on the GPU: one RGBA32F (or RGBA16F) texture read with texelFetch, and the
// include's si_palette_info, si_morph_info and si_morph_cuts values in a 64-byte uniform buffer
// (block SiPaletteInfo; the last three members only with SI_MORPH_TARGETS).

#include <glad/gl.h>

#include <array>

#include <glm/glm.hpp>

#include "gl/programs/program_set.h"
#include "gl/resources/live_texels_held.h"
#include "gl/resources/record_ring.h"
#include "si/core/baked_palette.h"
#include "si/core/shader_inputs.h"
#include "si/core/span.h"
#include "si/crowd/crowd_export.h"
#include "si/gl/gl_context.h"

namespace si::detail {

/// What the skinning reads beside the palette for a mesh with morph targets.
struct PaletteMorphs {
  glm::uvec4 info{0u};                      ///< si::morphShaderInfo() (0 without targets).
  std::array<float, kMorphLodCuts> cuts{};  ///< si::morphLodCuts().
  GLuint texture = kNoObject;  ///< The morph stream's texture (borrowed; kNoObject without).
};

class PaletteTexture {
 public:
  /// Uploads `palette` (borrowed: it must outlive the upload's use) with what the skinning
  /// reads beside it for a mesh with morph targets (`morphs`). kInvalidArgument for a palette
  /// that fails BakedPalette::validate(); kLimitExceeded past GL_MAX_TEXTURE_SIZE.
  Status upload(const BakedPalette& palette, const GlInfo& info,
                const PaletteMorphs& morphs = PaletteMorphs());
  void release();
  /// Places a crowd's live poses (CrowdExport::livePoseTexels, in the palette's format) after
  /// the palette's texels: the texture grows by the rows they need, once (kLimitExceeded past
  /// GL_MAX_TEXTURE_SIZE); all of them are uploaded for another crowd than last time (its
  /// identity), for the same crowd those written since the version uploaded
  /// (livePoseTexelsChangedSince). Nothing for none. On desktop GL the texels go through a
  /// fenced, persistently mapped staging ring of kLiveRegions regions (one copy on the CPU, on
  /// the crowd's workers past 256 KiB: CrowdExport::copyLivePoseTexels; the
  /// texture written by the GPU from it; kBackend when it cannot be mapped or its region is not
  /// free in time), on the ES profile from memory. Writes the unpack state (its buffer left 0).
  Status uploadLive(const CrowdExport& live, uint64_t crowd_identity, const GlInfo& info);

  /// Staging regions of the live uploads: an upload waits for the GPU's copy of the one
  /// kLiveRegions uploads back.
  static constexpr uint32_t kLiveRegions = 3;

  GLuint texture() const { return texture_; }
  const glm::uvec4& shaderInfo() const { return shader_info_; }
  /// The uniform buffer holding shaderInfo(), for block SiPaletteInfo.
  GLuint infoBuffer() const { return info_buffer_; }
  /// Binds the texture at unit 0, the info block at uniform binding 4 and the morph texture,
  /// when there is one, at unit 5 (the include's SI_PALETTE_BINDING, SI_PALETTE_INFO_BINDING
  /// and SI_MORPH_BINDING defaults, which the library's programs use).
  void bind() const;
  const BakedPalette* palette() const { return palette_; }
  bool ready() const { return texture_ != kNoObject; }
  uint64_t gpuBytes() const;  ///< The texture's, the info block's and the live staging's.

 private:
  GLuint texture_ = kNoObject, info_buffer_ = kNoObject;
  GLuint morph_texture_ = kNoObject;  // Borrowed (CharacterBuffers').
  glm::uvec4 shader_info_{0};
  const BakedPalette* palette_ = nullptr;
  uint32_t height_ = 0;  // The texture's rows: the palette's and the live poses'.
  LiveTexelsHeld live_held_;  // What the live rows hold.
  RecordRing live_staging_;   // The live uploads' staging (desktop GL).
};

}  // namespace si::detail
