// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling selects exactly what the CPU selects, on random scenes and on the
// boundaries, and draws the same image.
#include <glad/gl.h>

#include <optional>
#include <random>

#include "render/render_fixture.h"
#include "si/core/lod_error.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, GpuCullingSelectsWhatTheCpuSelects) {
  Renderer r;
  makeRenderer(&r);
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Scenes: the technique's distance lines; with animation LOD; with wide hysteresis; and
  // screen-space-error LOD (the character's measured errors, a 1.5-pixel budget).
  for (int scene = 0; scene < 4; ++scene) {
    SCOPED_TRACE(scene);
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    cd.animation_lod_start = scene == 1 ? 1 : 0;
    cd.lod_hysteresis_ratio = scene == 2 ? 0.2f : 0.0f;
    if (scene == 3) {
      cd.lod_mode = LodMode::kScreenError;
      cd.pixel_error_budget = 1.5f;
      ASSERT_TRUE(lodErrorsByLevel(character().mesh, &cd.lod_errors_units).isOk());
    }
    CrowdManager crowd;
    ASSERT_TRUE(crowd.init(cd).isOk());
    const uint32_t clips = uint32_t(palette().clips.size());
    std::vector<InstanceHandle> handles;
    for (int i = 0; i < 3000; ++i) {
      InstanceDesc d;
      d.position = glm::dvec3(u(rng) * 300.0 - 150.0, u(rng) * 4.0 - 2.0, u(rng) * 300.0 - 150.0);
      d.rotation = glm::normalize(glm::quat(float(u(rng) - 0.5), float(u(rng) - 0.5),
                                            float(u(rng) - 0.5), float(u(rng) - 0.5)));
      d.scale = float(0.5 + 1.5 * u(rng));
      d.clip = uint32_t(u(rng) * clips) % clips;
      d.time_seconds = u(rng) * 3.0;
      d.speed = float(u(rng) * 2.0);
      d.loop_mode = u(rng) < 0.3 ? LoopMode::kOnce : LoopMode::kDefault;
      d.variation_mask = uint32_t(u(rng) * 16.0) | 1u;
      InstanceHandle h;
      ASSERT_TRUE(crowd.add(d, &h).isOk());
      if (u(rng) < 0.2) {
        ASSERT_TRUE(crowd.crossfade(h, (d.clip + 1) % clips, 0.05 + u(rng) * 0.5).isOk());
      }
      handles.push_back(h);
    }
    uint32_t compared = 0, coarse = 0;
    for (int frame = 0; frame < 8; ++frame) {
      SCOPED_TRACE(frame);
      if (frame == 4) {  // Change state between frames: moves, new crossfades.
        for (int k = 0; k < 200; ++k) {
          const InstanceHandle h = handles[size_t(u(rng) * handles.size()) % handles.size()];
          const glm::dvec3 to(u(rng) * 60.0 - 30.0, 0.0, u(rng) * 60.0 - 30.0);
          ASSERT_TRUE(crowd.setTransform(h, to, glm::quat(1, 0, 0, 0), 1.0f).isOk());
          ASSERT_TRUE(crowd.crossfade(h, uint32_t(u(rng) * clips) % clips, 0.3).isOk());
        }
      }
      const glm::dvec3 eye(u(rng) * 200.0 - 100.0, 1.0 + u(rng) * 20.0, u(rng) * 200.0 - 100.0);
      const glm::dvec3 target(u(rng) * 100.0 - 50.0, 0.0, u(rng) * 100.0 - 50.0);
      Camera camera = Camera::lookAt(eye, target, glm::vec3(0, 1, 0), float(0.6 + u(rng)), 1.0f,
                                     0.1f, 1000.0f);
      camera.viewport_height_pixels = float(200.0 + u(rng) * 2000.0);
      // The clock moves first; the GPU selects from the LODs of the previous frame, then the
      // CPU does the same at the same clock.
      ASSERT_TRUE(crowd.advance(0.11).isOk());
      DrawStats stats;
      r.clear(glm::vec4(0.0f));
      ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, &stats).isOk());
      std::vector<glm::uvec2> gpu;
      ASSERT_TRUE(r.readGpuSelection(CharacterId{}, &gpu).isOk());
      ASSERT_TRUE(crowd.update(0.0, camera).isOk());
      std::vector<glm::uvec2> cpu = cpuSelection(crowd);
      const auto order = [](const glm::uvec2& a, const glm::uvec2& b) {
        return a.x != b.x ? a.x < b.x : a.y < b.y;
      };
      std::sort(gpu.begin(), gpu.end(), order);
      std::sort(cpu.begin(), cpu.end(), order);
      ASSERT_EQ(gpu.size(), cpu.size());
      size_t mismatches = 0;
      for (size_t k = 0; k < cpu.size(); ++k) mismatches += gpu[k] != cpu[k];
      EXPECT_EQ(mismatches, 0u);
      compared += uint32_t(cpu.size());
      for (const glm::uvec2& v : cpu) coarse += v.y > 0;
      std::printf("[ gpu cull ] scene %d frame %d: %zu visible, %zu mismatches\n", scene, frame,
                  cpu.size(), mismatches);
      EXPECT_EQ(crowd.view().stats().visible, cpu.size());
    }
    EXPECT_GT(compared, 500u);  // The scenes do show instances,
    EXPECT_GT(coarse, 100u);    // at more than one LOD.
  }
}

