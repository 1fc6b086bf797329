// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Pieces the examples' mixed scenes share (crowd_demo --mix, crowd_bench --mix): a glTF kind
// imported and baked, a crowd of it scaled onto given places, and summing draw statistics.

#include <algorithm>
#include <string>
#include <vector>

#include "si/bake/animation_baker.h"
#include "si/bake/lod_chain.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/renderer.h"
#include "si/gltf/gltf_import.h"

namespace si::examples {

/// Imports the glTF character `file`, gives it an LOD chain (si::buildLodChain) when
/// `lod_chain`, and bakes it with `bake`. Errors name the file.
inline Status importAndBake(const std::string& file, const BakeDesc& bake, bool lod_chain,
                            Character* character, BakedPalette* palette, BakeReport* report) {
  Status s = importGltfFile(file, {}, character, nullptr);
  if (s.isOk() && lod_chain) s = buildLodChain(&character->mesh, {}, nullptr);
  if (s.isOk()) s = bakePalette(*character, bake, palette, report);
  return s.isOk() ? s : Status(s.code(), "--mix " + file + ": " + s.message());
}

/// Inits `crowd` for `character` (its palette, sub-mesh and LOD counts; `desc`'s other fields
/// as given) with one random instance at each of `places` (`random`'s positions are replaced;
/// its seed, masks and the rest apply), feet on the ground and the largest extent of its bind
/// pose scaled to `size` units.
inline Status makeScaledCrowd(const Character& character, const BakedPalette& palette,
                              CrowdDesc desc, const std::vector<glm::dvec3>& places, double size,
                              RandomCrowdDesc random, CrowdManager* crowd) {
  desc.palette = &palette;
  desc.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  desc.lod_count = uint32_t(character.mesh.maxLodCount());
  Status s = crowd->init(desc);
  if (!s.isOk()) return s;
  const Aabb box = character.bindPoseBounds();
  const glm::vec3 extent = box.max - box.min;
  const float scale = float(size) / std::max({extent.x, extent.y, extent.z, 1e-6f});
  std::vector<glm::dvec3> at;
  for (const glm::dvec3& p : places)
    at.push_back(p - glm::dvec3(0.0, double(box.min.y) * scale, 0.0));
  random.positions = at;
  std::vector<InstanceHandle> handles;
  s = crowd->addRandom(random, &handles);
  for (InstanceHandle h : handles) {
    InstanceDesc d;
    if (s.isOk()) s = crowd->get(h, &d);
    if (s.isOk()) s = crowd->setTransform(h, d.position, d.rotation, d.scale * scale);
  }
  return s;
}

/// Adds `b` to `a`: counts, instances and times (the GPU time only when both measured it, else
/// -1), the largest ring use.
inline void accumulate(const DrawStats& b, DrawStats* a) {
  a->draw_calls += b.draw_calls;
  a->triangles += b.triangles;
  a->instances += b.instances;
  a->cpu_submit_ms += b.cpu_submit_ms;
  a->gpu_ms = a->gpu_ms >= 0.0 && b.gpu_ms >= 0.0 ? a->gpu_ms + b.gpu_ms : -1.0;
  a->compute_dispatches += b.compute_dispatches;
  a->compute_chunks += b.compute_chunks;
  a->skinned_vertices += b.skinned_vertices;
  a->ring_bytes_used = std::max(a->ring_bytes_used, b.ring_bytes_used);
  a->gpu_visible += b.gpu_visible;
  a->vertex_shader_instances += b.vertex_shader_instances;
}

}  // namespace si::examples
