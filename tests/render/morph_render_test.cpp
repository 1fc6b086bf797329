// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Morph targets drawn (issue "Any animated glTF becomes a crowd", part 1): a character with
// face-like targets (examples/common/face_targets.h) draws on every path what the CPU emulation
// draws with the targets at the palette's weights, over frames of its clip and through a
// crossfade, and visibly not what the character without them draws; the captures put the
// morphed vertices where the reference does, and the impostor atlas holds the morphed poses;
// the OpenGL ES profile draws them too.
#include "render/morph_scenes.h"
#include "render/skinning_paths.h"
#include "si/core/impostor_level.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

class MorphRenderTest : public MorphRenderFixture {};

TEST_P(MorphRenderTest, EveryPathDrawsTheMorphs) {
  const Character morphed = morphCharacter(6);
  Character plain = morphed;
  plain.mesh.morph_targets.clear();
  for (Clip& clip : plain.clips) clip.morph_tracks.clear();
  const BakedPalette palette = bakeAt30(morphed), plain_palette = bakeAt30(plain);
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id, without;
  const Status added = r.addCharacter(morphed, palette, &id);
  ASSERT_TRUE(added.isOk()) << added.toString();
  ASSERT_TRUE(r.addCharacter(plain, plain_palette, &without).isOk());
  CrowdManager crowd, plain_crowd;
  const Status made = headCrowd(morphed, palette, &crowd);
  ASSERT_TRUE(made.isOk()) << made.toString();
  ASSERT_TRUE(headCrowd(plain, plain_palette, &plain_crowd).isOk());
  const Camera camera = headCamera(morphed);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  for (int frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE(testing::Message() << "frame " << frame);
    ASSERT_TRUE(crowd.update(frame == 0 ? 0.0 : 0.2, camera).isOk());
    ASSERT_TRUE(plain_crowd.update(frame == 0 ? 0.0 : 0.2, camera).isOk());
    const std::vector<uint8_t> plain_image =
        cpuSkinnedImage(r, without, plain_crowd.view(), camera, background, *context_);
    const std::vector<uint8_t> emulated =
        cpuSkinnedImage(r, id, crowd.view(), camera, background, *context_);
    EXPECT_GT(compare(emulated, plain_image, nullptr).share, 3 * kMaxDifferingShare)
        << "the targets show in this view";
    expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, emulated);
  }
  r.shutdown();
}

// At a coarse LOD level each vertex leaves out the targets that together move it no farther
// than the level's cut (RendererDesc::morph_lod_share of its error): every path leaves out what
// the CPU emulation leaves out, and the image visibly differs from keeping them all; a share
// outside [0, 1] is refused by name.
TEST_P(MorphRenderTest, CoarseLevelsLeaveOutWhatMovesLessThanTheirCut) {
  const Character c = morphCharacter(6);
  const BakedPalette palette = bakeAt30(c);
  ASSERT_GE(c.mesh.maxLodCount(), 2u);
  CrowdManager crowd;
  ASSERT_TRUE(headCrowd(c, palette, &crowd, {0.1f, 100.0f}).isOk());  // All at LOD 1.
  const Camera camera = headCamera(c);
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  for (InstanceHandle h : crowd.view().visibleHandles()) {
    uint32_t lod = 0;
    ASSERT_TRUE(crowd.view().lodOf(h, &lod).isOk());
    ASSERT_EQ(lod, 1u);
  }
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  // A renderer cutting `share` of each level's error, with the character added.
  const auto addAt = [&](float share, Renderer* r, CharacterId* id) {
    RendererDesc rd;
    rd.morph_lod_share = share;
    const Status s = r->init(info_, rd);
    return s.isOk() ? r->addCharacter(c, palette, id) : s;
  };
  Renderer all, r;  // Every target kept; cutting a whole level's error.
  CharacterId all_id, id;
  ASSERT_TRUE(addAt(0.0f, &all, &all_id).isOk());
  ASSERT_TRUE(addAt(1.0f, &r, &id).isOk());
  const std::vector<uint8_t> kept =
      cpuSkinnedImage(all, all_id, crowd.view(), camera, background, *context_);
  all.shutdown();
  const std::vector<uint8_t> cut =
      cpuSkinnedImage(r, id, crowd.view(), camera, background, *context_);
  EXPECT_GT(compare(cut, kept, nullptr).share, kMaxDifferingShare) << "the cut leaves targets out";
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, cut);
  r.shutdown();
  for (float bad : {-0.5f, 1.5f}) {
    Renderer refused;
    RendererDesc rd;
    rd.morph_lod_share = bad;
    const Status s = refused.init(info_, rd);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("morph_lod_share"), std::string::npos) << s.toString();
  }
}

