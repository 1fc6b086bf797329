// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Materials in one draw: a generated asset of 200 primitives and 100 materials, imported as
// one always-worn part with per-vertex materials, draws (both skinning paths) the image of a
// reference that draws each material's triangles separately with that material alone; and
// every sample asset draws the same image on the GPU as skinned on the CPU.
#include <cstdlib>
#include <set>

#include "gltf/parts_asset.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"
#include "test_assets.h"

namespace si {
namespace {

using namespace test;

Camera partsCamera() {
  return Camera::lookAt({0.0, 1.0, 3.0}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.75f, 1.0f, 0.1f,
                        100.0f);
}

// The triangles of `c` whose vertices use material `m`, as a character of that material alone.
Character onlyMaterial(const Character& c, uint16_t m) {
  Character out = c;
  out.mesh.indices.clear();
  for (const SubMesh& sm : c.mesh.sub_meshes)
    for (uint32_t i = sm.lods[0].first_index; i + 2 < sm.lods[0].first_index + sm.lods[0].index_count; i += 3)
      if (c.mesh.vertex_materials[c.mesh.indices[i]] == m)
        out.mesh.indices.insert(out.mesh.indices.end(), &c.mesh.indices[i], &c.mesh.indices[i] + 3);
  out.mesh.vertex_materials.clear();
  out.materials = {c.materials[m]};
  out.mesh.sub_meshes.resize(1);
  out.mesh.sub_meshes[0].material = 0;
  out.mesh.sub_meshes[0].lods = {{0, uint32_t(out.mesh.indices.size())}};
  out.mesh.sub_meshes[0].lod_error_units.clear();
  return out;
}

template <bool kEs>
class MaterialScenes : public RenderTest {
 protected:
  bool es() const override { return kEs; }

  // One instance at the origin playing clip 0 at `time`.
  void oneInstance(const BakedPalette& p, uint32_t sub_meshes, double time, CrowdManager* crowd) {
    CrowdDesc cd;
    cd.palette = &p;
    cd.sub_mesh_count = sub_meshes;
    cd.lod_count = 1;
    ASSERT_TRUE(crowd->init(cd).isOk());
    InstanceDesc d;
    d.clip = 0;
    d.time_seconds = time;
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
    ASSERT_TRUE(crowd->update(0.0, partsCamera()).isOk());
  }

  // Draws `c` (after clearing when `clear`) and reads the image.
  std::vector<uint8_t> drawCharacter(Renderer& r, const Character& c, const BakedPalette& p,
                                     Path path, bool clear = true) {
    // Character 0 is each call's character: added the first time, replaced after.
    const Status uploaded = r.characterCount() == 0 ? r.addCharacter(c, p, &id_)
                                                    : r.replaceCharacter(id_, c, p);
    EXPECT_TRUE(uploaded.isOk()) << uploaded.toString();
    CrowdManager crowd;
    oneInstance(p, uint32_t(c.mesh.sub_meshes.size()), 0.3, &crowd);
    InstanceBatcher batcher;
    EXPECT_TRUE(batcher.init(r.batchLimits()).isOk());
    if (clear) r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats stats;
    const Status s = path == Path::kCpuSkinned
                         ? r.drawCpuSkinned(CharacterId{}, crowd.view(), partsCamera(), &stats)
                     : path == Path::kCompute
                         ? r.drawCrowd(CharacterId{}, crowd.view(), batcher, partsCamera(), &stats,
                                       DrawMode::kComputeSkinned)
                         : r.drawCrowd(CharacterId{}, crowd.view(), batcher, partsCamera(), &stats,
                                       DrawMode::kSkinned);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }

  Renderer& renderer() {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    EXPECT_TRUE(renderer_.init(info_, rd).isOk());  // drawCharacter uploads each character.
    return renderer_;
  }

  // A generated asset of 200 primitives and `materials` materials, one part, and its palette.
  static void partsCharacter(int materials, Character* c, BakedPalette* p) {
    GltfImportReport report;
    const std::string json = partsAsset({{"Body", 200}}, materials);
    ASSERT_TRUE(importGltfMemory(
                    Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()),
                    "", {}, c, &report)
                    .isOk());
    ASSERT_EQ(c->mesh.sub_meshes.size(), 1u);
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    ASSERT_TRUE(bakePalette(*c, bd, p, nullptr).isOk());
  }

  void twoHundredPartsDrawLikeEachMaterialDrawnAlone();

