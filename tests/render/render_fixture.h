// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The render tests' fixture, run on each headless back-end: the embedded character and its
// palettes, a renderer and a crowd, drawing through every path and comparing with golden PNGs
// (the comparison: image_compare.h; the scenes several tests share: render_scenes.h). Skips with a
// printed reason when a back-end has no context; SI_REQUIRE_GL (a list of back-end names) turns
// that into a failure. SI_UPDATE_GOLDEN=1 rewrites the golden images (from llvmpipe) instead of
// comparing; SI_GOLDEN_DIR overrides where they are read. On llvmpipe the egl_device variants skip
// (the same driver as egl_surfaceless), and the osmesa variants but for the tests of what the
// context itself decides (runsOnEveryContext), unless SI_ALL_BACKENDS=1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "render/image_compare.h"
#include "render/render_test_helpers.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/impostor_level.h"
#include "si/crowd/crowd_export.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"

#ifndef SI_GOLDEN_DIR
#error "SI_GOLDEN_DIR must name tests/render/golden"
#endif

namespace si::test {

inline const Character& character() {
  static const Character c = [] {
    Character out;
    if (!makeDefaultCharacter({}, &out).isOk()) std::abort();
    return out;
  }();
  return c;
}

// The embedded character with its impostor level appended (si::appendImpostorLevel).
inline const Character& impostorCharacter() {
  static const Character c = [] {
    Character k = character();
    if (!appendImpostorLevel(&k.mesh).isOk()) std::abort();
    return k;
  }();
  return c;
}

inline const BakedPalette& palette(PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                                   InterpolationChoice interpolation = InterpolationChoice::kLinear) {
  static BakedPalette cache[4][2];
  BakedPalette& p = cache[size_t(format)][interpolation == InterpolationChoice::kCubic ? 1 : 0];
  if (p.clips.empty()) {
    BakeDesc d;
    d.rate_mode = RateMode::kFixed;
    d.sample_rate_hz = 30.0f;
    d.format = format;
    d.interpolation = interpolation;
    if (!bakePalette(character(), d, &p, nullptr).isOk()) std::abort();
  }
  return p;
}

// Every drawing path by one name, for the tests that draw one scene on each: the instanced
// paths (drawCrowd, vertex-shader skinning or compute pre-skinning), the GPU-driven ones
// (drawCrowdGpuCulled, either skinning) and the two baselines.
enum class PathKind { kInstanced, kCompute, kGpuDriven, kGpuDrivenCompute, kTraditional, kCpu };
inline constexpr PathKind kEveryPath[] = {PathKind::kInstanced,        PathKind::kCompute,
                                          PathKind::kGpuDriven,        PathKind::kGpuDrivenCompute,
                                          PathKind::kTraditional,      PathKind::kCpu};
inline const char* pathKindName(PathKind k) {
  switch (k) {
    case PathKind::kInstanced: return "instanced";
    case PathKind::kCompute: return "compute";
    case PathKind::kGpuDriven: return "gpu-driven";
    case PathKind::kGpuDrivenCompute: return "gpu-driven compute";
    case PathKind::kTraditional: return "traditional";
    case PathKind::kCpu: return "cpu-skinned";
  }
  return "?";
}
// Draws `crowd`'s own view with `camera` on `kind` (depth only when `depth_only`: the instanced
// and GPU-driven kinds), without clearing; adds the draw's statistics to `stats` when given.
inline Status drawOnPath(Renderer& r, PathKind kind, const CrowdManager& crowd,
                         const Camera& camera, DrawStats* stats, bool depth_only = false) {
  InstanceBatcher batcher;
  Status s = batcher.init(r.batchLimits());
  if (!s.isOk()) return s;
  const DrawMode skinned = depth_only ? DrawMode::kDepthOnly : DrawMode::kSkinned;
  switch (kind) {
    case PathKind::kInstanced:
      return r.drawCrowd(si::CharacterId{}, crowd.view(), batcher, camera, stats, skinned);
    case PathKind::kCompute:
      return r.drawCrowd(si::CharacterId{}, crowd.view(), batcher, camera, stats,
                         DrawMode::kComputeSkinned);
    case PathKind::kGpuDriven:
      return r.drawCrowdGpuCulled(si::CharacterId{}, crowd.view(), camera, stats, skinned);
    case PathKind::kGpuDrivenCompute:
      return r.drawCrowdGpuCulled(si::CharacterId{}, crowd.view(), camera, stats,
                                  DrawMode::kComputeSkinned);
    case PathKind::kTraditional:
      return r.drawTraditional(si::CharacterId{}, crowd.view(), camera, stats);
    case PathKind::kCpu:
      return r.drawCpuSkinned(si::CharacterId{}, crowd.view(), camera, stats);
  }
  return Status::ok();
}

// `c` drawing into a y-flipped target (a render texture as OGRE and others draw them).
inline Camera yFlipped(Camera c) {
  c.projection[1][1] = -c.projection[1][1];
  return c;
}

// Scenes (render_scenes.h, included at the end).
inline Camera closeCamera();
inline Camera lodCamera();
inline void populateLodCrowd(CrowdManager* crowd);

class RenderTest : public ::testing::TestWithParam<HeadlessBackend> {
 protected:
  // The OpenGL ES profile's fixture (EsRenderTest) answers true: an ES 3 context.
  virtual bool es() const { return false; }

