// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Per-part LOD (si::buildPartLods): a crowd at every LOD of a character whose parts take their
// own levels and are dropped at the coarser ones draws, on every path (instanced, traditional,
// compute, GPU-driven with vertex-shader and with compute skinning), the image and triangle
// count of the CPU-skinning emulation; and fewer triangles than the same crowd without it.
#include "render/render_fixture.h"
#include "si/core/part_lod.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

// A crowd of `lods` levels: four rows at 10, 36, 76 and 156 units, lines at 20, 50, 100 (a
// radius of 1), so every level is drawn; every variation and several tints.
void partLodCrowd(uint32_t lods, CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = lods;
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = {20.0f, 50.0f, 100.0f, 200.0f, 400.0f, 800.0f, 1600.0f};
  cd.lod_distances_radii.resize(lods - 1);
  cd.max_distance_radii = -1.0f;
  ASSERT_TRUE(crowd->init(cd).isOk());
  const uint32_t clips = uint32_t(palette().clips.size());
  const double rows[4] = {-4.0, -30.0, -70.0, -150.0}, spacing[4] = {1.2, 4.0, 8.0, 16.0};
  for (int row = 0; row < 4; ++row)
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k - 3.5) * spacing[row], 0.0, rows[row]);
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.1 * k;
      d.color = glm::u8vec4(uint8_t(40 + 30 * k), uint8_t(200 - 20 * k), uint8_t(60 + 50 * row), 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
  ASSERT_TRUE(crowd->advance(0.4).isOk());
  ASSERT_TRUE(crowd->update(0.0, lodCamera()).isOk());
}

TEST_P(RenderTest, PartLodsDrawTheCpuEmulationsImageOnEveryPath) {
  Character parts = character();
  AnimatedLodErrorDesc poses;  // A few poses: what is drawn matters here, not the errors.
  poses.poses_per_clip = 2;
  poses.max_poses = 12;
  ASSERT_TRUE(measureAnimatedLodErrors(&parts, poses).isOk());
  PartLodReport report;
  PartLodDesc pd;
  pd.poses = poses;
  ASSERT_TRUE(buildPartLods(&parts, pd, &report).isOk());
  const uint32_t lods = uint32_t(parts.mesh.maxLodCount());
  uint32_t dropped = 0;
  for (const PartLodReport::Part& p : report.parts)
    for (int level : p.level_of) dropped += level < 0 ? 1u : 0u;
  ASSERT_GT(dropped, 0u);
  CrowdManager crowd;
  partLodCrowd(lods, &crowd);
  for (uint32_t l = 0; l < lods; ++l) ASSERT_GT(crowd.view().stats().per_lod[l], 0u) << l;

  const auto renderer = [&](Renderer* r, SkinningPath path, const Character& c) {
    RendererDesc rd;
    rd.skinning_path = path;
    rd.measure_gpu_time = true;  // The GPU-driven path reads back its counts.
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(c, palette(), &id).isOk());
  };
  Renderer vs, cs;
  renderer(&vs, SkinningPath::kVertexShader, parts);
  renderer(&cs, SkinningPath::kCompute, parts);
  DrawStats emulation_stats;
  const std::vector<uint8_t> emulation =
      draw(vs, crowd, lodCamera(), 0, false, &emulation_stats, Path::kCpuSkinned);
  ASSERT_GT(emulation_stats.triangles, 0u);

  expectEveryCaseDraws({{"instanced", &vs, Path::kInstanced, false, DrawMode::kSkinned},
                        {"traditional", &vs, Path::kTraditional, false, DrawMode::kSkinned},
                        {"compute", &cs, Path::kCompute, false, DrawMode::kSkinned},
                        {"gpu-driven", &vs, Path::kInstanced, true, DrawMode::kSkinned},
                        {"gpu-driven compute", &cs, Path::kInstanced, true,
                         DrawMode::kComputeSkinned}},
                       crowd, lodCamera(), emulation, emulation_stats);

  // The same crowd of the character without per-part LOD (its last level repeated past its
  // chain) draws more triangles.
  Renderer whole;
  renderer(&whole, SkinningPath::kVertexShader, character());
  DrawStats whole_stats;
  (void)draw(whole, crowd, lodCamera(), 0, false, &whole_stats, Path::kCpuSkinned);
  EXPECT_LT(emulation_stats.triangles, whole_stats.triangles);
}

}  // namespace
}  // namespace si
