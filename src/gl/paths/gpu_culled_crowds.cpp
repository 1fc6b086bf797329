// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path's state per crowd: found by identity, evicted when idle or past the count.
#include "gl/paths/gpu_culled_crowds.h"

#include <algorithm>

namespace si::detail {

GpuCulledPath* GpuCulledCrowds::find(uint64_t identity) {
  ++draws_;
  // Idle crowds go at any draw (a crowd destroyed frees its buffers at the character's next
  // draws), then the least recently drawn when a new one comes while the count is full.
  const auto idle = [&](const Crowd& c) {
    return c.identity != identity && draws_ - c.last_draw > kIdleDraws;
  };
  for (Crowd& c : crowds_)
    if (idle(c)) c.path->release();
  crowds_.erase(std::remove_if(crowds_.begin(), crowds_.end(), idle), crowds_.end());
  for (Crowd& c : crowds_)
    if (c.identity == identity) {
      c.last_draw = draws_;
      return last_ = c.path.get();
    }
  if (crowds_.size() >= kMaxCrowds) {
    auto oldest =
        std::min_element(crowds_.begin(), crowds_.end(),
                         [](const Crowd& a, const Crowd& b) { return a.last_draw < b.last_draw; });
    oldest->path->release();
    crowds_.erase(oldest);
  }
  crowds_.push_back({identity, draws_, std::make_unique<GpuCulledPath>()});
  return last_ = crowds_.back().path.get();
}

void GpuCulledCrowds::memory(std::vector<CrowdGpuMemory>* out) const {
  out->resize(crowds_.size());
  for (size_t k = 0; k < crowds_.size(); ++k) crowds_[k].path->memory(&(*out)[k]);
}

void GpuCulledCrowds::release() {
  for (Crowd& c : crowds_) c.path->release();
  crowds_.clear();
  last_ = nullptr;
}

}  // namespace si::detail
