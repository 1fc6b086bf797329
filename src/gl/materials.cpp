// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Materials (si/gl/material.h): a host's GLSL compiled into every path's fragment stage, and
// which material each character draws with.
#include "core/str_cat.h"
#include "gl/renderer_impl.h"
#include "si/gl/material.h"

namespace si {

using detail::strCat;

Status MaterialDesc::validate() const {
  if (name.empty()) return {StatusCode::kInvalidArgument, "MaterialDesc.name is empty"};
  if (source.empty())
    return {StatusCode::kInvalidArgument,
            strCat("MaterialDesc.source of '", name, "' is empty (it must define "
                   "void siMaterial(SiSurface surface))")};
  if (source.find("#version") != std::string::npos)
    return {StatusCode::kInvalidArgument,
            strCat("MaterialDesc.source of '", name,
                   "' has a #version line; the renderer writes it (GLSL 4.50)")};
  return Status::ok();
}

Status Renderer::addMaterial(const MaterialDesc& desc, MaterialId* id) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  if (id == nullptr) return {StatusCode::kInvalidArgument, "addMaterial: id is null"};
  Impl& m = *impl_;
  Status s = m.esRefuses("addMaterial",
                         "host materials (GLSL ES 3.00 has no binding qualifiers for their "
                         "resources)");
  if (!s.isOk()) return s;
  s = desc.validate();
  if (!s.isOk()) return {s.code(), strCat("addMaterial: ", s.message())};
  if (m.debug) detail::takeHostErrors("addMaterial");
  detail::MaterialSource source;
  source.name = desc.name;
  source.text = desc.source;
  source.depth_discard = desc.depth_discard;
  source.instance_handle = desc.instance_handle;
  uint32_t index = 0;
  s = m.programs.addMaterial(source, &index);
  if (!s.isOk()) return {s.code(), strCat("addMaterial: ", s.message())};
  s = m.check("addMaterial");
  if (!s.isOk()) return s;
  id->index = index;
  return Status::ok();
}

Status Renderer::setMaterial(CharacterId character, MaterialId material) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  detail::CharacterSlot* c = nullptr;
  const Status found = m.find(character, "setMaterial", &c);
  if (!found.isOk()) return found;
  if (material.index >= m.programs.materialCount())
    return {StatusCode::kInvalidArgument,
            strCat("setMaterial: no material ", material.index, " (", m.programs.materialCount(),
                   " with the built-in one; addMaterial gives the ids)")};
  {  // Its variants of the material's programs for its mesh's features, built once.
    const Status s = m.programs.buildMeshVariants(material.index, c->character.meshFeatures());
    if (!s.isOk()) return {s.code(), strCat("setMaterial: ", s.message())};
  }
  c->material = material.index;
  return Status::ok();
}

MaterialId Renderer::material(CharacterId character) const {
  if (!impl_ || character.index >= impl_->characters.size()) return kBuiltinMaterial;
  return MaterialId{impl_->characters[character.index]->material};
}

}  // namespace si
