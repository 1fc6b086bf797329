// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/motion_vectors_table.h"

#include "si/crowd/crowd_manager.h"
#include "si/gl/motion_target.h"

namespace si::bench {

namespace {

// Times `path` on the field of `count` drawn into `target`, with motion vectors or without.
Status runMotion(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                 MotionTarget& target, uint32_t count, const std::string& path, bool motion,
                 Row* row, MotionSummary* summary) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  RendererDesc rd = desc;
  rd.skinning_path = path == "compute" ? SkinningPath::kCompute : SkinningPath::kVertexShader;
  rd.motion_vectors = motion;
  Renderer renderer;
  Status s = renderer.init(setup.info, rd);
  CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(setup.character, palette, &id);
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(setup.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(setup.character.mesh.maxLodCount());
  cd.max_distance_radii = -1.0f;  // As the paths table: everything in view, however far.
  cd.previous_records = motion && !isGpuSelected(path);  // The GPU-driven paths keep their own.
  if (s.isOk()) s = crowd.init(cd);
  RandomCrowdDesc rc;
  rc.positions = places;
  rc.seed = 2026;
  rc.optional_mask = 0xE;
  if (s.isOk()) s = crowd.addRandom(rc, nullptr);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;
  row->path = path;
  row->lod = motion ? "on" : "off";
  row->instances = count;
  s = timeFrames(
      setup, "field", places,
      [&](const Camera& cam) { return stepCrowd(crowd, path, cam, 1.0 / 60.0); },
      [&](const Camera& cam, DrawStats* st, uint32_t* visible) {
        target.clear(kClearColor);
        const Status drawn = drawKind(renderer, CharacterId{}, crowd, batcher, path, cam, st);
        *visible = isGpuSelected(path) ? st->gpu_visible : crowd.view().stats().visible;
        return drawn;
      },
      row);
  target.restore();  // The bench's framebuffer again, for the tables after this one.
  if (s.isOk()) s = target.summarize(summary);
  renderer.shutdown();
  return s;
}

}  // namespace

Status motionVectorsTable(Setup& setup, const BakedPalette& palette, const RendererDesc& desc,
                          const std::vector<uint32_t>& sizes, const std::vector<std::string>& paths,
                          std::FILE* csv) {
  MotionTarget target;
  Status s = target.create(setup.width, setup.height);
  if (!s.isOk()) return s;
  std::printf("\nMotion vectors (field, drawn into colour + RG16F motion + depth): off against "
              "on, in the same run\n");
  printSideBySideHeader("motion");
  std::printf(" %9s %9s\n", "mean px", "max px");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if (path != "instanced" && path != "compute" && path != "gpu-culled" && path != "gpu-driven")
        continue;
      Row rows[2];
      MotionSummary summaries[2];
      for (int on = 0; on < 2; ++on) {
        s = runMotion(setup, palette, desc, target, count, path, on == 1, &rows[on],
                      &summaries[on]);
        if (!s.isOk()) return {s.code(), "motion vectors, " + path + ": " + s.message()};
      }
      for (int on = 0; on < 2; ++on) {
        printSideBySideRow(rows[on], rows[0], "motion-vectors", csv);
        // Without motion vectors nothing defines what the motion attachment gets.
        if (on == 1)
          std::printf(" %9.2f %9.2f\n", summaries[on].mean_pixels, summaries[on].max_pixels);
        else
          std::printf(" %9s %9s\n", "-", "-");
      }
    }
  target.release();
  return Status::ok();
}

}  // namespace si::bench