// The hard cases for "exactly": instances within a few ulps of the far line, of each LOD line
// (both hysteresis edges) and of each side plane of the frustum, all of them selected the same.
TEST_P(RenderTest, GpuCullingAgreesOnTheBoundaries) {
  Renderer r;
  makeRenderer(&r);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = 3;
  cd.lod_hysteresis_ratio = 0.1f;
  CrowdManager crowd;
  ASSERT_TRUE(crowd.init(cd).isOk());
  const Camera camera = Camera::lookAt({0.5, 1.5, 0.25}, {0.5, 1.0, -50.0}, glm::vec3(0, 1, 0),
                                       1.1f, 1.3f, 0.1f, 2000.0f);
  const CullParams p = CrowdExport::cullParams(crowd.view(), camera);
  const BakedClip& clip = palette().clips[0];
  const glm::dvec3 sphere_center(clip.bounding_sphere.center);
  std::vector<double> distances = {p.max_distance_radii * p.radius};
  for (uint32_t l = 0; l + 1 < p.lod_count; ++l) {
    distances.push_back(p.lod_lines[l] * (1.0 + p.hysteresis) * p.radius);
    distances.push_back(p.lod_lines[l] * (1.0 - p.hysteresis) * p.radius);
  }
  const auto add = [&](const glm::dvec3& position) {
    InstanceDesc d;
    d.position = position;
    d.clip = 0;
    d.speed = 0.0f;
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  };
  for (int i = 0; i < 4000; ++i) {
    // Distance boundaries, straight ahead within a few degrees.
    const double line = distances[size_t(i) % distances.size()];
    const double a = (u(rng) - 0.5) * 0.3;
    const double e = (u(rng) - 0.5) * 6e-7;
    add(camera.position + glm::dvec3(std::sin(a), 0.0, -std::cos(a)) * line * (1.0 + e));
  }
  for (int i = 0; i < 4000; ++i) {
    // Side-plane boundaries: the clip's sphere just touching a plane from outside or inside.
    const glm::vec4 plane = p.planes[size_t(i) % 4];
    const glm::dvec3 n(plane);
    glm::dvec3 c(u(rng) * 60.0 - 30.0, u(rng) * 20.0 - 10.0, -5.0 - u(rng) * 60.0);
    const double target = -double(clip.bounding_sphere.radius) * (1.0 + (u(rng) - 0.5) * 6e-7);
    c += n * (target - (glm::dot(n, c) + double(plane.w)));
    add(camera.position + c - sphere_center);
  }
  size_t straddling = 0;
  for (int frame = 0; frame < 2; ++frame) {
    ASSERT_TRUE(crowd.advance(0.0).isOk());
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, nullptr).isOk());
    std::vector<glm::uvec2> gpu;
    ASSERT_TRUE(r.readGpuSelection(CharacterId{}, &gpu).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera).isOk());
    const size_t n = crowd.size();
    std::vector<int> gpu_lod(n, -1), cpu_lod(n, -1);
    for (const glm::uvec2& g : gpu) gpu_lod[g.x] = int(g.y);
    for (const glm::uvec2& c : cpuSelection(crowd)) cpu_lod[c.x] = int(c.y);
    size_t mismatches = 0, visible = 0;
    for (size_t i = 0; i < n; ++i) {
      mismatches += gpu_lod[i] != cpu_lod[i];
      visible += cpu_lod[i] >= 0;
    }
    std::printf("[ gpu cull ] boundaries, frame %d: %zu of %zu visible, %zu mismatches\n", frame,
                visible, n, mismatches);
    EXPECT_EQ(mismatches, 0u);
    straddling = visible;
  }
  // Both sides of the boundaries are populated: some culled, some not.
  EXPECT_GT(straddling, 1000u);
  EXPECT_LT(straddling, 7000u);
}

