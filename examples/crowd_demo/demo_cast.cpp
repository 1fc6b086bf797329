// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "demo_cast.h"

#include <algorithm>
#include <cstdio>

#include "common/character_kinds.h"

namespace demo {

si::Status DemoCast::load(const std::vector<std::string>& files, float rate_hz) {
  kinds_.clear();
  si::BakeDesc bake;
  if (rate_hz > 0.0f) {
    bake.rate_mode = si::RateMode::kFixed;
    bake.sample_rate_hz = rate_hz;
  }
  for (const std::string& file : files) {
    auto k = std::make_unique<Kind>();
    si::BakeReport report;
    si::Status s = si::examples::importAndBake(file, bake, false, &k->character, &k->palette,
                                               &report);
    if (!s.isOk()) return s;
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
    si::RandomCrowdDesc rc;
    rc.seed = seed + i + 1;
    const size_t parts = k.character.mesh.sub_meshes.size();
    rc.required_mask = parts >= 32 ? 0xFFFFFFFFu : (1u << parts) - 1u;  // Every sub-mesh.
    si::Status s = si::examples::makeScaledCrowd(k.character, k.palette, {}, positions[i], size,
                                                 rc, &k.crowd);
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
        traditional ? renderer.drawTraditional(k->id, k->crowd.view(), camera, &st)
        : cpu       ? renderer.drawCpuSkinned(k->id, k->crowd.view(), camera, &st)
                    : renderer.drawCrowd(k->id, k->crowd.view(), batcher, camera, &st, mode);
    if (!s.isOk()) return {s.code(), k->name + ": " + s.message()};
    si::examples::accumulate(st, stats);
  }
  return si::Status::ok();
}

uint32_t DemoCast::visible() const {
  uint32_t n = 0;
  for (const auto& k : kinds_) n += k->crowd.view().stats().visible;
  return n;
}

}  // namespace demo
