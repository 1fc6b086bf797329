// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/live_poses_table.h"

#include <algorithm>

#include "si/crowd/crowd_manager.h"

namespace si::bench {

namespace {

// Poses to cycle through: the stored matrices of the walk's frames (any clip's will do).
constexpr uint32_t kPoses = 16;

// The field of `count` with room for `live` live poses, and what an engine poses: every tenth
// instance, so the posed ones spread over the field as characters would, their poses in one
// array as an engine's animation writes them, in two sets taking turns, so that every frame
// writes poses other than the last frame's.
struct LiveField {
  std::vector<glm::dvec3> places;
  CrowdManager crowd;
  std::vector<InstanceHandle> posed;
  std::vector<glm::mat4> batches[2];
};

Status makeLiveField(const Setup& setup, const BakedPalette& palette,
                     const std::vector<std::vector<glm::mat4>>& poses, uint32_t count,
                     uint32_t live, LiveField* f) {
  f->places = scenePositions("field", count);
  std::vector<InstanceHandle> handles;
  const Status s = makeCrowd(setup, palette, f->places, LodChoice(), &f->crowd, &handles, 0, live);
  if (!s.isOk()) return s;
  f->posed.resize(live);
  for (uint32_t k = 0; k < live; ++k)
    f->posed[k] = handles[(size_t(k) * 10 + k / (count / 10 + 1)) % count];
  for (uint32_t b = 0; b < 2; ++b)
    for (uint32_t k = 0; k < live; ++k)
      f->batches[b].insert(f->batches[b].end(), poses[(k + b) % kPoses].begin(),
                           poses[(k + b) % kPoses].end());
  return Status::ok();
}

// Times `path` on the field of `count` with `live` instances posed every frame.
Status runLive(Setup& setup, Renderer& renderer, const BakedPalette& palette,
               const std::vector<std::vector<glm::mat4>>& poses, uint32_t count, uint32_t live,
               const std::string& path, Row* row) {
  LiveField field;
  const Status s = makeLiveField(setup, palette, poses, count, live, &field);
  if (!s.isOk()) return s;
  row->lod = live == 0 ? "off" : std::to_string(live) + " live";
  CrowdManager& crowd = field.crowd;
  const std::vector<InstanceHandle>& posed = field.posed;
  const std::vector<glm::mat4>* batches = field.batches;
  uint32_t frame = 0;
  return timeCrowd(setup, renderer, crowd, "field", field.places, path, row,
                   [&](const Camera& cam) {
                     // Advance, write the live poses (one setLivePoses on the crowd's workers),
                     // select (the GPU selects on the GPU-selected paths).
                     Status st = crowd.advance(1.0 / 60.0);
                     ++frame;
                     if (st.isOk() && live > 0) st = crowd.setLivePoses(posed, batches[frame % 2]);
                     return st.isOk() && !isGpuSelected(path) ? crowd.update(0.0, cam) : st;
                   });
}

// What posing `live` instances adds to a frame's CPU, measured on one crowd: its frames in
// pairs, the first setting no pose (the poses set before are held), the second setting all of
// them; the medians (and quartiles) over the pairs of the second frame's update and submit less
// the first's, so that what drifts over a run (the host's load, the camera) falls out.
struct PairedAdded {
  double update = 0, submit = 0, total = 0, total_p25 = 0, total_p75 = 0;
};

Status pairLive(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                const std::vector<std::vector<glm::mat4>>& poses, uint32_t count, uint32_t live,
                const std::string& path, PairedAdded* out) {
  LiveField field;
  Status s = makeLiveField(setup, palette, poses, count, live, &field);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  std::vector<double> update, submit, total;
  double frame_update[2] = {0, 0}, frame_submit[2] = {0, 0};
  const uint32_t warmup = kWarmupFrames, n = setup.frames;
  for (uint32_t f = 0; f < 2 * (warmup + n) && s.isOk(); ++f) {
    const uint32_t pair = f / 2, k = f % 2;
    const Camera cam = cameraAt(setup, "field", field.places, pair < warmup ? 0 : pair - warmup, n);
    const auto t0 = Clock::now();
    s = field.crowd.advance(1.0 / 60.0);
    // The first pair's posed frame sets them all from their clips (untimed): each pair's
    // second frame sets poses held since an earlier step, as an engine's every frame does.
    if (s.isOk() && (k == 1 || pair == 0))
      s = field.crowd.setLivePoses(field.posed, field.batches[pair % 2]);
    if (s.isOk() && !isGpuSelected(path)) s = field.crowd.update(0.0, cam);
    const double update_ms = msSince(t0);
    DrawStats st;
    if (s.isOk()) s = drawPath(renderer, field.crowd, batcher, path, cam, &st);
    frame_update[k] = update_ms;
    frame_submit[k] = st.cpu_submit_ms;
    if (k == 1 && pair >= warmup) {
      update.push_back(frame_update[1] - frame_update[0]);
      submit.push_back(frame_submit[1] - frame_submit[0]);
      total.push_back(update.back() + submit.back());
    }
  }
  out->update = median(update);
  out->submit = median(submit);
  out->total = median(total);
  out->total_p25 = quantile(total, 0.25);
  out->total_p75 = quantile(total, 0.75);
  return s;
}

}  // namespace

Status livePosesTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                      const std::vector<uint32_t>& sizes, const std::vector<uint32_t>& live,
                      const std::vector<std::string>& paths, std::FILE* csv) {
  const int32_t walk = palette.findClip("walk");
  if (walk < 0) return {StatusCode::kNotFound, "live: the palette has no 'walk' clip"};
  std::vector<std::vector<glm::mat4>> poses(kPoses);
  const BakedClip& clip = palette.clips[size_t(walk)];
  for (uint32_t p = 0; p < kPoses; ++p) {
    poses[p].resize(palette.palette_joints.size());
    for (uint32_t slot = 0; slot < poses[p].size(); ++slot)
      poses[p][slot] = decodeJoint(palette, uint32_t(walk), p % clip.frame_count, slot);
  }
  RendererDesc rd = desc;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer renderer;
  CharacterId id;
  Status s = renderer.init(setup.info, rd);
  if (s.isOk()) s = renderer.addCharacter(setup.character, palette, &id);
  if (!s.isOk()) return {s.code(), "live: " + s.message()};
  std::printf(
      "\nLive poses (field): instances posed by the engine every frame (setLivePoses, one batch, "
      "%zu joints "
      "each, a new pose every frame), beside none, side by side in one run; update = advance, "
      "poses set, select (GPU-selected paths: no select); submit includes the live frames' "
      "upload (and on the GPU-selected paths the posed instances' state)\n",
      palette.palette_joints.size());
  printSideBySideHeader("live");
  std::printf("\n");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if (path == "traditional" || path == "cpu" || path == "rigid") continue;  // No poses.
      Row off;
      s = runLive(setup, renderer, palette, poses, count, 0, path, &off);
      if (!s.isOk()) return {s.code(), "live, " + path + ": " + s.message()};
      printSideBySideRow(off, off, "live", csv);
      std::printf("\n");
      for (uint32_t n : live) {
        if (n == 0) continue;
        Row row;
        s = runLive(setup, renderer, palette, poses, count, std::min(n, count), path, &row);
        if (!s.isOk()) return {s.code(), "live, " + path + ": " + s.message()};
        printSideBySideRow(row, off, "live", csv);
        std::printf("\n");
      }
    }
  std::printf(
      "\nLive poses, paired frames (field): one crowd's frames in pairs, the first setting no "
      "pose (those set before held), the second setting every posed instance's "
      "(setLivePoses); what the second adds to the update and submit, medians over %u pairs "
      "(the total's quartiles after it)\n",
      setup.frames);
  std::printf("%-11s %-11s %9s %9s %9s %9s %9s %9s\n", "path", "live", "instances", "update+",
              "submit+", "CPU+", "CPU+ p25", "CPU+ p75");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if (path == "traditional" || path == "cpu" || path == "rigid") continue;
      for (uint32_t n : live) {
        if (n == 0) continue;
        const uint32_t posed = std::min(n, count);
        PairedAdded added;
        s = pairLive(setup, renderer, palette, poses, count, posed, path, &added);
        if (!s.isOk()) return {s.code(), "live, paired, " + path + ": " + s.message()};
        const std::string label = std::to_string(posed) + " live";
        std::printf("%-11s %-11s %9u %9.3f %9.3f %9.3f %9.3f %9.3f\n", path.c_str(), label.c_str(),
                    count, added.update, added.submit, added.total, added.total_p25,
                    added.total_p75);
        std::fprintf(csv, "live-paired,field,%s,%u,,,,%.4f,%.4f,,,,,,%s,,,\n", path.c_str(), count,
                     added.update, added.submit, label.c_str());
      }
    }
  renderer.shutdown();
  return Status::ok();
}

}  // namespace si::bench
