// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Root motion on the GPU: clips baked in place, instances moved by the crowd. What both
// skinning paths draw for a travelling instance lies on the reference's travelling pose (the
// clip evaluated with its motion, placed where the instance started), within the bake's
// reported errors; and every drawing path draws the moving crowd alike.
#include "render/render_fixture.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"
#include "si/crowd/crowd_manager.h"

#include <utility>

#include <glm/gtc/matrix_transform.hpp>

namespace si {
namespace {

using namespace test;

struct Moving {
  Character character;
  BakedPalette palette;
  BakeReport report;
};

// The embedded character's travelling clips, baked at 30 Hz with the error report.
const Moving& moving() {
  static const Moving m = [] {
    Moving out;
    DefaultCharacterDesc d;
    d.moving_clips = true;
    if (!makeDefaultCharacter(d, &out.character).isOk()) std::abort();
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.clip_names = {"walk_forward", "walk_turn_left"};
    if (!bakePalette(out.character, bd, &out.palette, &out.report).isOk()) std::abort();
    return out;
  }();
  return m;
}

class RootMotionRenderTest : public RenderTest {
 protected:
  void makeMovingRenderer(Renderer* r) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(moving().character, moving().palette, &id).isOk());
  }
  void makeMovingCrowd(CrowdManager* crowd) {
    CrowdDesc cd;
    cd.palette = &moving().palette;
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    ASSERT_TRUE(crowd->init(cd).isOk());
  }
};

TEST_P(RootMotionRenderTest, BothSkinningPathsDrawTheReferencePath) {
  const Moving& m = moving();
  Renderer r;
  makeMovingRenderer(&r);
  CrowdManager crowd;
  makeMovingCrowd(&crowd);
  struct Start {
    uint32_t clip;
    glm::dvec3 position;
    glm::quat rotation;
    float scale;
  };
  const Start starts[] = {
      {0, {1.0, 0.0, -3.0}, glm::angleAxis(-0.5f, glm::vec3(0, 1, 0)), 1.2f},
      {1, {-1.5, 0.0, -4.0}, glm::angleAxis(2.0f, glm::vec3(0, 1, 0)), 0.8f}};
  std::vector<InstanceHandle> handles;
  for (const Start& s : starts) {
    InstanceDesc d;
    d.clip = s.clip;
    d.position = s.position;
    d.rotation = s.rotation;
    d.scale = s.scale;
    d.root_motion = true;
    handles.emplace_back();
    ASSERT_TRUE(crowd.add(d, &handles.back()).isOk());
  }
  const Camera camera = Camera::lookAt({0.0, 4.0, 8.0}, {0.0, 0.0, -4.0}, glm::vec3(0, 1, 0),
                                       1.2f, 1.0f, 0.1f, 200.0f);
  const int frames = 41;  // 1.37 s: past a loop boundary of both 1 s clips.
  for (int f = 0; f < frames; ++f) ASSERT_TRUE(crowd.update(1.0 / 30.0, camera).isOk());
  const double t = frames / 30.0;
  ASSERT_EQ(crowd.view().records().size(), 2u);
  for (size_t v = 0; v < crowd.view().visibleHandles().size(); ++v) {
    const size_t k = crowd.view().visibleHandles()[v].id == handles[0].id ? 0 : 1;
    const Start& s = starts[k];
    SCOPED_TRACE(m.palette.clips[s.clip].name);
    // The reference: the clip with its motion in the poses, whole cycles before this one.
    Clip travelling = m.character.clips[size_t(m.character.findClip(m.palette.clips[s.clip].name))];
    travelling.root_motion.extract = false;
    ReferencePose pose;
    ASSERT_TRUE(evaluatePose(m.character.skeleton, travelling, t, &pose).isOk());
    std::vector<glm::dvec3> reference(m.character.mesh.vertexCount());
    ASSERT_TRUE(skinVertices(m.character.mesh, pose.skinning, reference, {}, {}).isOk());
    const glm::dmat4 start = glm::translate(glm::dmat4(1.0), s.position) *
                             glm::mat4_cast(glm::dquat(s.rotation)) *
                             glm::scale(glm::dmat4(1.0), glm::dvec3(s.scale));
    const glm::dmat4 place =
        start * groundMotionMatrix(repeatGroundMotion(
                    summarizeRootMotion(m.palette.clips[s.clip]).whole_clip, uint64_t(t)));
    const InstanceRecord& rec = crowd.view().records()[v];
    const ClipErrorReport& e = m.report.clips[s.clip];
    const double bound = (e.max_error_units + e.root_motion_max_error_units) * s.scale + 2e-4;
    for (SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
      std::vector<glm::vec3> gpu;  // Model space, in place.
      ASSERT_TRUE(r.captureSkinnedPositions(CharacterId{}, rec, &gpu, path).isOk());
      ASSERT_EQ(gpu.size(), reference.size());
      double worst = 0.0;
      for (size_t i = 0; i < gpu.size(); ++i) {
        glm::dvec3 drawn = camera.position;  // The record's world rows are camera-relative.
        for (int row = 0; row < 3; ++row)
          drawn[row] += double(rec.world_rows[row][0]) * gpu[i].x +
                        double(rec.world_rows[row][1]) * gpu[i].y +
                        double(rec.world_rows[row][2]) * gpu[i].z + double(rec.world_rows[row][3]);
        worst = std::max(worst, glm::length(drawn - glm::dvec3(place * glm::dvec4(reference[i], 1.0))));
      }
      EXPECT_LE(worst, bound) << (path == SkinningPath::kCompute ? "compute" : "vertex shader");
    }
  }
  InstanceDesc walker;
  ASSERT_TRUE(crowd.get(handles[0], &walker).isOk());
  EXPECT_GT(glm::length(walker.position - starts[0].position), 2.0);  // It travelled.
}