// An overlay on a mask of targets (an expression over whatever the clip plays) moves those
// targets by its clip's weights, mixed by its weight: every path draws what the CPU emulation
// draws, with the layers composed once per instance and walked per vertex, and the heads differ
// visibly from the same crowd without the overlay.
TEST_P(MorphRenderTest, AnOverlayMovesTheTargetsOfItsMask) {
  // The expression: a clip holding targets 0 to 3 at 1 (the face clips keep them near 0.5).
  Character c = morphCharacter(6);
  Clip smile = c.clips[0];
  smile.name = "smile";
  MorphWeightTrack& held = smile.morph_tracks[0];
  for (size_t key = 0; key < held.times_seconds.size(); ++key)
    for (size_t k = 0; k < 6; ++k) held.values[key * 6 + k] = k < 4 ? 1.0f : 0.0f;
  c.clips.push_back(smile);
  const BakedPalette palette = bakeAt30(c);
  LayerMask face;
  ASSERT_TRUE(
      buildMorphTargetMask(c.mesh, palette, "face", {"face0", "face1", "face2", "face3"}, &face)
          .isOk());
  CrowdManager crowd, plain;
  ASSERT_TRUE(headCrowd(c, palette, &crowd).isOk());
  ASSERT_TRUE(headCrowd(c, palette, &plain).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd.addLayerMask(face, &mask).isOk());
  const Camera camera = headCamera(c);
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  ASSERT_TRUE(plain.update(0.0, camera).isOk());
  const std::vector<InstanceHandle> handles(crowd.view().visibleHandles().begin(),
                                            crowd.view().visibleHandles().end());
  ASSERT_EQ(handles.size(), 3u);
  const uint32_t expression = uint32_t(palette.findClip("smile"));
  ASSERT_TRUE(crowd.playOverlay(handles[0], expression, mask, 1.0f, 0.0, 0.4).isOk());
  ASSERT_TRUE(crowd.playOverlay(handles[2], expression, mask, 1.0f, 1.0, 0.1).isOk());  // Fading.
  Renderer r;
  CharacterId id;
  InstanceBatcher batcher;
  initRenderer(c, palette, &r, &id, &batcher);
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  for (int frame = 0; frame < 2; ++frame) {
    SCOPED_TRACE(testing::Message() << "frame " << frame);
    ASSERT_TRUE(crowd.update(0.3, camera).isOk());
    ASSERT_TRUE(plain.update(0.3, camera).isOk());
    ASSERT_FALSE(crowd.view().layerRecords().empty());
    const std::vector<uint8_t> emulated =
        cpuSkinnedImage(r, id, crowd.view(), camera, background, *context_);
    const std::vector<uint8_t> without =
        cpuSkinnedImage(r, id, plain.view(), camera, background, *context_);
    EXPECT_GT(compare(emulated, without, nullptr).share, 3 * kMaxDifferingShare)
        << "the overlay moves the faces";
    for (bool composed : {true, false}) {
      SCOPED_TRACE(composed ? "layers composed" : "layers walked per vertex");
      r.setComposeLayers(composed);
      expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, emulated);
    }
  }
  r.shutdown();
}

