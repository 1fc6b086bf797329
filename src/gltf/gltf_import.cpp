// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// glTF 2.0 import: parsing with tinygltf (with the callbacks of gltf_io.cpp), then the skin's
// skeleton, meshes, materials and clips (one file each, gltf_convert.h), validated as a whole.
#include "si/gltf/gltf_import.h"

#include <algorithm>

#include "gltf/gltf_convert.h"
#include "si/bake/lod_chain.h"
#include "si/core/lod_error.h"
#include "si/core/tangents.h"

namespace si {
using detail::corrupt;
using detail::strCat;

namespace {

// Normal maps need the mesh's tangents: generated where the file has none (every vertex has
// texture coordinates: convertMeshes gives a primitive without TEXCOORD_0 zeros, whose
// vertices are then counted as without a UV gradient).
Status tangentsForNormalMaps(GltfImportReport* report, Character* c) {
  const bool normal_maps = std::any_of(c->materials.begin(), c->materials.end(),
                                       [](const Material& m) { return m.normal_image >= 0; });
  if (!normal_maps || !c->mesh.tangents.empty()) return Status::ok();
  TangentReport tr;
  const Status s = generateTangents(&c->mesh, &tr);
  if (!s.isOk()) return corrupt(s.message());
  report->generated_tangents = uint32_t(tr.vertices);
  report->degenerate_tangents = uint32_t(tr.degenerate);
  report->warnings.push_back(strCat("no TANGENT for the normal maps: generated for ", tr.vertices,
                                    " vertices (", tr.degenerate, " without a UV gradient)"));
  return Status::ok();
}

Status convert(const tinygltf::Model& m, const GltfImportDesc& desc, Character* out,
               GltfImportReport* report) {
  if (!(desc.fold_tolerance_height >= 0.0f))
    return {StatusCode::kInvalidArgument,
            "GltfImportDesc::fold_tolerance_height must be >= 0 (infinity: always fold)"};
  Character c;
  detail::SkinBinding skin;
  Status s = detail::convertSkeleton(m, desc, report, &c, &skin);
  std::vector<detail::ImportedPrimitive> primitives;
  std::vector<detail::WideVertex> wide;
  std::vector<detail::NodeMorphTargets> node_targets;
  if (s.isOk())
    s = detail::convertMeshes(m, skin, desc.keep_morph_targets, report, &c, &primitives, &wide,
                              &node_targets);
  if (s.isOk()) s = detail::groupVariations(primitives, desc, report, &c);
  if (!s.isOk()) return s;
  detail::convertMaterials(m, report, &c);
  report->materials = uint32_t(c.materials.size());
  report->images = uint32_t(c.images.size());
  s = tangentsForNormalMaps(report, &c);
  if (!s.isOk()) return s;
  s = detail::convertClips(m, desc, skin, node_targets, report, &c);
  if (!s.isOk()) return s;
  if (c.clips.empty() && desc.rest_pose_clip_when_none) {
    c.clips.push_back(makeRestPoseClip(c.skeleton.jointCount()));
    report->added_rest_pose_clip = true;
    report->warnings.push_back(
        "no animation for the skeleton: added clip 'rest_pose' (its rest pose, one frame)");
  }
  WeightNormalizationReport wr;
  s = normalizeWeights(c.mesh, &wr);
  if (!s.isOk()) return corrupt(s.message());
  s = detail::measureInfluenceFold(c, wide, report);
  if (!s.isOk()) return s;
  detail::keepWideInfluences(wide, desc.fold_tolerance_height, report, &c);
  // LODs: generated when asked for and the file has none, then every level's error measured.
  const bool has_lods = std::any_of(c.mesh.sub_meshes.begin(), c.mesh.sub_meshes.end(),
                                    [](const SubMesh& sm) { return sm.lods.size() > 1; });
  if (!has_lods && desc.generate_lods > 0) {
    LodChainDesc chain;
    chain.level_count = std::min<uint32_t>(desc.generate_lods + 1, 8);
    chain.triangle_ratio = desc.lod_index_ratio > 0.0f ? desc.lod_index_ratio : 0.25f;
    LodChainReport chain_report;
    s = buildLodChain(&c.mesh, chain, &chain_report);
    if (!s.isOk()) return s;
    for (const LodLevelReport& l : chain_report.levels) report->generated_lods += l.generated;
  }
  s = measureLodErrors(&c.mesh, false);
  if (!s.isOk()) return s;
  c.name = m.scenes.empty() || m.defaultScene < 0 || size_t(m.defaultScene) >= m.scenes.size()
               ? "gltf" : m.scenes[size_t(m.defaultScene)].name;
  s = c.validate();
  if (!s.isOk()) return s;
  *out = std::move(c);
  return Status::ok();
}

Status importImpl(Span<const uint8_t> bytes, const std::string& base_dir, const GltfImportDesc& desc,
                  Character* out, GltfImportReport* report) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "importGltf: out is null"};
  return detail::parseAndConvert(bytes, base_dir, desc.load_images, report,
                                 [&](const tinygltf::Model& model, GltfImportReport* r) {
                                   return convert(model, desc, out, r);
                                 });
}


}  // namespace

Status importGltfMemory(Span<const uint8_t> bytes, const std::string& base_dir,
                        const GltfImportDesc& desc, Character* out, GltfImportReport* report) {
  return importImpl(bytes, base_dir, desc, out, report);
}

Status importGltfFile(const std::string& path, const GltfImportDesc& desc, Character* out,
                      GltfImportReport* report) {
  detail::GltfFile file;
  const Status s = detail::readGltfFile(path, &file);
  return s.isOk() ? importImpl(file.bytes, file.dir, desc, out, report) : s;
}

}  // namespace si
