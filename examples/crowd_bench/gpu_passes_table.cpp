// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/gpu_passes_table.h"

#include <string>

#include "si/crowd/gpu_crowd_state.h"

namespace si::bench {

namespace {

// What the GPU-driven path's per-instance passes read and write at least, from its layouts
// (an estimate: caches, atomics and the palette's texels are not counted); 0 where none is
// made. `n` instances, the draw's statistics `st`.
double passBytes(GpuPass pass, uint32_t n, const DrawStats& st) {
  switch (pass) {
    case GpuPass::kUpload:  // Staged, then scattered: read and written once each.
      return 2.0 * double(st.state_bytes_uploaded + st.view_seed_bytes);
    case GpuPass::kCull:  // The state; the view's LOD and flags read and written; visible rows.
      return double(n) * (sizeof(GpuInstanceState) + 2 * 8) + double(st.gpu_visible) * 16;
    case GpuPass::kScatter:  // A visible row read and an 80-byte record written per entry.
      return double(st.instances) * (16 + 80);
    case GpuPass::kSkin:  // A 36-byte vertex read and a 16-byte one written.
      return double(st.skinned_vertices) * (36 + 16);
    default:
      return 0.0;
  }
}

}  // namespace

void PassCollector::add(uint64_t ticket, uint32_t frame) {
  while (!pending_.empty() && readFront(false)) ++read_late_;
  if (ticket != 0) pending_.emplace_back(ticket, frame);
}

bool PassCollector::readFront(bool wait) {
  GpuPassTimes t;
  do {
    if (!renderer_.readGpuPasses(pending_.front().first, &t).isOk()) {  // Reused: dropped.
      pending_.pop_front();
      return false;
    }
  } while (wait && !t.ready);
  if (!t.ready) return false;
  done_.emplace_back(t, pending_.front().second);
  pending_.pop_front();
  return true;
}

void PassCollector::finish(Row* row) {
  while (!pending_.empty()) readFront(true);
  row->passes_read = uint32_t(done_.size());
  row->passes_read_late = read_late_;
  row->pass_ms.clear();
  row->pass_total_ms = 0.0;
  if (done_.empty()) return;
  std::map<uint32_t, GpuPassTimes> frames;  // Each frame's draws summed.
  for (const auto& [t, frame] : done_) {
    GpuPassTimes& sum = frames[frame];
    for (uint32_t p = 0; p < kGpuPassCount; ++p) sum.ms[p] += t.ms[p];
    sum.total_ms += t.total_ms;
  }
  for (uint32_t p = 0; p < kGpuPassCount; ++p) {
    std::vector<double> v;
    for (const auto& frame : frames) v.push_back(frame.second.ms[p]);
    row->pass_ms.push_back(median(v));
  }
  std::vector<double> totals;
  for (const auto& frame : frames) totals.push_back(frame.second.total_ms);
  row->pass_total_ms = median(totals);
}

void printPassTable(const std::vector<Row>& rows, const char* csv_path) {
  std::printf(
      "\nGPU time per pass (ms, medians; RendererDesc::measure_gpu_passes, read a frame "
      "late: 'late' counts the draws whose times were there at the next draw; a frame of several "
      "views sums them). Estimated "
      "bytes each per-instance pass moves, as GB/s at its time, in brackets.\n");
  std::printf("%-8s %-22s %-11s %9s", "scene", "path", "lod", "instances");
  for (uint32_t p = 0; p < kGpuPassCount; ++p) std::printf(" %13s", gpuPassName(GpuPass(p)));
  std::printf(" %9s %9s\n", "total", "late");
  std::FILE* csv = std::fopen(csv_path, "w");
  if (csv != nullptr) {
    std::fprintf(csv, "scene,path,lod,instances,pass,ms,estimated_bytes,total_ms\n");
  }
  for (const Row& r : rows) {
    if (r.pass_ms.size() != kGpuPassCount) continue;
    std::printf("%-8s %-22s %-11s %9u", r.scene.c_str(), r.path.c_str(), r.lod.c_str(),
                r.instances);
    const bool gpu_driven = r.path.compare(0, 4, "gpu-") == 0 && r.pass_bytes;
    for (uint32_t p = 0; p < kGpuPassCount; ++p) {
      const double bytes = gpu_driven ? passBytes(GpuPass(p), r.instances, r.last) : 0.0;
      const double ms = r.pass_ms[p];
      if (bytes > 0.0 && ms > 0.0)
        std::printf(" %6.3f[%5.0f]", ms, bytes / (ms * 1e-3) / 1e9);
      else
        std::printf(" %13.3f", ms);
      if (csv != nullptr)
        std::fprintf(csv, "%s,%s,%s,%u,%s,%.5f,%.0f,%.5f\n", r.scene.c_str(), r.path.c_str(),
                     r.lod.c_str(), r.instances, gpuPassName(GpuPass(p)), ms, bytes,
                     r.pass_total_ms);
    }
    std::printf(" %9.3f %4u/%-4u\n", r.pass_total_ms, r.passes_read_late, r.passes_read);
  }
  if (csv != nullptr) std::fclose(csv);
}

}  // namespace si::bench