// The captures (the vertex shader's through transform feedback, the compute pre-skinning
// pass's buffer) put the morphed vertices where the reference does, within the bake's error.
TEST_P(MorphRenderTest, TheCapturesApplyTheMorphs) {
  const Character c = morphCharacter(6);
  BakeReport report;
  const BakedPalette palette = bakeAt30(c, &report);
  Renderer r;
  ASSERT_TRUE(r.init(info_, RendererDesc()).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(c, palette, &id).isOk());
  const BakedClip& clip = palette.clips[0];
  std::vector<double> weights(c.mesh.morph_targets.size());
  for (double t : {0.3 * clip.duration_seconds, 0.8 * clip.duration_seconds}) {
    const InstanceRecord rec = clipRecord(palette, 0, t);
    ReferencePose pose;
    ASSERT_TRUE(evaluateLocalPose(c.skeleton, c.clips[0], t, &pose).isOk());
    ASSERT_TRUE(evaluateMorphWeights(c.mesh, c.clips[0], t, weights).isOk());
    std::vector<glm::dvec3> reference(c.mesh.vertexCount()), unmorphed(c.mesh.vertexCount());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, reference, {}, {}, weights).isOk());
    ASSERT_TRUE(skinVertices(c.mesh, pose.skinning, unmorphed, {}, {},
                             std::vector<double>(weights.size(), 0.0))
                    .isOk());
    for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
      SCOPED_TRACE(testing::Message()
                   << (path == SkinningPath::kCompute ? "compute" : "vertex") << " t=" << t);
      std::vector<glm::vec3> gpu;
      ASSERT_TRUE(r.captureSkinnedPositions(id, rec, &gpu, path).isOk());
      ASSERT_EQ(gpu.size(), reference.size());
      double worst = 0.0, moved = 0.0;
      for (size_t v = 0; v < gpu.size(); ++v) {
        worst = std::max(worst, glm::length(glm::dvec3(gpu[v]) - reference[v]));
        moved = std::max(moved, glm::length(unmorphed[v] - reference[v]));
      }
      EXPECT_LE(worst, report.max_error_units + 2e-5);
      EXPECT_GT(moved, 10.0 * worst + 1e-3) << "the targets move the head";
    }
  }
  r.shutdown();
}

// Three characters held at times of their clip, side by side facing flatCamera()-like views,
// every one drawn at its impostor level (`impostors`) or at LOD 0.
Status standingCrowd(const Character& c, const BakedPalette& palette, bool impostors,
                     CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(c.mesh.maxLodCount());
  cd.character_radius = 1.0f;
  for (uint32_t l = 1; l < cd.lod_count; ++l)
    cd.lod_distances_radii.push_back((impostors ? 1e-3f : 1e6f) * float(l));
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = cd.lod_count - 1;
  Status s = crowd->init(cd);
  const double height = c.height();
  // At the frames the atlas captures (ImpostorDesc::frames_per_clip 4: 1, 2 and 3 of 0 to 3
  // spread over the clip's baked frames), unturned (its first azimuth).
  const BakedClip& clip = palette.clips[0];
  for (uint32_t k = 0; k < 3 && s.isOk(); ++k) {
    const uint32_t frame = ((k + 1) * (clip.frame_count - 1) + 1) / 3;
    InstanceDesc d;
    d.position = glm::dvec3((double(k) - 1.0) * 0.45 * height, 0.0, 0.0);
    d.time_seconds = double(frame) * clip.frame_interval_seconds;
    d.speed = 0.0f;
    InstanceHandle h;
    s = crowd->add(d, &h);
  }
  return s;
}

