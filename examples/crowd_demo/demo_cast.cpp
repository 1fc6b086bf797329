// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "demo_cast.h"

#include <algorithm>
#include <cstdio>

#include "si/bake/animation_baker.h"
#include "si/gltf/gltf_import.h"

namespace demo {

si::Status DemoCast::load(const std::vector<std::string>& files, float rate_hz) {
  kinds_.clear();
  for (const std::string& file : files) {
    auto k = std::make_unique<Kind>();
    si::Status s = si::importGltfFile(file, {}, &k->character, nullptr);
    si::BakeDesc bake;
    if (rate_hz > 0.0f) {
      bake.rate_mode = si::RateMode::kFixed;
      bake.sample_rate_hz = rate_hz;
    }
    si::BakeReport report;
    if (s.isOk()) s = si::bakePalette(k->character, bake, &k->palette, &report);
    if (!s.isOk()) return {s.code(), "--mix " + file + ": " + s.message()};
    k->name = k->character.name.empty() ? file : k->character.name;
    std::printf("Mixed in '%s': %zu joints, %zu vertices, %zu clips, palette %.1f KiB, max error "
                "%.2g of the height\n",
                k->name.c_str(), k->character.skeleton.jointCount(),
                k->character.mesh.vertexCount(), k->palette.clips.size(),
                double(k->palette.texel_bytes.size()) / 1024.0, report.max_error_ratio);
    kinds_.push_back(std::move(k));
  }
  uploaded_ = false;
  return si::Status::ok();
}

si::Status DemoCast::upload(si::Renderer& renderer) {
  if (uploaded_) return si::Status::ok();
  for (auto& k : kinds_) {
    si::Status s = renderer.addCharacter(k->character, k->palette, &k->id);
    if (!s.isOk()) return {s.code(), k->name + ": " + s.message()};
  }
  uploaded_ = true;
  return si::Status::ok();
}

si::Status DemoCast::layout(const std::vector<std::vector<glm::dvec3>>& positions, double size,
                            uint64_t seed) {
  for (size_t i = 0; i < kinds_.size(); ++i) {
    Kind& k = *kinds_[i];
    si::CrowdDesc cd;
    cd.palette = &k.palette;
    cd.sub_mesh_count = uint32_t(k.character.mesh.sub_meshes.size());
    cd.lod_count = uint32_t(k.character.mesh.maxLodCount());
    si::Status s = k.crowd.init(cd);
    if (!s.isOk()) return s;
    // The model's largest extent becomes `size`, its feet on the ground.
    const si::Aabb box = k.character.bindPoseBounds();
    const glm::vec3 extent = box.max - box.min;
    const float scale =
        float(size) / std::max({extent.x, extent.y, extent.z, 1e-6f});
    std::vector<glm::dvec3> at;
    for (const glm::dvec3& p : positions[i])
      at.push_back(p - glm::dvec3(0.0, double(box.min.y) * scale, 0.0));
    si::RandomCrowdDesc rc;
    rc.positions = at;
    rc.seed = seed + i + 1;
    rc.required_mask = cd.sub_mesh_count >= 32 ? 0xFFFFFFFFu : (1u << cd.sub_mesh_count) - 1u;
    std::vector<si::InstanceHandle> handles;
    s = k.crowd.addRandom(rc, &handles);
    for (si::InstanceHandle h : handles) {
      si::InstanceDesc d;
      if (s.isOk()) s = k.crowd.get(h, &d);
      if (s.isOk()) s = k.crowd.setTransform(h, d.position, d.rotation, scale);
    }
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

si::Status DemoCast::update(double dt, const si::Camera& camera) {
  for (auto& k : kinds_) {
    si::Status s = k->crowd.update(dt, camera);
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

si::Status DemoCast::draw(si::Renderer& renderer, const si::InstanceBatcher& batcher,
                          const si::Camera& camera, si::DrawMode mode, bool traditional, bool cpu,
                          si::DrawStats* stats) {
  for (auto& k : kinds_) {
    si::DrawStats st;
    const si::Status s =
        traditional ? renderer.drawTraditional(k->id, k->crowd, camera, &st)
        : cpu       ? renderer.drawCpuSkinned(k->id, k->crowd, camera, &st)
                    : renderer.drawCrowd(k->id, k->crowd, batcher, camera, &st, mode);
    if (!s.isOk()) return {s.code(), k->name + ": " + s.message()};
    accumulate(st, stats);
  }
  return si::Status::ok();
}

uint32_t DemoCast::visible() const {
  uint32_t n = 0;
  for (const auto& k : kinds_) n += k->crowd.stats().visible;
  return n;
}

void accumulate(const si::DrawStats& b, si::DrawStats* a) {
  a->draw_calls += b.draw_calls;
  a->triangles += b.triangles;
  a->instances += b.instances;
  a->cpu_submit_ms += b.cpu_submit_ms;
  a->gpu_ms = a->gpu_ms >= 0.0 && b.gpu_ms >= 0.0 ? a->gpu_ms + b.gpu_ms : -1.0;
  a->compute_dispatches += b.compute_dispatches;
  a->compute_chunks += b.compute_chunks;
  a->skinned_vertices += b.skinned_vertices;
  a->ring_bytes_used = std::max(a->ring_bytes_used, b.ring_bytes_used);
}

}  // namespace demo
