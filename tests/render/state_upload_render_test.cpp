// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven uploads in proportion to change (RendererDesc::gpu_state_upload): over frames of
// moves, tints, removals, additions, crossfades, masks and overlays, uploading only what
// changed selects and draws what uploading everything does, and what the CPU path draws (with
// occlusion culling too), while the bytes uploaded follow the change.
#include <algorithm>
#include <cmath>

#include "render/far_crowd.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

// Lines at 20 and 60 units, wide hysteresis (16-24, 48-72 units): an instance's LOD there
// depends on where it came from.
CrowdDesc bandedCrowd(const BakedPalette& palette) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = 4;
  cd.lod_count = 3;
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = {20.0f, 60.0f};
  cd.lod_hysteresis_ratio = 0.2f;
  cd.max_distance_radii = -1.0f;
  return cd;
}

TEST_P(RenderTest, ChangedStateUploadsDrawWhatWholeUploadsDraw) {
  struct Drawer {
    GpuStateUpload upload;
    bool occlusion;
    Renderer renderer;
  };
  Drawer drawers[3] = {{GpuStateUpload::kChanged, false, {}},
                       {GpuStateUpload::kWhole, false, {}},
                       {GpuStateUpload::kChanged, true, {}}};
  for (Drawer& d : drawers) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    rd.measure_gpu_time = true;  // Reads back the selection's counts.
    rd.gpu_state_upload = d.upload;
    rd.gpu_occlusion_culling = d.occlusion;
    ASSERT_TRUE(d.renderer.init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(d.renderer.addCharacter(character(), palette(), &id).isOk());
  }
  CrowdManager crowd;
  const CrowdDesc cd = bandedCrowd(palette());
  ASSERT_TRUE(crowd.init(cd).isOk());
  const uint32_t clips = uint32_t(palette().clips.size());
  std::vector<InstanceHandle> handles;
  for (int row = 0; row < 15; ++row)
    for (int k = 0; k < 20; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k - 9.5) * 3.0, 0.0, -25.0 - 4.0 * row);
      d.clip = uint32_t(k + row) % clips;
      d.time_seconds = 0.05 * k;
      d.variation_mask = 1u | (uint32_t(k) << 1);
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
      handles.push_back(h);
    }
  {  // Last: 20 units from the camera, in the first band, at LOD 0 (it never left it). The
     // first removal moves it into the slot of an instance at LOD 1: where it sits, each view
     // must start over from its LOD (0), or the GPU goes on from the other's (1).
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, 4.0 - std::sqrt(20.0 * 20.0 - 16.0));
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    handles.push_back(h);
  }
  LayerMask arm;
  ASSERT_TRUE(buildLayerMask(character().skeleton, palette(), "arm", {"r_clavicle"}, &arm).isOk());
  uint32_t mask = 0;
  ASSERT_TRUE(crowd.addLayerMask(arm, &mask).isOk());
  const Camera camera = Camera::lookAt({0.0, 4.0, 4.0}, {0.0, 0.0, -30.0}, glm::vec3(0, 1, 0),
                                       1.0f, 1.0f, 0.1f, 300.0f);
  const uint64_t whole_bytes = uint64_t(handles.size()) * sizeof(GpuInstanceState);
  for (int frame = 0; frame < 7; ++frame) {
    SCOPED_TRACE(frame);
    // Changes 67 or more dense indices apart (closer runs are merged).
    if (frame == 1) {  // Moves and tints.
      for (int k = 0; k < 4; ++k)
        ASSERT_TRUE(crowd.setTransform(handles[k * 67], glm::dvec3(k - 2.0, 0.0, -6.0 - k),
                                       glm::quat(1, 0, 0, 0), 1.1f).isOk());
      for (int k = 0; k < 4; ++k)
        ASSERT_TRUE(crowd.setColor(handles[k * 67 + 1], glm::u8vec4(250, 40, 40, 255)).isOk());
    } else if (frame == 2) {  // Removals (the last instances move into the holes), additions.
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(crowd.remove(handles[k * 67 + 10]).isOk());
        handles[k * 67 + 10] = handles.back();
        handles.pop_back();
      }
      for (int k = 0; k < 2; ++k) {
        InstanceDesc d;
        d.position = glm::dvec3(k - 7.0, 0.0, -3.0);
        d.clip = uint32_t(k) % clips;
        InstanceHandle h;
        ASSERT_TRUE(crowd.add(d, &h).isOk());
        handles.push_back(h);
      }
    } else if (frame == 3) {  // Crossfades and masks.
      for (int k = 0; k < 4; ++k)
        ASSERT_TRUE(crowd.crossfade(handles[k * 67 + 3], uint32_t(k + 1) % clips, 0.4).isOk());
      for (int k = 0; k < 4; ++k)
        ASSERT_TRUE(crowd.setVariationMask(handles[k * 67 + 4], 1u).isOk());
    } else if (frame == 5) {  // The first overlays: the overlays uploaded whole.
      for (int k = 0; k < 4; ++k)
        ASSERT_TRUE(crowd.playOverlay(handles[k * 67 + 5], 1, mask, 1.0f, 0.0).isOk());
    } else if (frame == 6) {  // One more: only its instance.
      ASSERT_TRUE(crowd.playOverlay(handles[150], 1, mask, 0.6f, 0.0).isOk());
    }
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    std::vector<std::vector<uint8_t>> images;
    std::vector<std::vector<glm::uvec2>> selections;
    std::vector<DrawStats> stats(3);
    for (int d = 0; d < 3; ++d) {
      drawers[d].renderer.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      const Status s = drawers[d].renderer.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera,
                                                              &stats[size_t(d)]);
      ASSERT_TRUE(s.isOk()) << s.toString();
      images.emplace_back();
      ASSERT_TRUE(context_->readPixels(&images.back()).isOk());
      selections.emplace_back();
      ASSERT_TRUE(
          drawers[d].renderer.readGpuSelection(si::CharacterId{}, &selections.back()).isOk());
      std::sort(selections.back().begin(), selections.back().end(),
                [](const glm::uvec2& a, const glm::uvec2& b) {
                  return a.x != b.x ? a.x < b.x : a.y < b.y;
                });
    }
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    std::vector<glm::uvec2> cpu = cpuSelection(crowd);
    std::sort(cpu.begin(), cpu.end(), [](const glm::uvec2& a, const glm::uvec2& b) {
      return a.x != b.x ? a.x < b.x : a.y < b.y;
    });
    const std::vector<uint8_t> cpu_image = draw(drawers[0].renderer, crowd, camera, 0);
    EXPECT_EQ(selections[0], cpu);
    EXPECT_EQ(selections[1], cpu);
    for (int d = 0; d < 3; ++d) {
      const Diff diff = compare(images[size_t(d)], cpu_image, nullptr);
      EXPECT_LE(diff.share, 0.001) << d << ": max channel difference " << diff.max_channel;
    }
    // Bytes: everything at the first frame; a few runs after each change; none when nothing
    // changed; uploading whole, everything at every change.
    const uint64_t changed = stats[0].state_bytes_uploaded, whole = stats[1].state_bytes_uploaded;
    if (frame == 0) {
      EXPECT_EQ(changed, whole_bytes);
    } else if (frame == 4) {
      EXPECT_EQ(changed, 0u);
      EXPECT_EQ(whole, 0u);
    } else {
      EXPECT_GT(changed, 0u);
      EXPECT_LT(changed, whole / 2);
      EXPECT_GE(whole, uint64_t(crowd.size()) * sizeof(GpuInstanceState));
    }
    EXPECT_EQ(stats[2].state_bytes_uploaded, changed);
  }
}