// What the GPU-culled path draws equals the CPU path's image, with the same triangles.
TEST_P(RenderTest, GpuCulledDrawEqualsTheCpuPath) {
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.measure_gpu_time = true;  // Also reads back the visible count and triangles.
  // A crowd drawn by the GPU-culled path, then updated on the CPU and drawn by the CPU path;
  // with a cubic palette the GPU writes the interval modes into the records as the CPU does.
  // The linear renderer goes on below.
  Renderer renderers[2];
  const InterpolationChoice interpolations[2] = {InterpolationChoice::kCubic,
                                                 InterpolationChoice::kLinear};
  DrawStats gpu_stats;
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(interpolationChoiceName(interpolations[k]));
    Renderer& renderer = renderers[k];
    makeRenderer(&renderer, 0, PaletteFormat::kMatrix3x4F32, &rd, interpolations[k]);
    CrowdManager crowd;
    makeCrowd(&crowd, PaletteFormat::kMatrix3x4F32, interpolations[k]);
    populateLodCrowd(&crowd);
    addFadingCharacter(&crowd);
    ASSERT_TRUE(crowd.advance(0.3).isOk());
    renderer.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(
        renderer.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &gpu_stats).isOk());
    std::vector<uint8_t> gpu_image;
    ASSERT_TRUE(context_->readPixels(&gpu_image).isOk());
    ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
    DrawStats cpu_stats;
    const std::vector<uint8_t> cpu_image = draw(renderer, crowd, lodCamera(), 0, false, &cpu_stats);
    const Diff diff = compare(gpu_image, cpu_image, nullptr);
    EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
    EXPECT_EQ(gpu_stats.draw_calls, 1u);  // One multi-draw.
    EXPECT_EQ(gpu_stats.vertex_shader_instances, gpu_stats.instances);  // No pre-skinning.
    EXPECT_EQ(gpu_stats.skinned_vertices, 0u);
    EXPECT_EQ(gpu_stats.gpu_visible, crowd.view().stats().visible);
    EXPECT_EQ(gpu_stats.triangles, cpu_stats.triangles);
    EXPECT_EQ(gpu_stats.instances, cpu_stats.instances);
  }
  Renderer& r = renderers[1];
  // A new crowd of the same size where the last one was (same address): its own state is
  // uploaded and drawn, not the old one's.
  std::optional<CrowdManager> reused;
  for (int k = 0; k < 2; ++k) {
    reused.emplace();
    CrowdDesc rd2;
    rd2.palette = &palette();
    rd2.sub_mesh_count = 4;
    rd2.lod_count = 3;
    ASSERT_TRUE(reused->init(rd2).isOk());
    for (int i = 0; i < 50; ++i) {
      InstanceDesc one;
      one.position = glm::dvec3(i % 10 - 5.0, 0.0, k == 0 ? -8.0 - i / 10 : 500.0);  // k 1: out of view
      InstanceHandle h;
      ASSERT_TRUE(reused->add(one, &h).isOk());
    }
    ASSERT_TRUE(
        r.drawCrowdGpuCulled(si::CharacterId{}, reused->view(), lodCamera(), &gpu_stats).isOk());
    ASSERT_TRUE(reused->update(0.0, lodCamera()).isOk());
    EXPECT_EQ(gpu_stats.gpu_visible, reused->view().stats().visible) << k;
  }
  EXPECT_EQ(gpu_stats.gpu_visible, 0u);
  // A crowd with another palette is refused.
  CrowdManager other;
  CrowdDesc od;
  od.palette = &palette(PaletteFormat::kMatrix3x4F16);
  od.sub_mesh_count = 4;
  od.lod_count = 3;
  ASSERT_TRUE(other.init(od).isOk());
  EXPECT_EQ(r.drawCrowdGpuCulled(si::CharacterId{}, other.view(), lodCamera(), &gpu_stats).code(),
            StatusCode::kInvalidArgument);
}

