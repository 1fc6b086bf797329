// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/churn_table.h"
#include "crowd_bench/bench_character.h"

#include <algorithm>
#include <memory>
#include <random>

#include "common/cascades.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/crowd_view.h"

namespace si::bench {

namespace {

constexpr uint32_t kViews = 4;  // The main view and 3 cascades.

struct Side {
  double churn_ms = 0, submit_ms = 0, gpu_ms = 0, mib = 0;
};

// `count` on the field; each frame `share` x count removed (random) and as many added at the
// freed places, then the clock and the 4 views' draws.
Status runChurn(Setup& setup, Renderer& renderer, const BakedPalette& palette, uint32_t count,
                double share, Side* out) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
  Status s = makeCrowd(setup, palette, places, LodChoice(), &crowd, &handles);
  std::vector<std::unique_ptr<CrowdView>> views;
  CrowdViewDesc shadow;
  shadow.lod_bias = 1;
  shadow.max_distance_radii = -1.0f;
  for (uint32_t k = 0; k < kViews && s.isOk(); ++k) {
    views.push_back(std::make_unique<CrowdView>());
    s = k == 0 ? views.back()->init(crowd) : views.back()->init(crowd, shadow);
  }
  if (!s.isOk()) return s;
  std::mt19937 random(7);
  const uint32_t churned = uint32_t(double(count) * share);
  std::vector<double> churn, submit, gpu, mib;
  const uint32_t warmup = 2, n = setup.frames;
  for (uint32_t f = 0; f < warmup + n && s.isOk(); ++f) {
    const Camera cam = cameraAt(setup, "field", places, f < warmup ? 0 : f - warmup, n);
    const auto t0 = Clock::now();
    for (uint32_t k = 0; k < churned && s.isOk(); ++k) {  // Despawn one, spawn one in its place.
      const size_t i = random() % handles.size();
      InstanceDesc d;
      s = crowd.get(handles[i], &d);
      if (s.isOk()) s = crowd.remove(handles[i]);
      if (s.isOk()) s = crowd.add(d, &handles[i]);
    }
    const double churn_ms = msSince(t0);
    if (s.isOk()) s = crowd.advance(1.0 / 60.0);
    const std::vector<Camera> lights =
        si::examples::cascadeCameras(cam, kViews - 1, glm::vec3(-0.4f, -1.0f, -0.3f),
                                     float(setup.height), 5.0, 400.0, -2.0, 6.0);
    double frame_submit = 0, frame_gpu = 0, frame_mib = 0;
    for (uint32_t k = 0; k < kViews && s.isOk(); ++k) {
      renderer.clear(kClearColor);
      DrawStats st;
      s = renderer.drawCrowdGpuCulled(CharacterId{}, *views[k], k == 0 ? cam : lights[k - 1], &st,
                                      k == 0 ? DrawMode::kDefault : DrawMode::kDepthOnly);
      frame_submit += st.cpu_submit_ms;
      frame_gpu = st.gpu_ms >= 0.0 && frame_gpu >= 0.0 ? frame_gpu + st.gpu_ms : -1.0;
      frame_mib += double(st.state_bytes_uploaded + st.view_seed_bytes) / (1024.0 * 1024.0);
    }
    if (f < warmup) continue;
    churn.push_back(churn_ms);
    submit.push_back(frame_submit);
    gpu.push_back(frame_gpu);
    mib.push_back(frame_mib);
  }
  *out = Side{median(churn), median(submit), median(gpu), median(mib)};
  return s;
}

}  // namespace

Status churnTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                  const std::vector<uint32_t>& sizes, const std::vector<double>& shares,
                  std::FILE* csv) {
  Renderer renderer;
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kCompute;
  Status s = initRenderer(setup, palette, rd, &renderer);
  if (!s.isOk()) return {s.code(), "churn: " + s.message()};
  std::printf(
      "\nChurn (field, gpu-driven, pre-skinned, %u views: the main one and %u cascades "
      "depth-only): a share removed and as many added each frame, against none; "
      "medians; MiB up: the state and the views' seeds staged\n",
      kViews, kViews - 1);
  std::printf("%9s %7s %9s %10s %12s %10s %9s\n", "instances", "share", "churn ms", "submit ms",
              "CPU ms (all)", "MiB up", "GPU ms");
  for (uint32_t count : sizes)
    for (double share : shares) {
      Side side;
      s = runChurn(setup, renderer, palette, count, share, &side);
      if (!s.isOk()) return {s.code(), "churn: " + s.message()};
      std::printf("%9u %7.4g %9.3f %10.3f %12.3f %10.2f %9.3f\n", count, share, side.churn_ms,
                  side.submit_ms, side.churn_ms + side.submit_ms, side.mib, side.gpu_ms);
      std::fprintf(csv, "churn,field,gpu-driven,%u,,,,%.4f,%.4f,%.4f,,%g,%.4f,,%u views,,,\n",
                   count, side.churn_ms, side.submit_ms, side.gpu_ms, share, side.mib, kViews);
    }
  renderer.shutdown();
  return Status::ok();
}

}  // namespace si::bench
