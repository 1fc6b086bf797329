// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/root_motion_table.h"

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/crowd/crowd_manager.h"

namespace si::bench {

namespace {

// Times `path` on the field of `count`, every instance playing a travelling clip, moved by its
// root motion or not.
Status runRootMotion(Setup& setup, Renderer& renderer, CharacterId id, const BakedPalette& palette,
                     uint32_t count, const std::string& path, bool root_motion, Row* row) {
  const std::vector<glm::dvec3> places = scenePositions("field", count);
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(setup.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(setup.character.mesh.maxLodCount());
  cd.max_distance_radii = -1.0f;  // As the paths table: everything in view, however far.
  Status s = crowd.init(cd);
  RandomCrowdDesc rc;
  rc.positions = places;
  rc.seed = 2026;
  rc.optional_mask = 0xE;
  rc.root_motion = root_motion;  // The palette holds only the travelling clips.
  if (s.isOk()) s = crowd.addRandom(rc, nullptr);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;
  row->path = path;
  row->lod = root_motion ? "on" : "off";
  row->instances = count;
  return timeFrames(
      setup, "field", places,
      [&](const Camera& cam) {  // Root motion moves instances in update() only.
        return root_motion ? crowd.update(1.0 / 60.0, cam) : stepCrowd(crowd, path, cam, 1.0 / 60.0);
      },
      [&](const Camera& cam, DrawStats* st, uint32_t* visible) {
        renderer.clear(kClearColor);
        const Status drawn = drawKind(renderer, id, crowd, batcher, path, cam, st);
        *visible = isGpuSelected(path) ? st->gpu_visible : crowd.view().stats().visible;
        return drawn;
      },
      row);
}

}  // namespace

Status rootMotionTable(Setup& setup, const RendererDesc& desc, const std::vector<uint32_t>& sizes,
                       const std::vector<std::string>& paths, uint32_t max_baseline,
                       std::FILE* csv) {
  // The embedded character's mesh and LOD chain, with its travelling clips only.
  DefaultCharacterDesc moving_desc;
  moving_desc.moving_clips = true;
  Character moving;
  Status s = makeDefaultCharacter(moving_desc, &moving);
  if (!s.isOk()) return s;
  Character character = setup.character;
  character.clips.clear();
  for (const Clip& c : moving.clips)
    if (c.root_motion.extract) character.clips.push_back(c);
  BakeDesc bd;
  bd.rate_mode = RateMode::kFixed;
  BakedPalette palette;
  s = bakePalette(character, bd, &palette, nullptr);
  Renderer renderer;
  if (s.isOk()) s = renderer.init(setup.info, desc);
  CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  if (!s.isOk()) return s;
  std::printf("\nRoot motion (field; walk_forward and walk_turn_left baked in place at 30 Hz): "
              "played in place against moved by their root motion, in the same run\n");
  printSideBySideHeader("motion");
  std::printf("\n");
  for (uint32_t count : sizes)
    for (const std::string& path : paths) {
      if ((path == "traditional" || path == "cpu") && count > max_baseline) continue;
      Row rows[2];
      for (int on = 0; on < 2; ++on) {
        s = runRootMotion(setup, renderer, id, palette, count, path, on == 1, &rows[on]);
        if (!s.isOk()) return {s.code(), "root motion, " + path + ": " + s.message()};
      }
      for (const Row& r : rows) {
        printSideBySideRow(r, rows[0], "root-motion", csv);
        std::printf("\n");
      }
    }
  renderer.shutdown();
  return Status::ok();
}

}  // namespace si::bench