  void SetUp() override {
    HeadlessDesc d;
    d.width = kSize;
    d.height = kSize;
    d.backend = GetParam();
    d.es = es();
    const Status s = HeadlessContext::create(d, &context_);
    if (!s.isOk()) {
      if (requireGl(GetParam())) FAIL() << s.toString();
      GTEST_SKIP() << "no " << headlessBackendName(GetParam()) << (es() ? " ES" : "")
                   << " context: " << s.message();
    }
    const Status loaded = loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_);
    ASSERT_TRUE(loaded.isOk()) << loaded.toString();
    ASSERT_EQ(info_.es, es()) << info_.version;
    // Without a GPU the EGL device platform and OSMesa reach the same llvmpipe driver
    // egl_surfaceless tests, so each render test runs on it once: egl_device runs none of them
    // (ContextTest still creates, clears and reads back through it), OSMesa what depends on the
    // context it makes (runsOnEveryContext). SI_ALL_BACKENDS=1 runs them all anyway.
    const char* all = std::getenv("SI_ALL_BACKENDS");
    const bool every = all != nullptr && all[0] == '1';
    const bool same_driver = !every && info_.renderer.find("llvmpipe") != std::string::npos &&
                             (GetParam() == HeadlessBackend::kEglDevice ||
                              (GetParam() == HeadlessBackend::kOsMesa && !runsOnEveryContext()));
    if (same_driver)
      GTEST_SKIP() << headlessBackendName(GetParam()) << " reached " << info_.renderer
                   << ", which egl_surfaceless tests already (SI_ALL_BACKENDS=1 runs it)";
  }

  // The tests OSMesa runs on llvmpipe (see SetUp): those whose name holds one of these.
  static bool runsOnEveryContext() {
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    for (const char* kept :
         {"Golden", "InstancedEqualsTraditionalAndCpuSkinned",
          "GpuDrivenComputePathEqualsTheCpuComputePath",
          "UploadsPastTheContextsLimitsAreNamedErrors", "AllocationsTheDriverRefusesAreNamedErrors",
          "TheApplicationsPendingErrorsAreGivenBackOrLeftPending", "NoCurrentContextIsANamedError",
          "MatchesTheCppStruct"})
      if (name.find(kept) != std::string::npos) return true;
    return false;
  }

  // `crowd` (of character `c`, baked as `palette`) updated once for `camera` and drawn by a
  // fresh renderer on this context, by the CPU emulation with `cpu`, else by drawCrowd (the
  // vertex-shader path): the image, over a blue-grey background.
  std::vector<uint8_t> drawCrowdImage(const Character& c, const BakedPalette& palette,
                                      CrowdManager& crowd, const Camera& camera, bool cpu) {
    Renderer r;
    EXPECT_TRUE(r.init(info_, RendererDesc()).isOk());
    CharacterId id;
    const Status added = r.addCharacter(c, palette, &id);
    EXPECT_TRUE(added.isOk()) << added.toString();
    EXPECT_TRUE(crowd.update(0.0, camera).isOk());
    InstanceBatcher batcher;
    EXPECT_TRUE(batcher.init(r.batchLimits()).isOk());
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = cpu ? r.drawCpuSkinned(id, crowd.view(), camera, nullptr)
                         : r.drawCrowd(id, crowd.view(), batcher, camera, nullptr);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> image;
    EXPECT_TRUE(context_->readPixels(&image).isOk());
    r.shutdown();
    return image;
  }

