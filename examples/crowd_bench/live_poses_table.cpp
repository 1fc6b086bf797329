// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/live_poses_table.h"

#include <algorithm>

#include "si/crowd/crowd_manager.h"

namespace si::bench {

namespace {

// Poses to cycle through: the stored matrices of the walk's frames (any clip's will do).
constexpr uint32_t kPoses = 16;

// Times `path` on the field of `count` with `live` instances posed every frame.
Status runLive(Setup& setup, Renderer& renderer, const BakedPalette& palette,
               const std::vector<std::vector<glm::mat4>>& poses, uint32_t count, uint32_t live,
               const std::string& path, Row* row) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  std::vector<InstanceHandle> handles;
  const Status s = makeCrowd(setup, palette, places, LodChoice(), &crowd, &handles, 0, live);
  if (!s.isOk()) return s;
  row->lod = live == 0 ? "off" : std::to_string(live) + " live";
  // Every tenth instance, so the posed ones spread over the field as characters would, their
  // poses in one array as an engine's animation writes them: two sets taking turns, so that
  // every frame writes poses other than the last frame's.
  std::vector<InstanceHandle> posed(live);
  for (uint32_t k = 0; k < live; ++k)
    posed[k] = handles[(size_t(k) * 10 + k / (count / 10 + 1)) % count];
  std::vector<glm::mat4> batches[2];
  for (uint32_t b = 0; b < 2; ++b)
    for (uint32_t k = 0; k < live; ++k)
      batches[b].insert(batches[b].end(), poses[(k + b) % kPoses].begin(),
                        poses[(k + b) % kPoses].end());
  uint32_t frame = 0;
  return timeCrowd(setup, renderer, crowd, "field", places, path, row, [&](const Camera& cam) {
    // Advance, write the live poses (one setLivePoses on the crowd's workers), select (the GPU
    // selects on the GPU-selected paths).
    Status st = crowd.advance(1.0 / 60.0);
    ++frame;
    if (st.isOk() && live > 0) st = crowd.setLivePoses(posed, batches[frame % 2]);
    return st.isOk() && !isGpuSelected(path) ? crowd.update(0.0, cam) : st;
  });
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
  renderer.shutdown();
  return Status::ok();
}

}  // namespace si::bench