  Renderer renderer_;
  CharacterId id_;
};
using MaterialsTest = MaterialScenes<false>;
using EsMaterialsTest = MaterialScenes<true>;  // The ES profile: its one path.

template <bool kEs>
void MaterialScenes<kEs>::twoHundredPartsDrawLikeEachMaterialDrawnAlone() {
  Character c;
  BakedPalette p;
  partsCharacter(100, &c, &p);
  Renderer& r = renderer();
  // The reference: one draw per material, each with that material alone, into one image.
  std::vector<uint8_t> reference;
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  for (uint16_t m = 0; m < c.materials.size(); ++m) {
    const Character part = onlyMaterial(c, m);
    if (part.mesh.indices.empty()) continue;
    reference = drawCharacter(r, part, p, Path::kInstanced, /*clear=*/false);
  }
  std::set<uint32_t> colours;
  for (size_t i = 0; i < reference.size(); i += 4)
    colours.insert(uint32_t(reference[i]) | uint32_t(reference[i + 1]) << 8 | uint32_t(reference[i + 2]) << 16);
  EXPECT_GE(colours.size(), 50u);  // The materials show: many distinct colours.
  for (Path path : {Path::kInstanced, Path::kCompute, Path::kCpuSkinned}) {
    if (kEs && path != Path::kInstanced) continue;
    const Diff d = compare(drawCharacter(r, c, p, path), reference, nullptr);
    EXPECT_LE(d.share, kMaxDifferingShare) << "path " << int(path) << " max " << d.max_channel;
  }
  // The comparison can fail: every vertex with one material is another image.
  Character one = c;
  one.mesh.vertex_materials.assign(one.mesh.vertexCount(), 5);
  EXPECT_GT(compare(drawCharacter(r, one, p, Path::kInstanced), reference, nullptr).share, 0.01);
}

TEST_P(MaterialsTest, TwoHundredPartsDrawLikeEachMaterialDrawnAlone) {
  twoHundredPartsDrawLikeEachMaterialDrawnAlone();
}
TEST_P(EsMaterialsTest, TwoHundredPartsDrawLikeEachMaterialDrawnAlone) {
  twoHundredPartsDrawLikeEachMaterialDrawnAlone();
}

// The ES profile's material table is a uniform block of kEsMaxMaterials (256) entries: a
// character with more is refused by name, and the renderer keeps working.
TEST_P(EsMaterialsTest, MoreMaterialsThanTheBlockHoldsAreRefused) {
  Character c;
  BakedPalette p;
  partsCharacter(300, &c, &p);
  ASSERT_GT(c.materials.size(), 256u);
  Renderer& r = renderer();
  CharacterId id;
  const Status s = r.addCharacter(c, p, &id);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("material block holds 256"), std::string::npos) << s.message();
  EXPECT_EQ(r.characterCount(), 0u);
  EXPECT_TRUE(checkGlErrors("after the refusal").isOk());
}

TEST_P(MaterialsTest, SampleAssetsDrawOnTheGpuAsSkinnedOnTheCpu) {
  for (const char* file :
       {"RiggedSimple/glTF/RiggedSimple.gltf", "RiggedSimple/glTF-Binary/RiggedSimple.glb",
        "RiggedFigure/glTF-Binary/RiggedFigure.glb", "CesiumMan/glTF/CesiumMan.gltf",
        "RiggedFigure/glTF/RiggedFigure.gltf", "CesiumMan/glTF-Binary/CesiumMan.glb",
        "Fox/glTF-Binary/Fox.glb", "Fox/glTF/Fox.gltf",
        "SimpleSkin/glTF/SimpleSkin.gltf", "SimpleSkin/glTF-Embedded/SimpleSkin.gltf"}) {
    SCOPED_TRACE(file);
    const std::string path = test::assetPath(file);
    ASSERT_TRUE(test::assetExists(path));
    Character c;
    const Status s = importGltfFile(path, {}, &c, nullptr);
    ASSERT_TRUE(s.isOk()) << s.toString();
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    BakedPalette p;
    ASSERT_TRUE(bakePalette(c, bd, &p, nullptr).isOk());
    // The character fills the view: scaled to 2 units, its bind-pose centre at (0, 1, 0).
    Renderer r;
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    ASSERT_TRUE(r.init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r.addCharacter(c, p, &id).isOk());
    CrowdDesc cd;
    cd.palette = &p;
    cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
    cd.lod_count = 1;
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(cd).isOk());
    const Aabb box = c.bindPoseBounds();
    const float scale = 2.0f / std::max(c.height(), 1e-6f);
    InstanceDesc d;
    d.clip = 0;
    d.time_seconds = 0.5 * p.clips[0].duration_seconds;
    d.scale = scale;
    d.position = -glm::dvec3(box.center()) * double(scale) + glm::dvec3(0, 1, 0);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    // From the front and from behind: assets face either way.
    for (double z : {4.0, -4.0}) {
      const Camera cam = Camera::lookAt({0.0, 1.0, z}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.9f,
                                        1.0f, 0.1f, 100.0f);
      ASSERT_TRUE(crowd.update(0.0, cam).isOk());
      InstanceBatcher batcher;
      ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
      std::vector<uint8_t> gpu, cpu;
      r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      DrawStats stats;
      ASSERT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, cam, &stats, DrawMode::kSkinned)
                      .isOk());
      ASSERT_TRUE(context_->readPixels(&gpu).isOk());
      r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      ASSERT_TRUE(r.drawCpuSkinned(CharacterId{}, crowd.view(), cam, &stats).isOk());
      ASSERT_TRUE(context_->readPixels(&cpu).isOk());
      size_t covered = 0;
      for (size_t i = 0; i < gpu.size(); i += 4)
        covered += gpu[i] != 51 || gpu[i + 1] != 64 || gpu[i + 2] != 77;
      EXPECT_GT(covered, gpu.size() / 4 / 50) << "z " << z << ": the character covers 2 % of the view";
      const Diff diff = compare(gpu, cpu, nullptr);
      EXPECT_LE(diff.share, kMaxDifferingShare) << "z " << z << " max " << diff.max_channel;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, MaterialsTest, allBackends(), backendTestName);
INSTANTIATE_TEST_SUITE_P(Backends, EsMaterialsTest, esBackends(), backendTestName);

}  // namespace
}  // namespace si