// The GPU-driven path end to end: GPU culling and LOD selection, an indirect compute dispatch
// that pre-skins every bucket's vertices, and one indirect multi-draw of them. Its image equals
// the CPU-selected compute path's; with a ring too small for the frame, the instances past it
// are drawn with vertex-shader skinning and the image is still the same.
TEST_P(RenderTest, GpuDrivenComputePathEqualsTheCpuComputePath) {
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  addFadingCharacter(&crowd);
  ASSERT_TRUE(crowd.advance(0.3).isOk());
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  std::vector<uint8_t> cpu_image;
  DrawStats cpu_stats;
  {
    Renderer r;
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kCompute;
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    cpu_image = draw(r, crowd, lodCamera(), 0, false, &cpu_stats, Path::kCompute);
  }
  ASSERT_GT(cpu_stats.skinned_vertices, 0u);
  // A full ring (the default) and one that holds about a third of the frame's vertices.
  for (const uint64_t ring_bytes : {uint64_t(0), cpu_stats.skinned_vertices * 16 / 3}) {
    SCOPED_TRACE(ring_bytes);
    Renderer r;
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kCompute;
    rd.measure_gpu_time = true;  // Reads back the counts.
    rd.gpu_driven_ring_bytes = ring_bytes;
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats gpu_stats;
    const Status s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(),
                                          &gpu_stats);  // kDefault: kCompute.
    ASSERT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> gpu_image;
    ASSERT_TRUE(context_->readPixels(&gpu_image).isOk());
    const Diff diff = compare(gpu_image, cpu_image, nullptr);
    EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
    EXPECT_EQ(gpu_stats.gpu_visible, crowd.view().stats().visible);
    EXPECT_EQ(gpu_stats.triangles, cpu_stats.triangles);
    EXPECT_EQ(gpu_stats.instances, cpu_stats.instances);
    if (ring_bytes == 0) {
      EXPECT_EQ(gpu_stats.skinned_vertices, cpu_stats.skinned_vertices);
      EXPECT_EQ(gpu_stats.vertex_shader_instances, 0u);
    } else {
      EXPECT_LE(gpu_stats.skinned_vertices * 16, ring_bytes);
      EXPECT_GT(gpu_stats.skinned_vertices, 0u);
      EXPECT_GT(gpu_stats.vertex_shader_instances, 0u);
      EXPECT_LT(gpu_stats.vertex_shader_instances, gpu_stats.instances);
    }
    // Forcing vertex-shader skinning on the same renderer draws the same image.
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    ASSERT_TRUE(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &gpu_stats,
                                     DrawMode::kSkinned)
                    .isOk());
    std::vector<uint8_t> vs_image;
    ASSERT_TRUE(context_->readPixels(&vs_image).isOk());
    EXPECT_LE(compare(vs_image, cpu_image, nullptr).share, 0.001);
    EXPECT_EQ(gpu_stats.skinned_vertices, 0u);
    EXPECT_EQ(gpu_stats.vertex_shader_instances, gpu_stats.instances);
  }
  // kRigid is refused (kDepthOnly draws: gpu_views_render_test.cpp).
  Renderer r;
  makeRenderer(&r);
  EXPECT_EQ(
      r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), nullptr, DrawMode::kRigid)
          .code(),
      StatusCode::kInvalidArgument);
}

// Two-phase occlusion culling: a dense wall of characters in front of a crowd. Every frame's
// image equals the one drawn without occlusion culling. Frame 0 has no history (phase 1 draws
// nothing, phase 2 everything); frame 1's phase 1 draws all of it and phase 2 learns what is
// hidden; from frame 2 on, the crowd hidden behind the wall is not drawn. With pre-skinning
// and without.
TEST_P(RenderTest, GpuOcclusionCullingDrawsTheSameImageWithFewerTriangles) {
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
  populateWallCrowd(&crowd);
  const Camera camera = wallCamera();
  for (const SkinningPath path : {SkinningPath::kVertexShader, SkinningPath::kCompute}) {
    SCOPED_TRACE(skinningPathName(path));
    Renderer plain, occluding;
    RendererDesc rd;
    rd.skinning_path = path;
    rd.measure_gpu_time = true;  // Reads back the counts.
    makeRenderer(&plain, 0, PaletteFormat::kMatrix3x4F32, &rd);
    rd.gpu_occlusion_culling = true;
    makeRenderer(&occluding, 0, PaletteFormat::kMatrix3x4F32, &rd);
    for (int frame = 0; frame < 4; ++frame) {
      SCOPED_TRACE(frame);
      ASSERT_TRUE(crowd.advance(frame == 0 ? 0.0 : 1.0 / 30.0).isOk());
      DrawStats all, culled;
      plain.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      ASSERT_TRUE(plain.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, &all).isOk());
      std::vector<uint8_t> expected, actual;
      ASSERT_TRUE(context_->readPixels(&expected).isOk());
      occluding.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      const Status s = occluding.drawCrowdGpuCulled(CharacterId{}, crowd.view(), camera, &culled);
      ASSERT_TRUE(s.isOk()) << s.toString();
      ASSERT_TRUE(context_->readPixels(&actual).isOk());
      const Diff diff = compare(actual, expected, nullptr);
      EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
      EXPECT_EQ(culled.draw_calls, all.draw_calls * 2);  // Two phases.
      std::printf("[ occlusion] %s frame %d: %llu of %llu triangles, %u of %u instances\n",
                  skinningPathName(path), frame, static_cast<unsigned long long>(culled.triangles),
                  static_cast<unsigned long long>(all.triangles), culled.gpu_visible,
                  all.gpu_visible);
      if (frame < 2) {
        EXPECT_EQ(culled.triangles, all.triangles);
      } else {
        EXPECT_LT(culled.triangles, all.triangles);
        EXPECT_LT(culled.gpu_visible * 2, all.gpu_visible);  // Most of the crowd is hidden.
        EXPECT_GE(culled.gpu_visible, 40u);                  // The wall's front row is drawn.
      }
    }
  }
}