  // On an ES fixture: expects what `draw(false)` draws on this context (the ES profile's
  // vertex-shader path) within kMaxDifferingShare of what `draw(true)` draws on a desktop
  // context of the same back-end (the CPU emulation). This context is current again after.
  void expectEsDrawsAsDesktopCpu(const std::function<std::vector<uint8_t>(bool cpu)>& draw) {
    ASSERT_TRUE(info_.es);
    const std::vector<uint8_t> es_image = draw(false);
    HeadlessDesc d;
    d.width = d.height = kSize;
    d.backend = GetParam();
    std::unique_ptr<HeadlessContext> desktop;
    ASSERT_TRUE(HeadlessContext::create(d, &desktop).isOk());
    std::swap(desktop, context_);
    ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_).isOk());
    const std::vector<uint8_t> emulated = draw(true);
    std::swap(desktop, context_);
    desktop.reset();
    ASSERT_TRUE(context_->makeCurrent().isOk());
    ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_).isOk());
    EXPECT_LE(compare(es_image, emulated, nullptr).share, kMaxDifferingShare);
  }

  // A renderer with the default character uploaded (block size 0: the context's limit).
  // The skinning path is explicit (the vertex shader) unless `rd_in` says otherwise.
  // `info` (when given) stands for the context's: limits lowered as a smaller GPU reports them.
  void makeRenderer(Renderer* r, uint32_t block_size = 0,
                    PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                    const RendererDesc* rd_in = nullptr,
                    InterpolationChoice interpolation = InterpolationChoice::kLinear,
                    const GlInfo* info = nullptr) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    if (rd_in) rd = *rd_in;
    rd.uniform_block_size_bytes = block_size;
    const Status init = r->init(info != nullptr ? *info : info_, rd);
    ASSERT_TRUE(init.isOk()) << init.toString();
    CharacterId id;
    const Status added = r->addCharacter(character(), palette(format, interpolation), &id);
    ASSERT_TRUE(added.isOk()) << added.toString();
  }
  void makeRenderer(Renderer* r, const GlInfo& info) {
    makeRenderer(r, 0, PaletteFormat::kMatrix3x4F32, nullptr, InterpolationChoice::kLinear, &info);
  }

  // The render tests' crowd of character(): its 4 sub-meshes and 3 LODs, playing palette(format,
  // interpolation).
  CrowdDesc crowdDesc(PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                      InterpolationChoice interpolation = InterpolationChoice::kLinear) {
    CrowdDesc cd;
    cd.palette = &palette(format, interpolation);
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    return cd;
  }
  void makeCrowd(CrowdManager* crowd, PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                 InterpolationChoice interpolation = InterpolationChoice::kLinear) {
    ASSERT_TRUE(crowd->init(crowdDesc(format, interpolation)).isOk());
  }
  // makeCrowd()'s crowd with its LODs from 3 and 6 radii on (the default's 20 and 60): in the
  // wall scene (populateWallCrowd) most of the crowd behind the wall draws LOD 2. For tests of
  // culling, which need no finer level: skinning that crowd at the default's levels took
  // most of their time on llvmpipe and lavapipe (si::vk's occlusion tests 37 s -> 15 s, alone).
  void makeCoarseCrowd(CrowdManager* crowd) {
    CrowdDesc cd = crowdDesc();
    cd.lod_distances_radii = {3.0f, 6.0f};
    ASSERT_TRUE(crowd->init(cd).isOk());
  }
  // makeCrowd() holding one instance of InstanceDesc's defaults, updated for closeCamera().
  void makeOneInstanceCrowd(CrowdManager* crowd) {
    makeCrowd(crowd);
    InstanceDesc d;
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
    ASSERT_TRUE(crowd->update(0.1, closeCamera()).isOk());
  }

  enum class Path { kInstanced, kTraditional, kCpuSkinned, kCompute };
  std::vector<uint8_t> draw(Renderer& r, const CrowdManager& crowd, const Camera& camera,
                            uint32_t block_size, bool traditional = false, DrawStats* out = nullptr,
                            Path path = Path::kInstanced) {
    InstanceBatcher batcher;
    BatchLimits limits = r.batchLimits();
    if (block_size) limits.max_uniform_block_size_bytes = block_size;
    EXPECT_TRUE(batcher.init(limits).isOk());
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats stats;
    if (traditional) path = Path::kTraditional;
    const Status s = path == Path::kTraditional
                         ? r.drawTraditional(si::CharacterId{}, crowd.view(), camera, &stats)
                     : path == Path::kCpuSkinned
                         ? r.drawCpuSkinned(si::CharacterId{}, crowd.view(), camera, &stats)
                     : path == Path::kCompute
                         ? r.drawCrowd(si::CharacterId{}, crowd.view(), batcher, camera, &stats,
                                       DrawMode::kComputeSkinned)
                         : r.drawCrowd(si::CharacterId{}, crowd.view(), batcher, camera, &stats);
    EXPECT_TRUE(s.isOk()) << s.toString();
    if (out) *out = stats;
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }

  // One drawing path of a comparison: drawCrowdGpuCulled in `mode` when `gpu_driven`, else
  // draw() on `path`.
  struct PathCase {
    const char* name;
    Renderer* r;
    Path path;
    bool gpu_driven;
    DrawMode mode;
  };
  // Every case draws `crowd` seen by `camera` with `reference`'s image (at most 0.1 % of pixels
  // apart) and `reference_stats`' triangles and instances.
  void expectEveryCaseDraws(std::initializer_list<PathCase> cases, const CrowdManager& crowd,
                            const Camera& camera, const std::vector<uint8_t>& reference,
                            const DrawStats& reference_stats) {
    for (const PathCase& k : cases) {
      SCOPED_TRACE(k.name);
      DrawStats stats;
      std::vector<uint8_t> image;
      if (k.gpu_driven) {
        k.r->clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
        const Status s =
            k.r->drawCrowdGpuCulled(si::CharacterId{}, crowd.view(), camera, &stats, k.mode);
        ASSERT_TRUE(s.isOk()) << s.toString();
        ASSERT_TRUE(context_->readPixels(&image).isOk());
      } else {
        image = draw(*k.r, crowd, camera, 0, false, &stats, k.path);
      }
      const Diff diff = compare(image, reference, nullptr);
      EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
      // Impostors that hold no pixel centre are left out on the GPU-driven path (2 triangles
      // each).
      EXPECT_EQ(stats.triangles + 2 * stats.impostors_left_out, reference_stats.triangles);
      EXPECT_EQ(stats.instances + stats.impostors_left_out, reference_stats.instances);
    }
  }

  // Compares with tests/render/golden/<name>.png; writes actual and diff images on failure.
  void expectGolden(const std::string& name, const std::vector<uint8_t>& rgba) {
    const char* dir = std::getenv("SI_GOLDEN_DIR");  // Overrides the source tree's folder.
    const std::string golden = std::string(dir ? dir : SI_GOLDEN_DIR) + "/" + name + ".png";
    const char* update = std::getenv("SI_UPDATE_GOLDEN");
    if (update != nullptr && std::string(update) == "1") {
      ASSERT_TRUE(writePng(golden, kSize, kSize, rgba).isOk());
      std::printf("[ golden   ] wrote %s\n", golden.c_str());
      return;
    }
    uint32_t w = 0, h = 0;
    std::vector<uint8_t> expected;
    ASSERT_TRUE(readPng(golden, &w, &h, &expected).isOk()) << golden;
    std::vector<uint8_t> diff;
    const Diff d = compare(rgba, expected, &diff);
    if (d.share > kMaxDifferingShare) {
      const std::string base = ::testing::TempDir() + "si_" + name + "_" +
                               headlessBackendName(GetParam()) + (es() ? "_es" : "");
      (void)writePng(base + "_actual.png", kSize, kSize, rgba);
      (void)writePng(base + "_diff.png", kSize, kSize, diff);
      ADD_FAILURE() << name << ": " << d.share * 100 << " % of pixels differ (max channel "
                    << d.max_channel << "); actual " << base << "_actual.png, diff " << base
                    << "_diff.png, golden " << golden;
    }
  }

  // The golden scenes (golden_test.cpp), drawn on the desktop and the ES profile alike.
  void goldenSingleCharacter() {
    Renderer r;
    makeRenderer(&r);
    CrowdManager crowd;
    makeCrowd(&crowd);
    InstanceDesc d;
    d.clip = uint32_t(palette().findClip("walk"));
    d.time_seconds = 0.3;
    d.speed = 0.0f;
    d.color = glm::u8vec4(200, 40, 40, 255);
    d.variation_mask = 0xF;
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    ASSERT_TRUE(crowd.update(0.0, closeCamera()).isOk());
    expectGolden("single_walk", draw(r, crowd, closeCamera(), 0));
  }

  void goldenCrowdLods() {
    Renderer r;
    makeRenderer(&r);
    CrowdManager crowd;
    makeCrowd(&crowd);
    populateLodCrowd(&crowd);
    ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
    for (int l = 0; l < 3; ++l) EXPECT_GT(crowd.view().stats().per_lod[l], 0u) << "LOD " << l;
    expectGolden("crowd_lods", draw(r, crowd, lodCamera(), 0));
  }

  void goldenCrossfadeMidpoint() {
    Renderer r;
    makeRenderer(&r);
    CrowdManager crowd;
    makeCrowd(&crowd);
    InstanceDesc d;
    d.clip = uint32_t(palette().findClip("idle"));
    d.color = glm::u8vec4(40, 120, 220, 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
    ASSERT_TRUE(crowd.crossfade(h, uint32_t(palette().findClip("wave")), 1.0, 0.5).isOk());
    ASSERT_TRUE(crowd.update(0.5, closeCamera()).isOk());  // Half way through the blend.
    float weight;
    std::memcpy(&weight, &crowd.view().records()[0].blend[2], 4);
    ASSERT_NEAR(weight, 0.5f, 1e-6f);
    expectGolden("crossfade_mid", draw(r, crowd, closeCamera(), 0));
  }

  std::unique_ptr<HeadlessContext> context_;
  GlInfo info_;
};

}  // namespace si::test

#include "render/render_scenes.h"  // The scenes the fixture draws are defined after it.
