// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/uploads_table.h"
#include "crowd_bench/bench_character.h"

#include <cmath>

namespace si::bench {

namespace {

struct Side {
  double submit_ms = 0, gpu_ms = 0, mib = 0;
};

// One size and share: the field's crowd, every stride-th instance stepped each frame, drawn by
// both renderers ([0] changed only, [1] whole).
Status runShare(Setup& setup, Renderer* renderers, const BakedPalette& palette, uint32_t count,
                double share, Side out[2], double* move_ms, uint32_t* moved) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
  Status s = makeCrowd(setup, palette, places, LodChoice(), &crowd, &handles);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderers[0].batchLimits());
  const uint32_t stride = share > 0.0 ? uint32_t(std::max(1.0, std::round(1.0 / share))) : 0u;
  std::vector<double> submit[2], gpu[2], bytes[2], moving;
  const uint32_t warmup = 2, n = setup.frames;
  *moved = 0;
  for (uint32_t f = 0; f < warmup + n && s.isOk(); ++f) {
    const Camera cam = cameraAt(setup, "field", places, f < warmup ? 0 : f - warmup, n);
    const auto t0 = Clock::now();
    uint32_t m = 0;
    if (f > 0 && stride > 0)  // The first frame uploads everything on both sides.
      for (uint32_t i = f % stride; i < handles.size() && s.isOk(); i += stride, ++m) {
        InstanceDesc d;
        s = crowd.get(handles[i], &d);
        if (s.isOk())
          s = crowd.setTransform(handles[i], d.position + glm::dvec3(0.01, 0.0, 0.0), d.rotation,
                                 d.scale);
      }
    const double move = msSince(t0);
    if (s.isOk()) s = crowd.advance(1.0 / 60.0);
    for (int side = 0; side < 2 && s.isOk(); ++side) {
      DrawStats st;
      s = drawPath(renderers[side], crowd, batcher, "gpu-driven", cam, &st);
      if (f < warmup) continue;
      submit[side].push_back(st.cpu_submit_ms);
      gpu[side].push_back(st.gpu_ms);
      bytes[side].push_back(double(st.state_bytes_uploaded) / (1024.0 * 1024.0));
    }
    if (f >= warmup) moving.push_back(move), *moved = m;
  }
  for (int side = 0; side < 2; ++side)
    out[side] = Side{median(submit[side]), median(gpu[side]), median(bytes[side])};
  *move_ms = median(moving);
  return s;
}

}  // namespace

Status uploadsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                    const std::vector<uint32_t>& sizes, const std::vector<double>& shares,
                    std::FILE* csv) {
  Renderer renderers[2];
  for (int side = 0; side < 2; ++side) {
    RendererDesc rd = desc;
    rd.skinning_path = SkinningPath::kCompute;  // Pre-skinned, as the automatic choice picks on
                                                // the H100 and llvmpipe; never re-measured.
    rd.gpu_state_upload = side == 0 ? GpuStateUpload::kChanged : GpuStateUpload::kWhole;
    const Status s = initRenderer(setup, palette, rd, &renderers[side]);
    if (!s.isOk()) return {s.code(), "uploads: " + s.message()};
  }
  std::printf("\nState uploads (field, gpu-driven): a share of the crowd moved each frame by "
              "setTransform (every 1/share-th instance); changed only (the default) against "
              "whole, each frame drawn by both; medians\n");
  std::printf("%9s %7s %8s %9s %12s %12s %8s %10s %10s %9s %9s\n", "instances", "share",
              "moved", "move ms", "submit chg", "submit whole", "CPU x", "MiB chg", "MiB whole",
              "GPU chg", "GPU whole");
  for (uint32_t count : sizes)
    for (double share : shares) {
      Side side[2];
      double move_ms = 0;
      uint32_t moved = 0;
      const Status s = runShare(setup, renderers, palette, count, share, side, &move_ms, &moved);
      if (!s.isOk()) return {s.code(), "uploads: " + s.message()};
      std::printf("%9u %7.4g %8u %9.3f %12.3f %12.3f %8.3f %10.2f %10.2f", count, share, moved,
                  move_ms, side[0].submit_ms, side[1].submit_ms,
                  side[0].submit_ms / std::max(1e-9, side[1].submit_ms), side[0].mib,
                  side[1].mib);
      if (side[0].gpu_ms >= 0.0)
        std::printf(" %9.3f %9.3f\n", side[0].gpu_ms, side[1].gpu_ms);
      else
        std::printf(" %9s %9s\n", "-", "-");
      for (int k = 0; k < 2; ++k)
        std::fprintf(csv, "uploads,field,gpu-driven,%u,%u,,,%.4f,%.4f,%.4f,,%g,%.4f,,%s,,,\n",
                     count, moved, move_ms, side[k].submit_ms, side[k].gpu_ms, share,
                     side[k].mib, k == 0 ? "changed" : "whole");
    }
  return Status::ok();
}

}  // namespace si::bench
