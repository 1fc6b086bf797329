// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/restore_state_table.h"
#include "crowd_bench/bench_character.h"

namespace si::bench {

namespace {

// The cost of one call itself: `calls` draws of an empty crowd, alternating restore off and on;
// the median submit of each in microseconds (the save and restore are most of what is left).
Status perCallMicroseconds(Renderer& renderer, const Setup& setup, const BakedPalette& palette,
                           const std::string& path, uint32_t calls, double us[2]) {
  CrowdManager empty;
  Status s = makeCrowd(setup, palette, {}, LodChoice(), &empty);
  const Camera cam = cameraAt(setup, "field", {glm::dvec3(0.0)}, 0, 1);
  if (s.isOk()) s = empty.update(0.0, cam);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  std::vector<double> submit[2];
  for (uint32_t k = 0; k < 2 * calls && s.isOk(); ++k) {
    const int on = int(k % 2);
    renderer.setRestoreState(on == 1);
    DrawStats st;
    s = drawKind(renderer, CharacterId{}, empty, batcher, path, cam, &st);
    submit[on].push_back(st.cpu_submit_ms * 1000.0);
  }
  renderer.setRestoreState(true);
  us[0] = median(submit[0]);
  us[1] = median(submit[1]);
  return s;
}

}  // namespace

Status restoreStateTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                         const std::vector<uint32_t>& sizes,
                         const std::vector<std::string>& paths, std::FILE* csv) {
  // One renderer for every path (each path names its draw mode; kDefault is the vertex shader's).
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer renderer;
  Status init = renderer.init(setup.info, rd);
  CharacterId id;
  if (init.isOk()) init = renderer.addCharacter(setup.character, palette, &id);
  if (init.isOk()) init = addImpostor(setup, renderer, id);
  if (!init.isOk()) return {init.code(), "restore state: " + init.message()};
  std::printf("\nThe GL state contract (RendererDesc::restore_state): one call's own cost, on an "
              "empty crowd, restore off and on alternately, 200 calls each, medians\n");
  std::printf("%-22s %12s %12s %9s\n", "path", "call off us", "call on us", "delta us");
  for (const std::string& path : paths) {
    double us[2] = {0, 0};
    const Status s = perCallMicroseconds(renderer, setup, palette, path, 200, us);
    if (!s.isOk()) return {s.code(), "restore state, " + path + ": " + s.message()};
    std::printf("%-22s %12.1f %12.1f %9.1f\n", path.c_str(), us[0], us[1], us[1] - us[0]);
    std::fprintf(csv, "restore-state-call,empty,%s,0,0,0,,,%.4f,,,,,,off,,,\n", path.c_str(),
                 us[0] / 1000.0);
    std::fprintf(csv, "restore-state-call,empty,%s,0,0,0,,,%.4f,,,,,,on,,,\n", path.c_str(),
                 us[1] / 1000.0);
  }
  std::printf("\nThe GL state contract on the field: each frame drawn with restore off, then on, "
              "by the same renderer; medians over the frames\n");
  std::printf("%-22s %9s %9s %6s %10s %10s %9s %9s %9s %9s %8s\n", "path", "instances",
              "visible", "draws", "submit off", "submit on", "delta us", "of frame", "GPU off",
              "GPU on", "GPU x");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      Row p[2];  // Restore off, then on.
      const Status s = timePaired(setup, renderer, palette, count, path, [&](int on) {
        renderer.setRestoreState(on == 1);
        return Status::ok();
      }, p);
      renderer.setRestoreState(true);
      if (!s.isOk()) return {s.code(), "restore state, " + path + ": " + s.message()};
      const double delta_ms = p[1].submit_ms - p[0].submit_ms;
      // The frame: the CPU's update and submit, or the GPU's time when that is longer.
      const double frame_ms = std::max(p[1].update_ms + p[1].submit_ms, p[1].gpu_ms);
      std::printf("%-22s %9u %9u %6u %10.3f %10.3f %9.1f %8.3f%%", path.c_str(), count,
                  p[1].visible, p[1].draws, p[0].submit_ms, p[1].submit_ms, delta_ms * 1000.0,
                  100.0 * delta_ms / std::max(1e-9, frame_ms));
      if (p[0].gpu_ms >= 0.0)  // Without GPU timing (--no-gpu-time) the GPU columns are empty.
        std::printf(" %9.3f %9.3f %8.3f\n", p[0].gpu_ms, p[1].gpu_ms,
                    p[1].gpu_ms / std::max(1e-9, p[0].gpu_ms));
      else
        std::printf(" %9s %9s %8s\n", "-", "-", "-");
      for (int on = 0; on < 2; ++on)
        std::fprintf(csv, "restore-state,field,%s,%u,%u,%u,,%.4f,%.4f,%.4f,,,,,%s,,,\n",
                     path.c_str(), count, p[on].visible, p[on].draws, p[on].update_ms,
                     p[on].submit_ms, p[on].gpu_ms, on == 1 ? "on" : "off");
    }
  return Status::ok();
}

}  // namespace si::bench
