// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/character.h"

#include <algorithm>
#include <cmath>

#include "core/str_cat.h"
#include "si/core/transform.h"

namespace si {
using detail::strCat;

Status Image::validate() const {
  if (width == 0 || height == 0 || width > 16384 || height > 16384)
    return {StatusCode::kOutOfRange,
            strCat("image: size ", width, "x", height, " must be within 1..16384")};
  if (rgba8.size() != size_t(width) * height * 4)
    return {StatusCode::kCountMismatch, strCat("image: rgba8 holds ", rgba8.size(),
                                               " bytes, ", width, "x", height, " RGBA8 needs ",
                                               size_t(width) * height * 4)};
  return Status::ok();
}

namespace {

Status validateMaterial(const Material& m, size_t image_count, bool has_tangents) {
  for (const int32_t img : materialImages(m))
    if (img < -1 || img >= static_cast<int32_t>(image_count))
      return {StatusCode::kOutOfRange, strCat("uses image ", img, " of ", image_count)};
  const auto in01 = [](float v) { return std::isfinite(v) && v >= 0.0f && v <= 1.0f; };
  if (!isFinite(m.base_color_factor) || !isFinite(m.emissive_factor) ||
      !std::isfinite(m.normal_scale) || !std::isfinite(m.alpha_cutoff))
    return {StatusCode::kNotFinite, "has a factor that is not finite"};
  if (!in01(m.metallic_factor) || !in01(m.roughness_factor) || !in01(m.occlusion_strength))
    return {StatusCode::kOutOfRange, strCat("has metallic ", m.metallic_factor, ", roughness ",
                                            m.roughness_factor, ", occlusion strength ",
                                            m.occlusion_strength, ": each must be in [0, 1]")};
  if (m.emissive_factor.x < 0.0f || m.emissive_factor.y < 0.0f || m.emissive_factor.z < 0.0f ||
      m.alpha_cutoff < 0.0f)
    return {StatusCode::kOutOfRange, "has a negative emissive factor or alpha cutoff"};
  if (m.alpha_mode > AlphaMode::kBlend)
    return {StatusCode::kOutOfRange, strCat("has alpha mode ", int(m.alpha_mode))};
  if (m.normal_image >= 0 && !has_tangents)
    return {StatusCode::kInvalidArgument,
            "has a normal map but the mesh has no tangents (si::generateTangents makes them)"};
  return Status::ok();
}

}  // namespace

std::array<int32_t, 5> materialImages(const Material& m) {
  return {m.base_color_image, m.metallic_roughness_image, m.normal_image, m.occlusion_image,
          m.emissive_image};
}

Status Character::validate() const {
  Status s = skeleton.validate();
  if (!s.isOk()) return s;
  s = mesh.validate(skeleton.jointCount());
  if (!s.isOk()) return s;
  for (const Clip& c : clips) {
    s = c.validate(skeleton.jointCount(), mesh.morph_targets.size());
    uint32_t root_joint = 0;
    if (s.isOk() && c.root_motion.extract) s = rootMotionJoint(skeleton, c, &root_joint);
    if (!s.isOk()) return s;
  }
  for (size_t i = 0; i < images.size(); ++i) {
    s = images[i].validate();
    if (!s.isOk()) return {s.code(), strCat("character: image ", i, ": ", s.message())};
  }
  for (size_t m = 0; m < materials.size(); ++m) {
    s = validateMaterial(materials[m], images.size(), !mesh.tangents.empty());
    if (!s.isOk())
      return {s.code(), strCat("character: material ", m, " '", materials[m].name, "' ", s.message())};
  }
  for (size_t i = 0; i < mesh.sub_meshes.size(); ++i)
    if (!materials.empty() && mesh.sub_meshes[i].material >= materials.size())
      return {StatusCode::kOutOfRange,
              strCat("character: sub-mesh ", i, " '", mesh.sub_meshes[i].name, "' uses material ",
                     mesh.sub_meshes[i].material, " of ", materials.size())};
  const size_t material_count = std::max<size_t>(materials.size(), 1);  // None: one default.
  for (size_t v = 0; v < mesh.vertex_materials.size(); ++v)
    if (mesh.vertex_materials[v] >= material_count)
      return {StatusCode::kOutOfRange, strCat("character: vertex ", v, " uses material ",
                                              mesh.vertex_materials[v], " of ", materials.size())};
  return Status::ok();
}

int32_t Character::findClip(const std::string& clip_name) const {
  for (size_t i = 0; i < clips.size(); ++i)
    if (clips[i].name == clip_name) return static_cast<int32_t>(i);
  return -1;
}

Aabb Character::bindPoseBounds() const { return computeBounds(mesh.positions); }

float Character::height() const {
  const glm::vec3 e = bindPoseBounds().extent();
  return std::max({e.x, e.y, e.z});
}

}  // namespace si
