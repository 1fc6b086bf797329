// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What a frame is for motion vectors, the same on every path: one crowd step (update or advance,
// dt 0 included). A held clock, two draws in one step and a teleport, drawn by
// drawCrowd and by the GPU-driven path, each against the engine program's motion from the
// crowd's previous records. MotionVectorTest's instantiation (motion_vectors_render_test.cpp)
// runs it.
#include "render/motion_vector_fixture.h"

namespace si {
namespace test {

TEST_P(MotionVectorTest, AFrameIsACrowdStepOnEveryPath) {
  struct Drawer {
    const char* name;
    bool gpu_driven;
    DrawMode mode;
    std::unique_ptr<Renderer> renderer;
    InstanceBatcher batcher;
  };
  std::vector<Drawer> paths;
  for (const bool gpu_driven : {false, true})
    for (const DrawMode mode : {DrawMode::kSkinned, DrawMode::kComputeSkinned}) {
      paths.push_back({gpu_driven ? (mode == DrawMode::kSkinned ? "GPU-driven, vertex shader"
                                                                : "GPU-driven, pre-skinned")
                                  : (mode == DrawMode::kSkinned ? "drawCrowd, vertex shader"
                                                                : "drawCrowd, compute"),
                       gpu_driven, mode, std::make_unique<Renderer>(), InstanceBatcher()});
      RendererDesc rd;
      rd.motion_vectors = true;
      rd.gpu_driven_ring_bytes = 4u << 20;             // Plenty for 16 instances.
      rd.skinning_path = SkinningPath::kVertexShader;  // The draws name their mode: no timing.
      makeRenderer(paths.back().renderer.get(), 0, PaletteFormat::kMatrix3x4F32, &rd);
      ASSERT_TRUE(paths.back().batcher.init(paths.back().renderer->batchLimits()).isOk());
    }
  // Each path draws the crowd's last step with its update camera; `check` compares the motion
  // with the engine program's (its previous records, its previous update camera).
  const auto draw = [&](Drawer& p) {
    target_.clear(glm::vec4(0.0f));
    const Camera& c = crowd_.view().camera();
    const Status s =
        p.gpu_driven
            ? p.renderer->drawCrowdGpuCulled(CharacterId{}, crowd_.view(), c, nullptr, p.mode)
            : p.renderer->drawCrowd(CharacterId{}, crowd_.view(), p.batcher, c, nullptr, p.mode);
    ASSERT_TRUE(s.isOk()) << p.name << ": " << s.toString();
  };
  const auto check = [&](const char* step, int draws) {
    target_.clear(glm::vec4(0.0f));
    drawEngine(false);
    const std::vector<glm::vec2> expected = motions();
    const std::vector<float> expected_depth = depths();
    const std::vector<uint8_t> expected_color = colors();
    MotionSummary engine;
    ASSERT_TRUE(target_.summarize(&engine).isOk());
    EXPECT_GT(engine.max_pixels, 0.5) << step << ": the camera moves";
    for (Drawer& p : paths) {
      std::vector<glm::vec2> first;
      for (int d = 0; d < draws; ++d) {
        SCOPED_TRACE(std::string(step) + ", " + p.name + ", draw " + std::to_string(d + 1));
        draw(p);
        const std::vector<glm::vec2> motion = motions();
        const std::vector<float> depth = depths();
        expectMotion(motion, depth, expected, expected_depth, expected_color);
        if (d == 0)
          first = motion;
        else
          EXPECT_TRUE(motion == first) << "a second draw in one step drew other motion";
      }
    }
  };
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(1)).isOk());
  for (Drawer& p : paths) draw(p);
  nextFrame();  // Moving: crossfades, a cut, a speed change, the camera.
  check("moving", 1);
  // The clock held (a pause, photo mode): steps of dt 0 with the camera still moving. The
  // motion is the camera's between the last two steps, every instance still; each step drawn
  // twice (a depth pre-pass and the colour draw, say) draws the same motion twice.
  ASSERT_TRUE(crowd_.update(0.0, camera(3)).isOk());
  check("held once", 2);
  ASSERT_TRUE(crowd_.update(0.0, camera(4)).isOk());
  check("held twice", 2);
  // A teleport: the instance placed by setTransform gets the camera's motion only.
  InstanceDesc moved;
  ASSERT_TRUE(crowd_.get(handles_[5], &moved).isOk());
  ASSERT_TRUE(crowd_
                  .setTransform(handles_[5], moved.position + glm::dvec3(0.6, 0.0, -0.4),
                                moved.rotation, moved.scale)
                  .isOk());
  ASSERT_TRUE(crowd_.update(1.0 / 30.0, camera(5)).isOk());
  check("teleported", 1);
  for (Drawer& p : paths) p.renderer->shutdown();
}

}  // namespace test
}  // namespace si