// A spawn wave (instances added every frame) re-creates the GPU-driven buffers and uploads the
// whole state only when the crowd outgrows room made half as large again, not every frame: the
// other frames upload the instances added. The report's capacity shows the room.
TEST_P(RenderTest, ASpawnWaveUploadsWhatItAdds) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  const auto spawn = [&](uint32_t count) {
    std::vector<glm::dvec3> positions(count);
    for (uint32_t i = 0; i < count; ++i) positions[i] = {double(i % 50), 0.0, 20.0 + i / 50};
    RandomCrowdDesc rc;
    rc.positions = positions;
    ASSERT_TRUE(crowd.addRandom(rc, nullptr).isOk());
  };
  spawn(1000);
  uint32_t whole = 0;
  for (int frame = 0; frame < 20; ++frame) {
    if (frame > 0) spawn(10);
    ASSERT_TRUE(crowd.advance(1.0 / 60.0).isOk());
    DrawStats stats;
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), &stats).isOk());
    whole += stats.state_bytes_uploaded == uint64_t(crowd.size()) * sizeof(GpuInstanceState);
    if (frame > 1) {
      EXPECT_EQ(stats.state_bytes_uploaded, 10 * sizeof(GpuInstanceState)) << frame;
    }
  }
  // The first frame's (room for its 1000) and the second's (room for 1500: 1190 at the end).
  EXPECT_EQ(whole, 2u);
  GpuMemory m;
  ASSERT_TRUE(r.gpuMemory(&m).isOk());
  ASSERT_EQ(m.characters[0].crowds.size(), 1u);
  EXPECT_EQ(m.characters[0].crowds[0].capacity, 1500u);
  r.shutdown();
}

