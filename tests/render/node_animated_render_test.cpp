// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A file animated by its nodes (no skin; tests/gltf/node_animated_asset.h) draws on every path
// what the CPU emulation draws (drawCpuSkinned), over frames of its clip: its rigid parts are
// joints, so every skinning path takes them (issue "Any animated glTF becomes a crowd").
#include "gltf/node_animated_asset.h"
#include "render/render_fixture.h"
#include "render/skinning_paths.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using namespace test;

class NodeAnimatedRenderTest : public RenderTest {};

TEST_P(NodeAnimatedRenderTest, EveryPathDrawsWhatTheCpuEmulationDraws) {
  const std::string json = nodeAnimatedFile();
  Character c;
  ASSERT_TRUE(importGltfMemory(
                  Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()),
                  "", {}, &c, nullptr)
                  .isOk());
  BakedPalette palette;
  ASSERT_TRUE(bakePalette(c, BakeDesc(), &palette, nullptr).isOk());
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(c, palette, &id).isOk());
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
  cd.lod_count = 1;
  ASSERT_TRUE(crowd.init(cd).isOk());
  for (int k = 0; k < 3; ++k) {  // Three at different times of the clip.
    InstanceDesc d;
    d.position = glm::dvec3(-4.0 + 4.0 * k, 0.0, -3.0 * k);
    d.time_seconds = 0.3 * k;
    d.color = glm::u8vec4(uint8_t(120 + 60 * k), 200, 160, 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  }
  const Camera camera = Camera::lookAt({0.0, 6.0, 9.0}, {0.0, 0.5, -3.0}, glm::vec3(0, 1, 0), 1.0f,
                                       1.0f, 0.1f, 100.0f);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const glm::vec4 background(0.2f, 0.25f, 0.3f, 1.0f);
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(crowd.update(frame == 0 ? 0.0 : 0.2, camera).isOk());
    std::vector<uint8_t> emulated, empty;
    r.clear(background);
    ASSERT_TRUE(context_->readPixels(&empty).isOk());
    ASSERT_TRUE(r.drawCpuSkinned(id, crowd.view(), camera, nullptr).isOk());
    ASSERT_TRUE(context_->readPixels(&emulated).isOk());
    EXPECT_GT(compare(emulated, empty, nullptr).share, 0.01) << "the parts are in view";
    SCOPED_TRACE(testing::Message() << "frame " << frame);
    expectEveryPathDraws(r, id, crowd.view(), batcher, camera, background, *context_, emulated);
  }
  r.shutdown();
}

INSTANTIATE_TEST_SUITE_P(Backends, NodeAnimatedRenderTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