// A multisampled target (4 samples): occlusion culling copies its depth with the samples and
// takes each pixel's farthest, instead of refusing the target (it did: "needs a single-sampled
// depth buffer", an empty frame). The resolved image equals the one drawn without occlusion
// culling on the same target, the crowd behind the wall is culled, and the host's multisample
// texture on unit 0 is back afterwards.
TEST_P(RenderTest, GpuOcclusionCullingOnAMultisampledTarget) {
  GLint max_samples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (max_samples < 4) GTEST_SKIP() << "GL_MAX_SAMPLES " << max_samples;
  GLuint fbo[2] = {0, 0}, buffers[3] = {0, 0, 0}, host_texture = 0;
  glCreateFramebuffers(2, fbo);
  glCreateRenderbuffers(3, buffers);
  glNamedRenderbufferStorageMultisample(buffers[0], 4, GL_RGBA8, GLsizei(kSize), GLsizei(kSize));
  glNamedRenderbufferStorageMultisample(buffers[1], 4, GL_DEPTH_COMPONENT24, GLsizei(kSize),
                                        GLsizei(kSize));
  glNamedRenderbufferStorage(buffers[2], GL_RGBA8, GLsizei(kSize), GLsizei(kSize));
  glNamedFramebufferRenderbuffer(fbo[0], GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
  glNamedFramebufferRenderbuffer(fbo[0], GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
  glNamedFramebufferRenderbuffer(fbo[1], GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[2]);
  ASSERT_EQ(glCheckNamedFramebufferStatus(fbo[0], GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
  glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &host_texture);
  glTextureStorage2DMultisample(host_texture, 2, GL_RGBA8, 4, 4, GL_TRUE);
  glBindTextureUnit(0, host_texture);
  GLint previous = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo[0]);
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
  populateWallCrowd(&crowd);
  const auto frames = [&](bool occlusion, DrawStats* st) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    rd.gpu_occlusion_culling = occlusion;
    rd.measure_gpu_time = true;
    Renderer r;
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    for (int frame = 0; frame < 3; ++frame) {
      r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      const Status s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), wallCamera(), st);
      EXPECT_TRUE(s.isOk()) << s.toString();
    }
    glBlitNamedFramebuffer(fbo[0], fbo[1], 0, 0, GLsizei(kSize), GLsizei(kSize), 0, 0,
                           GLsizei(kSize), GLsizei(kSize), GL_COLOR_BUFFER_BIT, GL_NEAREST);
    std::vector<uint8_t> rgba(size_t(kSize) * kSize * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo[1]);
    glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo[0]);
    return rgba;
  };
  DrawStats all, culled;
  const std::vector<uint8_t> expected = frames(false, &all);
  const std::vector<uint8_t> actual = frames(true, &culled);
  const Diff diff = compare(actual, expected, nullptr);
  EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
  EXPECT_LT(culled.gpu_visible * 2, all.gpu_visible);  // Most of the crowd is hidden,
  EXPECT_GE(culled.gpu_visible, 40u);                  // the wall's front row drawn.
  GLint unit0 = 0;
  glActiveTexture(GL_TEXTURE0);
  glGetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &unit0);
  EXPECT_EQ(GLuint(unit0), host_texture);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previous));
  glBindTextureUnit(0, 0);
  glDeleteTextures(1, &host_texture);
  glDeleteFramebuffers(2, fbo);
  glDeleteRenderbuffers(3, buffers);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace si