// Changes past one staged chunk (4 MiB: some 29,000 instances' state) go through a copy of the
// export; fewer are exported straight into the staging ring. Both draw what uploading whole
// draws: 40,000 instances (12 in view) recoloured and moved, all of them, then 200 of them.
TEST_P(RenderTest, ChangesInOneChunkOrPastItDrawWhatWholeUploadsDraw) {
  Renderer changed_renderer, whole_renderer;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  makeRenderer(&changed_renderer, 0, PaletteFormat::kMatrix3x4F32, &rd);
  rd.gpu_state_upload = GpuStateUpload::kWhole;
  makeRenderer(&whole_renderer, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager crowd;
  makeCrowd(&crowd);
  const std::vector<glm::dvec3> positions = twelveInViewOfForty();
  RandomCrowdDesc rc;
  rc.positions = positions;
  std::vector<InstanceHandle> handles;
  ASSERT_TRUE(crowd.addRandom(rc, &handles).isOk());
  const auto drawn = [&](Renderer& r, DrawStats* stats) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    EXPECT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), closeCamera(), stats).isOk());
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  };
  std::vector<uint8_t> before;
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    // Step 1 changes every instance (past one chunk), step 2 every 200th (in one).
    const uint32_t every = step == 1 ? 1 : 200;
    if (step > 0)
      for (uint32_t i = 0; i < handles.size(); i += every) {
        const glm::dvec3 p = positions[i] + glm::dvec3(0.15 * step, 0.0, 0.0);
        ASSERT_TRUE(crowd.setTransform(handles[i], p, glm::quat(1, 0, 0, 0), 1.0f).isOk());
        ASSERT_TRUE(crowd.setColor(handles[i], glm::u8vec4(60 * step, 200, 90, 255)).isOk());
      }
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    DrawStats changed;
    const std::vector<uint8_t> image = drawn(changed_renderer, &changed);
    const std::vector<uint8_t> reference = drawn(whole_renderer, nullptr);
    EXPECT_EQ(compare(image, reference, nullptr).share, 0.0);
    if (step > 0) {
      EXPECT_GT(compare(image, before, nullptr).share, 0.0) << "the change is seen";
      EXPECT_EQ(changed.state_bytes_uploaded,
                uint64_t(step == 1 ? 40000 : 200) * sizeof(GpuInstanceState));
    }
    before = image;
  }
  changed_renderer.shutdown();
  whole_renderer.shutdown();
}

