// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets under blend spaces (issue "Any animated glTF becomes a crowd"): a 2D blend's four
// clips move the targets of its mask, its third and fourth through the layer compose pass's
// weights, on every path as the CPU emulation draws them, and in the motion vectors.
#include "render/morph_scenes.h"
#include "render/skinning_paths.h"
#include "si/crowd/blend_space.h"
#include "si/gl/motion_target.h"

namespace si {
namespace {

using namespace test;

class MorphBlendRenderTest : public MorphRenderFixture {};

// The face character with two more clips of its first clip's joints: "smile" holding targets 0
// to 3 at 1, "still" holding every target at 0.
Character smileCharacter() {
  Character c = morphCharacter(6);
  for (const char* name : {"smile", "still"}) {
    Clip held = c.clips[0];
    held.name = name;
    MorphWeightTrack& track = held.morph_tracks[0];
    for (size_t key = 0; key < track.times_seconds.size(); ++key)
      for (size_t k = 0; k < 6; ++k)
        track.values[key * 6 + k] = k < 4 && name[1] == 'm' ? 1.0f : 0.0f;
    c.clips.push_back(held);
  }
  return c;
}

// The 2D grid the blends play: "still" on its lower line, "smile" on its upper one.
BlendSpace smileGrid(const BakedPalette& palette, uint32_t mask) {
  const uint32_t smile = uint32_t(palette.findClip("smile")),
                 still = uint32_t(palette.findClip("still"));
  BlendSpace grid;
  grid.name = "grid";
  grid.clips = {still, still, smile, smile};
  grid.positions = {0.0f, 1.0f};
  grid.positions_y = {0.0f, 1.0f};
  grid.mask = mask;
  return grid;
}

// A 2D blend moves the targets of its mask with all four clips (its third and fourth through
// the compose pass's weights): on a mask of targets alone and on a full-body mask that holds
// targets too, every path draws what the CPU emulation draws, and the heads differ visibly from
// the same blend on the grid's lower line, where the third and fourth clips have no share.
TEST_P(MorphBlendRenderTest, ABlendsFourClipsMoveTheTargetsOnEveryPath) {
  const Character c = smileCharacter();
  const BakedPalette palette = bakeAt30(c);
  const std::vector<std::string> targets = {"face0", "face1", "face2", "face3"};
  LayerMask face, body;
  ASSERT_TRUE(buildMorphTargetMask(c.mesh, palette, "face", targets, &face).isOk());
  ASSERT_TRUE(buildFullBodyMask(c.skeleton, palette, "body", &body).isOk());
  body.morph_targets = face.morph_targets;
  Renderer r;
  CharacterId id;
  InstanceBatcher batcher;
  initRenderer(c, palette, &r, &id, &batcher);
  const Camera camera = headCamera(c);
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  // The heads blending at `y` on the grid (the middle one left crossfading), drawn emulated.
  const auto blended = [&](const LayerMask& mask, float y, CrowdManager* crowd) {
    EXPECT_TRUE(headCrowd(c, palette, crowd).isOk());
    uint32_t mask_id = 0, space = 0;
    EXPECT_TRUE(crowd->addLayerMask(mask, &mask_id).isOk());
    EXPECT_TRUE(crowd->addBlendSpace(smileGrid(palette, mask_id), &space).isOk());
    EXPECT_TRUE(crowd->update(0.0, camera).isOk());
    const std::vector<InstanceHandle> heads(crowd->view().visibleHandles().begin(),
                                            crowd->view().visibleHandles().end());
    EXPECT_EQ(heads.size(), 3u);
    for (size_t k = 0; k < heads.size(); k += 2)
      EXPECT_TRUE(crowd
                      ->playBlend(heads[k], space, glm::vec2(0.3f + 0.4f * float(k), y), 0.0,
                                  0.2 * double(k))
                      .isOk());
    EXPECT_TRUE(crowd->update(0.2, camera).isOk());
    return cpuSkinnedImage(r, id, crowd->view(), camera, background, *context_);
  };
  for (const LayerMask* mask : {&face, &body}) {
    SCOPED_TRACE(mask->name);
    CrowdManager crowd, lower_line;
    const std::vector<uint8_t> emulated = blended(*mask, 0.7f, &crowd);
    ASSERT_FALSE(crowd.view().extraLayerRecords().empty());
    EXPECT_GT(compare(emulated, blended(*mask, 0.0f, &lower_line), nullptr).share,
              3 * kMaxDifferingShare)
        << "the third and fourth clips move the faces";
    expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, emulated);
  }
  r.shutdown();
}

// Motion vectors of a 2D blend's morph targets: with every joint held still and only the blend
// point moving up the grid between two frames (the smile's share growing), the faces move by
// the composed weights' change alone; both skinning paths and both GPU-driven draws agree (the
// previous frame's composed weights are the previous records'), and held there, nothing moves.
TEST_P(MorphBlendRenderTest, ABlendsMorphTargetsMoveInTheMotionVectors) {
  const Character c = smileCharacter();
  const BakedPalette palette = bakeAt30(c);
  LayerMask face;
  ASSERT_TRUE(
      buildMorphTargetMask(c.mesh, palette, "face", {"face0", "face1", "face2", "face3"}, &face)
          .isOk());
  RendererDesc rd;
  rd.motion_vectors = true;
  rd.gpu_driven_ring_bytes = 4u << 20;
  rd.skinning_path = SkinningPath::kVertexShader;
  Renderer r;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(c, palette, &id).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  MotionTarget target;
  ASSERT_TRUE(target.create(kSize, kSize).isOk());
  const Camera camera = headCamera(c);
  // The heads held still, blending at y `from` then, 0.05 s later, at `to`; drawn in `mode`.
  const auto motionOf = [&](float from, float to, DrawMode mode, bool gpu_driven,
                            std::vector<glm::vec2>* motion) {
    CrowdManager crowd;
    CrowdDesc cd;
    cd.palette = &palette;
    cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
    cd.lod_count = uint32_t(c.mesh.maxLodCount());
    cd.previous_records = true;
    ASSERT_TRUE(crowd.init(cd).isOk());
    uint32_t mask = 0, space = 0;
    ASSERT_TRUE(crowd.addLayerMask(face, &mask).isOk());
    ASSERT_TRUE(crowd.addBlendSpace(smileGrid(palette, mask), &space).isOk());
    std::vector<InstanceHandle> heads;
    for (int k = 0; k < 3; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(-0.5 + 0.5 * k, 0.0, -0.4 * std::abs(k - 1));
      d.speed = 0.0f;
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
      ASSERT_TRUE(crowd.playBlend(h, space, glm::vec2(0.3f + 0.2f * float(k), from), 0.0, 0.0, 0.0f)
                      .isOk());
      heads.push_back(h);
    }
    const auto moveUp = [&] {
      for (size_t k = 0; k < heads.size(); ++k)
        ASSERT_TRUE(
            crowd.setBlendParameter(heads[k], glm::vec2(0.3f + 0.2f * float(k), to)).isOk());
    };
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    if (gpu_driven) {
      ASSERT_TRUE(r.drawCrowdGpuCulled(id, crowd.view(), camera, nullptr, mode).isOk());
      moveUp();
      ASSERT_TRUE(crowd.advance(0.05).isOk());
      target.clear(glm::vec4(0.0f));
      const Status s = r.drawCrowdGpuCulled(id, crowd.view(), camera, nullptr, mode);
      ASSERT_TRUE(s.isOk()) << s.toString();
      ASSERT_TRUE(target.readMotion(motion).isOk());
      return;
    }
    moveUp();
    ASSERT_TRUE(crowd.update(0.05, camera).isOk());
    target.clear(glm::vec4(0.0f));
    const Status s = r.drawCrowd(id, crowd.view(), batcher, camera, nullptr, mode);
    ASSERT_TRUE(s.isOk()) << s.toString();
    ASSERT_TRUE(target.readMotion(motion).isOk());
  };
  std::vector<glm::vec2> vs, cs, gpu_vs, gpu_cs, held, gpu_held;
  motionOf(0.2f, 0.9f, DrawMode::kSkinned, false, &vs);
  motionOf(0.2f, 0.9f, DrawMode::kComputeSkinned, false, &cs);
  motionOf(0.2f, 0.9f, DrawMode::kSkinned, true, &gpu_vs);
  motionOf(0.2f, 0.9f, DrawMode::kComputeSkinned, true, &gpu_cs);
  motionOf(0.9f, 0.9f, DrawMode::kSkinned, false, &held);
  motionOf(0.9f, 0.9f, DrawMode::kComputeSkinned, true, &gpu_held);
  std::printf("[ morph motion ] largest motion: blend moving %.2f px, held %.4f px\n",
              largestMotionPixels(vs), largestMotionPixels(held));
  EXPECT_GT(largestMotionPixels(vs), 0.5f) << "the smile's weights move the faces";
  EXPECT_LT(largestMotionPixels(held), 1e-3f);
  EXPECT_LT(largestMotionPixels(gpu_held), 1e-3f);
  for (const std::vector<glm::vec2>* other : {&cs, &gpu_vs, &gpu_cs}) {
    SCOPED_TRACE(other - &vs);
    expectMotionAgrees(vs, *other);
  }
  target.restore();
  target.release();
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, MorphBlendRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