// A crowd walking and turning, drawn after each of several updates by the instanced, compute,
// CPU-skinned and GPU-driven paths: the same images, and not the first frame's.
TEST_P(RootMotionRenderTest, EveryPathDrawsTheMovingCrowd) {
  Renderer r;
  makeMovingRenderer(&r);
  CrowdManager crowd;
  makeMovingCrowd(&crowd);
  std::vector<glm::dvec3> spots;
  for (int i = 0; i < 12; ++i) spots.push_back({(i % 4 - 1.5) * 2.0, 0.0, -2.0 - 2.5 * (i / 4)});
  RandomCrowdDesc rc;
  rc.positions = spots;
  rc.root_motion = true;
  ASSERT_TRUE(crowd.addRandom(rc, nullptr).isOk());
  const Camera camera = Camera::lookAt({0.0, 6.0, 7.0}, {0.0, 0.0, -5.0}, glm::vec3(0, 1, 0),
                                       1.2f, 1.0f, 0.1f, 200.0f);
  std::vector<uint8_t> first;
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(crowd.update(frame == 0 ? 0.0 : 0.4, camera).isOk());
    const std::vector<uint8_t> instanced = draw(r, crowd, camera, 0);
    const std::vector<uint8_t> compute = draw(r, crowd, camera, 0, false, nullptr, Path::kCompute);
    const std::vector<uint8_t> cpu = draw(r, crowd, camera, 0, false, nullptr, Path::kCpuSkinned);
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr,
                                     DrawMode::kComputeSkinned)
                    .isOk());
    std::vector<uint8_t> gpu_driven;
    ASSERT_TRUE(context_->readPixels(&gpu_driven).isOk());
    for (const std::vector<uint8_t>* other : {&compute, &cpu, &std::as_const(gpu_driven)})
      EXPECT_LE(compare(instanced, *other, nullptr).share, kMaxDifferingShare) << frame;
    if (frame == 0) first = instanced;
    else EXPECT_GT(compare(instanced, first, nullptr).share, 0.01) << frame;  // They moved.
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RootMotionRenderTest, test::allBackends(),
                         test::backendTestName);

}  // namespace
}  // namespace si
