// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Several characters in one renderer (Renderer::addCharacter): a mixed scene (the embedded
// character twice, as two kinds with different palettes and LOD counts, plus the sample Fox and
// CesiumMan from assets/) drawn by one renderer equals the same crowds drawn
// by one renderer per character, on every drawing path and over several frames; and the ids
// and palettes are checked.
#include <glad/gl.h>

#include <cstdlib>

#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"
#include "test_assets.h"

namespace si {
namespace {

using namespace test;

struct Kind {
  Character character;
  BakedPalette palette;
};

// The scene's character kinds. Each is baked here; its crowd borrows its palette.
std::vector<std::unique_ptr<Kind>> makeKinds() {
  std::vector<std::unique_ptr<Kind>> kinds;
  const auto add = [&](Character c, PaletteFormat format) {
    auto k = std::make_unique<Kind>();
    k->character = std::move(c);
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    bd.format = format;
    EXPECT_TRUE(bakePalette(k->character, bd, &k->palette, nullptr).isOk());
    kinds.push_back(std::move(k));
  };
  add(character(), PaletteFormat::kMatrix3x4F32);
  DefaultCharacterDesc one_lod;
  one_lod.lod_count = 1;
  Character second;
  EXPECT_TRUE(makeDefaultCharacter(one_lod, &second).isOk());
  add(std::move(second), PaletteFormat::kQuatTranslationF32);
  for (const char* file : {"Fox/glTF-Binary/Fox.glb", "CesiumMan/glTF-Binary/CesiumMan.glb"}) {
    const std::string path = test::assetPath(file);
    EXPECT_TRUE(test::assetExists(path));
    Character c;
    const Status s = importGltfFile(path, {}, &c, nullptr);
    EXPECT_TRUE(s.isOk()) << file << ": " << s.toString();
    if (s.isOk()) add(std::move(c), PaletteFormat::kMatrix3x4F32);
  }
  return kinds;
}

// Kind k's crowd: three instances 2 units tall in its own column, at different clip times.
void populate(const Kind& kind, size_t k, size_t kinds, CrowdManager* crowd) {
  CrowdDesc cd;
  cd.palette = &kind.palette;
  cd.sub_mesh_count = uint32_t(kind.character.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(kind.character.mesh.sub_meshes[0].lods.size());
  ASSERT_TRUE(crowd->init(cd).isOk());
  const Aabb box = kind.character.bindPoseBounds();
  const float scale = 2.0f / std::max(kind.character.height(), 1e-6f);
  for (int j = 0; j < 3; ++j) {
    InstanceDesc d;
    d.clip = uint32_t(j) % uint32_t(kind.palette.clips.size());
    d.time_seconds = 0.2 * j;
    d.scale = scale;
    d.position = glm::dvec3((double(k) - 0.5 * double(kinds - 1)) * 2.4 + (j - 1) * 0.6, 0.0,
                            -1.2 * j) -
                 glm::dvec3(box.center().x, box.min.y, box.center().z) * double(scale);
    d.color = glm::u8vec4(uint8_t(120 + 60 * j), 200, uint8_t(250 - 40 * k), 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
  }
}

Camera sceneCamera() {
  return Camera::lookAt({0.0, 2.5, 9.0}, {0.0, 1.0, -1.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        100.0f);
}

enum class DrawWith { kVertexShader, kCompute, kGpuDriven, kGpuDrivenCompute, kTraditional, kCpu };
const char* name(DrawWith w) {
  switch (w) {
    case DrawWith::kVertexShader: return "vertex-shader";
    case DrawWith::kCompute: return "compute";
    case DrawWith::kGpuDriven: return "GPU-driven";
    case DrawWith::kGpuDrivenCompute: return "GPU-driven compute";
    case DrawWith::kTraditional: return "traditional";
    case DrawWith::kCpu: return "CPU-skinned";
  }
  return "?";
}

Status drawWith(DrawWith w, Renderer& r, CharacterId id, const CrowdManager& crowd,
                const InstanceBatcher& batcher) {
  const Camera cam = sceneCamera();
  switch (w) {
    case DrawWith::kVertexShader:
      return r.drawCrowd(id, crowd.view(), batcher, cam, nullptr, DrawMode::kSkinned);
    case DrawWith::kCompute:
      return r.drawCrowd(id, crowd.view(), batcher, cam, nullptr, DrawMode::kComputeSkinned);
    case DrawWith::kGpuDriven:
      return r.drawCrowdGpuCulled(id, crowd.view(), cam, nullptr, DrawMode::kSkinned);
    case DrawWith::kGpuDrivenCompute:
      return r.drawCrowdGpuCulled(id, crowd.view(), cam, nullptr, DrawMode::kComputeSkinned);
    case DrawWith::kTraditional:
      return r.drawTraditional(id, crowd.view(), cam, nullptr);
    case DrawWith::kCpu:
      return r.drawCpuSkinned(id, crowd.view(), cam, nullptr);
  }
  return Status::ok();
}

class MultiCharacterTest : public RenderTest {};

TEST_P(MultiCharacterTest, OneRendererDrawsTheImageOfOneRendererPerCharacter) {
  const std::vector<std::unique_ptr<Kind>> kinds = makeKinds();
  ASSERT_GE(kinds.size(), 2u);
  std::printf("[ scene    ] %zu character kinds\n", kinds.size());
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.compute_ring_bytes = 1 << 20;  // Small: several characters' draws refill the shared ring.
  Renderer shared;
  ASSERT_TRUE(shared.init(info_, rd).isOk());
  std::vector<std::unique_ptr<Renderer>> separate;
  std::vector<CharacterId> ids;
  std::vector<std::unique_ptr<CrowdManager>> crowds;
  for (size_t k = 0; k < kinds.size(); ++k) {
    CharacterId id;
    const Status s = shared.addCharacter(kinds[k]->character, kinds[k]->palette, &id);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_EQ(id.index, uint32_t(k));
    ids.push_back(id);
    separate.push_back(std::make_unique<Renderer>());
    ASSERT_TRUE(separate.back()->init(info_, rd).isOk());
    CharacterId alone;  // Character 0 of its own renderer.
    ASSERT_TRUE(
        separate.back()->addCharacter(kinds[k]->character, kinds[k]->palette, &alone).isOk());
    crowds.push_back(std::make_unique<CrowdManager>());
    populate(*kinds[k], k, kinds.size(), crowds.back().get());
  }
  EXPECT_EQ(shared.characterCount(), uint32_t(kinds.size()));
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(shared.batchLimits()).isOk());
  for (int frame = 0; frame < 3; ++frame) {
    for (auto& c : crowds) ASSERT_TRUE(c->update(frame == 0 ? 0.0 : 0.15, sceneCamera()).isOk());
    for (DrawWith w : {DrawWith::kVertexShader, DrawWith::kCompute, DrawWith::kGpuDriven,
                       DrawWith::kGpuDrivenCompute, DrawWith::kTraditional, DrawWith::kCpu}) {
      SCOPED_TRACE(testing::Message() << name(w) << ", frame " << frame);
      std::vector<uint8_t> one, many, without_last;
      shared.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      for (size_t k = 0; k < kinds.size(); ++k) {
        const Status s = drawWith(w, shared, ids[k], *crowds[k], batcher);
        ASSERT_TRUE(s.isOk()) << s.toString();
      }
      ASSERT_TRUE(context_->readPixels(&one).isOk());
      shared.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      for (size_t k = 0; k < kinds.size(); ++k) {
        ASSERT_TRUE(drawWith(w, *separate[k], CharacterId{}, *crowds[k], batcher).isOk());
        if (k + 2 == kinds.size()) {
          ASSERT_TRUE(context_->readPixels(&without_last).isOk());
        }
      }
      ASSERT_TRUE(context_->readPixels(&many).isOk());
      const Diff d = compare(one, many, nullptr);
      EXPECT_EQ(d.max_channel, 0) << d.share * 100 << " % of pixels differ";
      // The last kind drew something: the comparison covers every kind.
      EXPECT_GT(compare(many, without_last, nullptr).share, 0.005);
    }
  }
  shared.shutdown();
  for (auto& r : separate) r->shutdown();
}

TEST_P(MultiCharacterTest, IdsAndPalettesAreChecked) {
  const std::vector<std::unique_ptr<Kind>> kinds = makeKinds();
  Renderer r;
  CharacterId id;
  EXPECT_EQ(r.addCharacter(kinds[0]->character, kinds[0]->palette, &id).code(),
            StatusCode::kInvalidArgument);  // No init.
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kCompute;  // Before any upload: the explicit setting.
  ASSERT_TRUE(r.init(info_, rd).isOk());
  EXPECT_EQ(r.skinningPath(CharacterId{2}), SkinningPath::kCompute);
  EXPECT_EQ(r.skinningPathReason(CharacterId{2}), "explicit setting");
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  EXPECT_EQ(r.addCharacter(kinds[0]->character, kinds[0]->palette, nullptr).code(),
            StatusCode::kInvalidArgument);
  ASSERT_TRUE(r.addCharacter(kinds[0]->character, kinds[0]->palette, &id).isOk());
  // A palette of another skeleton: refused, nothing added.
  BakedPalette wrong_palette = kinds[0]->palette;
  wrong_palette.skeleton_to_palette.pop_back();
  const Status wrong = r.addCharacter(kinds[0]->character, wrong_palette, &id);
  EXPECT_FALSE(wrong.isOk());
  EXPECT_EQ(r.characterCount(), 1u);
  // A mesh with morph targets and a palette baked without them: refused by name, nothing added.
  Character morphed = kinds[0]->character;
  MorphTarget target;
  target.vertices = {0};
  target.position_deltas = {{0, 0.1f, 0}};
  morphed.mesh.morph_targets = {target};
  const Status morph = r.addCharacter(morphed, kinds[0]->palette, &id);
  EXPECT_EQ(morph.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(morph.message().find("the weights of 0 morph targets, the mesh has 1"),
            std::string::npos)
      << morph.toString();
  EXPECT_EQ(r.characterCount(), 1u);
  ASSERT_TRUE(r.addCharacter(kinds[1]->character, kinds[1]->palette, &id).isOk());
  EXPECT_EQ(id.index, 1u);
  EXPECT_EQ(r.characterCount(), 2u);
  EXPECT_GT(r.triangleCount(CharacterId{1}, 0, 0), 0u);
  EXPECT_EQ(r.triangleCount(CharacterId{5}, 0, 0), 0u);
  CrowdManager crowd;
  populate(*kinds[0], 0, 2, &crowd);
  ASSERT_TRUE(crowd.update(0.0, sceneCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  for (DrawWith w : {DrawWith::kVertexShader, DrawWith::kCompute, DrawWith::kGpuDriven,
                     DrawWith::kTraditional, DrawWith::kCpu}) {
    SCOPED_TRACE(name(w));
    EXPECT_TRUE(drawWith(w, r, CharacterId{0}, crowd, batcher).isOk());
    // Character 1's palette is not the crowd's.
    const Status other = drawWith(w, r, CharacterId{1}, crowd, batcher);
    EXPECT_EQ(other.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(other.message().find("palette"), std::string::npos) << other.message();
    const Status unknown = drawWith(w, r, CharacterId{7}, crowd, batcher);
    EXPECT_EQ(unknown.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(unknown.message().find("no character 7"), std::string::npos) << unknown.message();
  }
  // A crowd holding live poses, and once none is held: every path draws it.
  CrowdDesc live_desc = crowd.desc();
  live_desc.live_pose_capacity = 1;
  CrowdManager live;
  ASSERT_TRUE(live.init(live_desc).isOk());
  InstanceHandle posed;
  ASSERT_TRUE(live.add(InstanceDesc{}, &posed).isOk());
  const BakedPalette& lp = *live_desc.palette;
  std::vector<glm::mat4> pose(lp.palette_joints.size());
  for (uint32_t slot = 0; slot < pose.size(); ++slot) pose[slot] = decodeJoint(lp, 0, 0, slot);
  for (const bool held : {true, false}) {
    SCOPED_TRACE(held ? "a live pose held" : "none held");
    if (held)
      ASSERT_TRUE(live.setLivePose(posed, pose).isOk());
    else
      ASSERT_TRUE(live.clearLivePose(posed).isOk());
    ASSERT_TRUE(live.update(0.0, sceneCamera()).isOk());
    for (DrawWith w : {DrawWith::kVertexShader, DrawWith::kCompute, DrawWith::kGpuDriven,
                       DrawWith::kGpuDrivenCompute, DrawWith::kTraditional, DrawWith::kCpu})
      EXPECT_TRUE(drawWith(w, r, CharacterId{0}, live, batcher).isOk()) << name(w);
  }
  CrowdManager crowd1;
  populate(*kinds[1], 1, 2, &crowd1);
  ASSERT_TRUE(crowd1.update(0.0, sceneCamera()).isOk());
  ASSERT_FALSE(crowd1.view().records().empty());
  std::vector<glm::vec3> positions;
  EXPECT_TRUE(
      r.captureSkinnedPositions(CharacterId{1}, crowd1.view().records()[0], &positions).isOk());
  EXPECT_EQ(positions.size(), kinds[1]->character.mesh.vertexCount());

  // Replacing character 0 with character 1's kind keeps the id: crowds of the old palette are
  // refused from then on, the new one's draw. A replacement that fails leaves it as it was.
  EXPECT_EQ(r.replaceCharacter(CharacterId{2}, kinds[1]->character, kinds[1]->palette).code(),
            StatusCode::kInvalidArgument);
  ASSERT_TRUE(r.replaceCharacter(CharacterId{0}, kinds[1]->character, kinds[1]->palette).isOk());
  EXPECT_EQ(r.characterCount(), 2u);
  EXPECT_EQ(r.drawCrowd(CharacterId{0}, crowd.view(), batcher, sceneCamera(), nullptr).code(),
            StatusCode::kInvalidArgument);
  EXPECT_TRUE(r.drawCrowd(CharacterId{0}, crowd1.view(), batcher, sceneCamera(), nullptr).isOk());
  EXPECT_EQ(r.triangleCount(CharacterId{0}, 0, 0), r.triangleCount(CharacterId{1}, 0, 0));
  const Status failed = r.replaceCharacter(CharacterId{0}, kinds[0]->character, wrong_palette);
  EXPECT_EQ(failed.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(failed.message().find("replaceCharacter"), std::string::npos) << failed.message();
  EXPECT_TRUE(r.drawCrowd(CharacterId{0}, crowd1.view(), batcher, sceneCamera(), nullptr).isOk());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

INSTANTIATE_TEST_SUITE_P(Backends, MultiCharacterTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
