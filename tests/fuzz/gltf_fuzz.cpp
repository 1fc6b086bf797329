// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// libFuzzer target for the glTF importer (from memory, no folder: external URIs refused):
// any bytes give an error or a character that validates (with its morph targets kept, and
// then without), whose clips give morph weights; and as a prop (importGltfPropMemory)
// an error or a mesh that validates and attaches; never a crash or sanitizer report.
// Run with scripts/fuzz.sh, seeded with assets.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "si/core/impostor_level.h"
#include "si/core/material_table.h"
#include "si/core/part_lod.h"
#include "si/core/reference_evaluator.h"
#include "si/gltf/gltf_import.h"
#include "si/gltf/gltf_prop.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  si::Character c;
  si::GltfImportDesc d;
  d.load_images = false;  // stb_image is fuzzed by its own project; keep the focus here.
  d.keep_morph_targets = true;
  const si::Status s = si::importGltfMemory(si::Span<const uint8_t>(data, size), "", d, &c, nullptr);
  if (s.isOk() && !c.validate().isOk()) std::abort();
  std::vector<double> weights(c.mesh.morph_targets.size());
  for (size_t k = 0; s.isOk() && k < c.clips.size(); ++k)
    if (!si::evaluateMorphWeights(c.mesh, c.clips[k], 0.5 * c.clips[k].duration_seconds, weights)
             .isOk())
      std::abort();
  // Per-part LOD on what imports: a character that still validates, whose error per level
  // lodErrorsByLevel gives, and a second call succeeds on it.
  if (s.isOk() && si::measureLodErrors(&c.mesh, false).isOk()) {
    si::PartLodDesc pd;
    pd.poses.max_poses = 3;
    if (si::buildPartLods(&c, pd, nullptr).isOk()) {
      std::vector<float> errors;
      if (!c.validate().isOk() || !si::lodErrorsByLevel(c.mesh, &errors).isOk()) std::abort();
      if (!si::buildPartLods(&c, pd, nullptr).isOk()) std::abort();
    }
    // An impostor level past the others: one level more, the mesh still valid.
    const size_t levels = c.mesh.maxLodCount();
    if (si::appendImpostorLevel(&c.mesh).isOk() &&
        (c.mesh.maxLodCount() != levels + 1 || !c.validate().isOk()))
      std::abort();
  }
  // Every variation source; each valid result gives a material table with one entry per
  // material and every vertex's material in it.
  d.keep_morph_targets = false;
  d.variations = size % 2 ? si::VariationSource::kEachMesh : si::VariationSource::kConvention;
  if (si::importGltfMemory(si::Span<const uint8_t>(data, size), "", d, &c, nullptr).isOk()) {
    si::MaterialTable t;
    if (!si::buildMaterialTable(c, 64, &t).isOk()) std::abort();
    if (t.vertex_materials.size() != c.mesh.vertexCount()) std::abort();
    for (uint16_t m : t.vertex_materials)
      if (m >= t.materials.size()) std::abort();
  }
  // The same bytes as a prop: an error, or a mesh that validates and attaches to what imported.
  si::PropMesh prop;
  si::GltfPropDesc pd;
  pd.load_images = false;
  if (si::importGltfPropMemory(si::Span<const uint8_t>(data, size), "", pd, &prop, nullptr)
          .isOk()) {
    if (!prop.validate().isOk()) std::abort();
    if (s.isOk() && c.skeleton.jointCount() > 0) {
      si::Socket socket;
      socket.name = "fuzz";
      const size_t parts = c.mesh.sub_meshes.size();
      const si::Status attached = si::attachProp(socket, prop, &c, nullptr);
      if (attached.isOk() && (c.mesh.sub_meshes.size() != parts + 1 || !c.validate().isOk()))
        std::abort();
      if (!attached.isOk() && c.mesh.sub_meshes.size() != parts) std::abort();
    }
  }
  return 0;
}
