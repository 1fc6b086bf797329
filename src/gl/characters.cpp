// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The renderer's characters (Renderer::addCharacter and replaceCharacter): uploading one (its
// palette, buffers, pre-skinning lists, the paths' per-character state, the alpha-masked
// depth programs it needs), its skinning path, measured or set, and what each one holds.
#include <initializer_list>

#include "core/str_cat.h"
#include "gl/paths/skinning_path_choice.h"
#include "gl/renderer_impl.h"
#include "si/core/log.h"
#include "si/gl/renderer.h"

namespace si {
using detail::strCat;

Status Renderer::Impl::uploadCharacter(const char* what, const Character& character,
                                       const BakedPalette& palette, detail::CharacterSlot& c,
                                       const glm::vec3& light) {
  Impl& m = *this;
  const auto named = [what](const Status& s) {
    return s.isOk() ? s : Status(s.code(), strCat(what, ": ", s.message()));
  };
  Status s =
      c.character.upload(character, palette, m.desc.max_texture_size, m.desc.morph_lod_share);
  if (s.isOk())
    s = c.palette.upload(
        palette, m.info,
        {c.character.morph_info, c.character.morph_cuts, c.character.morph_texture});
  if (s.isOk() && !m.info.es) s = c.preskin.build(c.character);
  // Depth-only draws of an alpha-masked character discard by its mask (built once).
  const uint32_t features = c.character.meshFeatures();
  if (s.isOk() && c.character.alpha_masked)
    s = m.programs.buildMaskedDepth(features & detail::kMeshSkinFeatures);
  // A mesh with texture coordinates 1 or colours, or with 8 influences, draws with the
  // variants that carry them.
  if (s.isOk()) s = m.programs.buildMeshVariants(c.material, features);
  if (!s.isOk()) return named(s);
  const detail::DrawResources r = m.resources(c);
  for (detail::DrawPath* p : std::initializer_list<detail::DrawPath*>{
           &m.vertex_path, &c.compute_path, &m.traditional_path, &c.cpu_path})
    if (s.isOk() && (p == &m.vertex_path || !m.info.es)) s = p->prepare(r);
  if (s.isOk()) s = m.check(what);
  c.path = m.desc.skinning_path == SkinningPath::kCompute ? SkinningPath::kCompute
                                                          : SkinningPath::kVertexShader;
  c.path_reason = "explicit setting";
  if (m.info.es) {
    c.path_reason = "the OpenGL ES profile has only the vertex-shader path";
    return named(s);
  }
  if (s.isOk() && m.desc.skinning_path == SkinningPath::kAutomatic) {
    detail::PathChoice choice;
    s = detail::chooseSkinningPath(r, m.vertex_path, c.compute_path, light, &choice);
    if (s.isOk()) {
      c.path = choice.path;
      c.path_reason = choice.reason;
      logMessage(LogLevel::kInfo, strCat("si::Renderer: skinning path ", skinningPathName(c.path),
                                         " (", c.path_reason, ")"));
      s = m.check("measuring the skinning paths");
    }
  }
  return named(s);
}

Status Renderer::addCharacter(const Character& character, const BakedPalette& palette,
                              CharacterId* id) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  if (id == nullptr) return {StatusCode::kInvalidArgument, "addCharacter: id is null"};
  Impl& m = *impl_;
  const auto guard = m.enter("addCharacter", detail::uploadFootprint());
  // The new character's ring regions exist before its path choice draws.
  m.characters.push_back(std::make_unique<detail::CharacterSlot>());
  m.sizeRing();
  const Status s =
      m.uploadCharacter("addCharacter", character, palette, *m.characters.back(), light_direction_);
  if (!s.isOk()) {
    m.characters.back()->release();
    m.characters.pop_back();
    m.sizeRing();
    return s;
  }
  id->index = uint32_t(m.characters.size() - 1);
  return Status::ok();
}

Status Renderer::replaceCharacter(CharacterId id, const Character& character,
                                  const BakedPalette& palette) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  detail::CharacterSlot* replaced = nullptr;
  const Status found = m.find(id, "replaceCharacter", &replaced);
  if (!found.isOk()) return found;
  const auto guard = m.enter("replaceCharacter", detail::uploadFootprint());
  auto slot = std::make_unique<detail::CharacterSlot>();
  const Status s =
      m.uploadCharacter("replaceCharacter", character, palette, *slot, light_direction_);
  if (!s.isOk()) {
    slot->release();
    return s;
  }
  slot->material = replaced->material;
  replaced->release();
  m.characters[id.index] = std::move(slot);
  return Status::ok();
}

uint32_t Renderer::characterCount() const {
  if (!impl_) return 0;
  uint32_t n = 0;
  for (const auto& c : impl_->characters) n += c->ready() ? 1 : 0;
  return n;
}

// Before a character's upload: the explicit setting, or the vertex shader until measured.
SkinningPath Renderer::skinningPath(CharacterId id) const {
  if (!impl_) return SkinningPath::kVertexShader;
  if (id.index < impl_->characters.size() && impl_->characters[id.index]->character.ready())
    return impl_->characters[id.index]->path;
  return impl_->desc.skinning_path == SkinningPath::kCompute ? SkinningPath::kCompute
                                                             : SkinningPath::kVertexShader;
}

const std::string& Renderer::skinningPathReason(CharacterId id) const {
  static const std::string none = "no renderer (init() first)";
  static const std::string explicit_setting = "explicit setting";
  static const std::string not_yet = "not measured yet (uploading the character measures)";
  if (!impl_) return none;
  if (id.index < impl_->characters.size() && impl_->characters[id.index]->character.ready())
    return impl_->characters[id.index]->path_reason;
  return impl_->desc.skinning_path == SkinningPath::kAutomatic ? not_yet : explicit_setting;
}

uint32_t Renderer::triangleCount(CharacterId id, uint32_t sub_mesh, uint32_t lod) const {
  if (!impl_ || id.index >= impl_->characters.size()) return 0;
  const detail::CharacterBuffers& c = impl_->characters[id.index]->character;
  if (sub_mesh >= c.sub_meshes.size()) return 0;
  return c.lodRange(sub_mesh, lod).index_count / 3;
}

}  // namespace si