// The impostor capture applies the morph targets at each captured frame's weights: the crowd
// drawn as impostors differs from impostors of the same character with its weights held at 0
// at least half as much as the meshes do, and the impostors are as close to their meshes as
// those with the weights at 0 are to theirs.
TEST_P(MorphRenderTest, TheImpostorCapturesTheMorphs) {
  Character morphed = morphCharacter(6);
  ASSERT_TRUE(appendImpostorLevel(&morphed.mesh).isOk());
  // The same targets held at 0, with the clips' bounds (which frame the atlas's cells) of the
  // weights: the images differ where the weights move the vertices.
  Character plain = morphed;
  for (MorphTarget& t : plain.mesh.morph_targets) t.default_weight = 0.0f;
  for (Clip& clip : plain.clips)
    for (MorphWeightTrack& track : clip.morph_tracks)
      std::fill(track.values.begin(), track.values.end(), 0.0f);
  const BakedPalette palette = bakeAt30(morphed);
  BakedPalette plain_palette = bakeAt30(plain);
  for (size_t k = 0; k < palette.clips.size(); ++k) {
    plain_palette.clips[k].bounds = palette.clips[k].bounds;
    plain_palette.clips[k].bounding_sphere = palette.clips[k].bounding_sphere;
  }
  ImpostorDesc atlas;
  atlas.azimuths = 8;
  atlas.elevations_degrees = {0.0f};
  atlas.frames_per_clip = 4;
  atlas.cell_pixels = 128;
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id, without;
  ASSERT_TRUE(r.addCharacter(morphed, palette, &id).isOk());
  const Status added = r.addCharacter(plain, plain_palette, &without);
  ASSERT_TRUE(added.isOk()) << added.toString();
  for (CharacterId k : {id, without}) {
    const Status s = r.buildImpostor(k, atlas);
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  // The three fill the view, seen level from the front.
  const double height = morphed.height();
  const double z = 0.5 * height / 0.8 / std::tan(0.45);
  const Camera camera = Camera::lookAt({0.0, 0.5 * height, z}, {0.0, 0.5 * height, 0.0},
                                       glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f, 100.0f);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const auto image = [&](CharacterId k, const BakedPalette& p, const Character& c, bool impostors) {
    CrowdManager crowd;
    EXPECT_TRUE(standingCrowd(c, p, impostors, &crowd).isOk());
    EXPECT_TRUE(crowd.update(0.0, camera).isOk());
    EXPECT_EQ(crowd.view().stats().per_lod[impostors ? c.mesh.maxLodCount() - 1 : 0], 3u);
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = r.drawCrowd(k, crowd.view(), batcher, camera, nullptr);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  };
  // The mean absolute difference of two images' channels (0 to 255).
  const auto distance = [](const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double sum = 0.0;
    for (size_t k = 0; k < a.size() && a.size() == b.size(); ++k)
      if (k % 4 != 3) sum += std::abs(int(a[k]) - int(b[k]));
    return a.size() == b.size() && !a.empty() ? sum / double(a.size() / 4 * 3) : 255.0;
  };
  const std::vector<uint8_t> meshes = image(id, palette, morphed, false);
  const std::vector<uint8_t> plain_meshes = image(without, plain_palette, plain, false);
  const std::vector<uint8_t> impostors = image(id, palette, morphed, true);
  const std::vector<uint8_t> plain_impostors = image(without, plain_palette, plain, true);
  const double morphs = distance(meshes, plain_meshes);
  const double captured = distance(impostors, plain_impostors);
  const double error = distance(impostors, meshes),
               plain_error = distance(plain_impostors, plain_meshes);
  std::printf(
      "[ morph impostor ] mean channel difference: the targets move the meshes by %.3f "
      "and the impostors by %.3f; impostors to meshes %.3f (targets at 0: %.3f)\n",
      morphs, captured, error, plain_error);
  EXPECT_GT(morphs, 0.1) << "the targets show in this view";
  EXPECT_GT(captured, 0.5 * morphs) << "the capture moves the faces";
  EXPECT_LT(error, 1.1 * plain_error) << "the impostors of the faces are as close as without";
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, MorphRenderTest, allBackends(), backendTestName);

// The OpenGL ES profile (GLSL ES 3.00, the vertex-shader path only) draws the morphs as a
// desktop context's CPU emulation does.
class MorphEsTest : public RenderTest {
 protected:
  bool es() const override { return true; }
  std::vector<uint8_t> drawHeads(bool cpu) {
    const Character c = morphCharacter(6);
    const BakedPalette palette = bakeAt30(c);
    CrowdManager crowd;
    EXPECT_TRUE(headCrowd(c, palette, &crowd).isOk());
    return drawCrowdImage(c, palette, crowd, headCamera(c), cpu);
  }
};

TEST_P(MorphEsTest, TheEsProfileDrawsTheMorphs) {
  expectEsDrawsAsDesktopCpu([this](bool cpu) { return drawHeads(cpu); });
}

INSTANTIATE_TEST_SUITE_P(Backends, MorphEsTest, esBackends(), backendTestName);

}  // namespace
}  // namespace si