// Churn with several views: each view starts its LODs over where other instances sit. A view
// that selects on the CPU is seeded there from its CPU LODs; views that never selected on the
// CPU start at LOD 0, which the culling pass does by itself (DrawStats::view_seed_bytes 0).
// Every view selects what uploading whole (seeding every view everywhere) selects.
TEST_P(RenderTest, ViewsThatNeverSelectedNeedNoSeed) {
  Renderer changed_renderer, whole_renderer;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.measure_gpu_time = true;
  makeRenderer(&changed_renderer, 0, PaletteFormat::kMatrix3x4F32, &rd);
  rd.gpu_state_upload = GpuStateUpload::kWhole;
  makeRenderer(&whole_renderer, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager crowd;
  makeCrowd(&crowd);
  std::vector<InstanceHandle> handles;
  for (int i = 0; i < 400; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3(double(i % 20) * 2.0 - 19.0, 0.0, -4.0 - double(i / 20) * 4.0);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    handles.push_back(h);
  }
  CrowdView first, second, selecting;
  ASSERT_TRUE(first.init(crowd).isOk());
  ASSERT_TRUE(second.init(crowd).isOk());
  ASSERT_TRUE(selecting.init(crowd).isOk());
  const Camera cameras[4] = {
      Camera::lookAt({0, 4, 4}, {0, 0, -30}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f, 300.0f),
      Camera::lookAt({-10, 6, 0}, {0, 0, -40}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f, 300.0f),
      Camera::lookAt({10, 6, -90}, {0, 0, -40}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f, 300.0f),
      Camera::lookAt({0, 8, -100}, {0, 0, -20}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f, 300.0f)};
  const CrowdView* views[4] = {&crowd.view(), &first, &second, &selecting};
  const auto sorted = [](std::vector<glm::uvec2> v) {
    std::sort(v.begin(), v.end(), [](const glm::uvec2& a, const glm::uvec2& b) {
      return a.x != b.x ? a.x < b.x : a.y < b.y;
    });
    return v;
  };
  for (int frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE(frame);
    if (frame > 0) {  // Removals scattered over the crowd (the last instances move there), then
                      // as many added at the near end.
      for (int k = 0; k < 12; ++k) {
        ASSERT_TRUE(crowd.remove(handles[size_t(k * 29 + frame)]).isOk());
        handles[size_t(k * 29 + frame)] = handles.back();
        handles.pop_back();
      }
      for (int k = 0; k < 12; ++k) {
        InstanceDesc d;
        d.position = glm::dvec3(double(k) * 2.0 - 11.0, 0.0, -2.0 - double(frame));
        InstanceHandle h;
        ASSERT_TRUE(crowd.add(d, &h).isOk());
        handles.push_back(h);
      }
    }
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    ASSERT_TRUE(selecting.select(cameras[3]).isOk());
    for (int v = 0; v < 4; ++v) {
      SCOPED_TRACE(v);
      DrawStats changed, whole;
      std::vector<glm::uvec2> changed_selection, whole_selection;
      ASSERT_TRUE(
          changed_renderer.drawCrowdGpuCulled(CharacterId{}, *views[v], cameras[v], &changed)
              .isOk());
      ASSERT_TRUE(changed_renderer.readGpuSelection(CharacterId{}, &changed_selection).isOk());
      ASSERT_TRUE(
          whole_renderer.drawCrowdGpuCulled(CharacterId{}, *views[v], cameras[v], &whole).isOk());
      ASSERT_TRUE(whole_renderer.readGpuSelection(CharacterId{}, &whole_selection).isOk());
      EXPECT_FALSE(changed_selection.empty());
      EXPECT_EQ(sorted(changed_selection), sorted(whole_selection));
      if (frame == 0) continue;
      // Churn: 24 indices hold other instances, 8 bytes of seed each for the view that selects
      // (the uploads before were whole: the first frame's).
      const uint64_t seed = 24 * sizeof(glm::uvec2);
      EXPECT_EQ(changed.view_seed_bytes, v == 3 ? seed : 0u);
      EXPECT_EQ(whole.view_seed_bytes, uint64_t(crowd.size()) * sizeof(glm::uvec2));
    }
  }
  changed_renderer.shutdown();
  whole_renderer.shutdown();
}

// A view that never selected on the CPU, unseeded: where a removal moves an instance at LOD 0
// (inside the hysteresis band round the first line) into the place of one at LOD 1, the
// culling pass starts the place over (LOD 0) as seeding it would; going on from the other's
// LOD would keep LOD 1 inside the band.
TEST_P(RenderTest, AnUnseededViewStartsOverWhereAnotherInstanceSits) {
  {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    Renderer renderer;
    makeRenderer(&renderer, 0, PaletteFormat::kMatrix3x4F32, &rd);
    CrowdManager crowd;
    const CrowdDesc cd = bandedCrowd(palette());
    ASSERT_TRUE(crowd.init(cd).isOk());
    // Dense 0: 40 units away (LOD 1); 1: 6 units (LOD 0); 2: 20 units, in the band (LOD 0).
    const Camera camera = Camera::lookAt({0.0, 0.0, 0.0}, {0.0, 0.0, -30.0}, glm::vec3(0, 1, 0),
                                         1.2f, 1.0f, 0.1f, 300.0f);
    InstanceHandle far_one, near_one, banded;
    InstanceDesc d;
    d.position = glm::dvec3(0.0, 0.0, -40.0);
    ASSERT_TRUE(crowd.add(d, &far_one).isOk());
    d.position = glm::dvec3(-2.0, 0.0, -6.0);
    ASSERT_TRUE(crowd.add(d, &near_one).isOk());
    d.position = glm::dvec3(3.0, 0.0, -std::sqrt(400.0 - 9.0));
    ASSERT_TRUE(crowd.add(d, &banded).isOk());
    CrowdView never;
    ASSERT_TRUE(never.init(crowd).isOk());
    const auto lodOf = [&](uint32_t dense) {
      std::vector<glm::uvec2> selection;
      EXPECT_TRUE(renderer.readGpuSelection(CharacterId{}, &selection).isOk());
      for (const glm::uvec2& s : selection)
        if (s.x == dense) return int(s.y);
      return -1;
    };
    DrawStats st;
    for (int frame = 0; frame < 2; ++frame) {
      ASSERT_TRUE(crowd.advance(0.1).isOk());
      ASSERT_TRUE(renderer.drawCrowdGpuCulled(CharacterId{}, never, camera, &st).isOk());
    }
    ASSERT_EQ(lodOf(0), 1);
    ASSERT_EQ(lodOf(2), 0);
    ASSERT_TRUE(crowd.remove(far_one).isOk());  // The banded instance moves to dense 0.
    ASSERT_TRUE(crowd.advance(0.1).isOk());
    ASSERT_TRUE(renderer.drawCrowdGpuCulled(CharacterId{}, never, camera, &st).isOk());
    EXPECT_EQ(st.view_seed_bytes, 0u);
    EXPECT_EQ(lodOf(0), 0) << "went on from the removed instance's LOD";
    EXPECT_EQ(lodOf(1), 0);
    renderer.shutdown();
  }
}

}  // namespace
}  // namespace si
