// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The render tests' fixture, run on each headless back-end: the embedded character and its
// palettes, a renderer and a crowd, drawing through every path, image comparison with golden
// PNGs, and the scenes several tests share. Skips with a printed reason when a back-end has no
// context; SI_REQUIRE_GL (a list of back-end names) turns that into a failure.
// SI_UPDATE_GOLDEN=1 rewrites the golden images (from llvmpipe) instead of comparing;
// SI_GOLDEN_DIR overrides where they are read. On llvmpipe the egl_device variants skip (the
// same driver as egl_surfaceless) unless SI_ALL_BACKENDS=1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

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


inline constexpr uint32_t kSize = 256;
// Image comparison: a pixel differs when a channel is off by more than kPixelTolerance; an image
// matches when at most kMaxDifferingShare of its pixels differ.
inline constexpr int kPixelTolerance = 8;
inline constexpr double kMaxDifferingShare = 0.005;


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

struct Diff {
  double share = 0.0;
  int max_channel = 0;
};

inline Diff compare(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
             std::vector<uint8_t>* diff_image) {
  Diff d;
  if (a.size() != b.size()) return {1.0, 255};
  size_t differing = 0;
  if (diff_image) diff_image->assign(a.size(), 255);
  for (size_t p = 0; p < a.size(); p += 4) {
    int m = 0;
    for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[p + c]) - int(b[p + c])));
    d.max_channel = std::max(d.max_channel, m);
    if (m > kPixelTolerance) {
      ++differing;
      if (diff_image) (*diff_image)[p] = 255, (*diff_image)[p + 1] = 0, (*diff_image)[p + 2] = 0;
    } else if (diff_image) {
      for (int c = 0; c < 3; ++c) (*diff_image)[p + c] = uint8_t(a[p + c] / 3);
    }
  }
  d.share = double(differing) / double(a.size() / 4);
  return d;
}

// Texels of two depth images more than 1e-6 apart.
inline size_t differingDepths(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) n += std::abs(a[i] - b[i]) > 1e-6f;
  return n;
}

// Two motion images (MotionTarget::readMotion) of one size agree: at least 99.5 % of their
// texels within 1e-4 texture units.
inline void expectMotionAgrees(const std::vector<glm::vec2>& a, const std::vector<glm::vec2>& b) {
  ASSERT_EQ(a.size(), b.size());
  size_t agree = 0;
  for (size_t i = 0; i < a.size(); ++i) agree += glm::length(a[i] - b[i]) < 1e-4f;
  EXPECT_GE(double(agree), 0.995 * double(a.size()));
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

// `image` (RGBA8, kSize x kSize) upside down.
inline std::vector<uint8_t> flipped(const std::vector<uint8_t>& image) {
  std::vector<uint8_t> out(image.size());
  const size_t row = size_t(kSize) * 4;
  for (uint32_t y = 0; y < kSize; ++y)
    std::memcpy(&out[size_t(kSize - 1 - y) * row], &image[size_t(y) * row], row);
  return out;
}

// `c` drawing into a y-flipped target (a render texture as OGRE and others draw them).
inline Camera yFlipped(Camera c) {
  c.projection[1][1] = -c.projection[1][1];
  return c;
}

// Scenes defined below the fixture.
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
    // Without a GPU the EGL device platform reaches the same llvmpipe driver egl_surfaceless
    // tests, so each render test runs on it once (ContextTest still creates, clears and reads
    // back through egl_device). SI_ALL_BACKENDS=1 runs them on it anyway.
    const char* all = std::getenv("SI_ALL_BACKENDS");
    if (GetParam() == HeadlessBackend::kEglDevice &&
        info_.renderer.find("llvmpipe") != std::string::npos && !(all != nullptr && all[0] == '1'))
      GTEST_SKIP() << "egl_device reached " << info_.renderer
                   << ", which egl_surfaceless tests already (SI_ALL_BACKENDS=1 runs it)";
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

  void makeCrowd(CrowdManager* crowd, PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                 InterpolationChoice interpolation = InterpolationChoice::kLinear) {
    CrowdDesc cd;
    cd.palette = &palette(format, interpolation);
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
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
      EXPECT_EQ(stats.triangles, reference_stats.triangles);
      EXPECT_EQ(stats.instances, reference_stats.instances);
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

inline Camera closeCamera() {
  return Camera::lookAt({0.0, 1.2, 3.2}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.75f, 1.0f, 0.1f,
                        200.0f);
}

// Every LOD, every variation and several tints: 3 rows at LOD distances, 8 masks each.
inline void populateLodCrowd(CrowdManager* crowd) {
  const uint32_t clips = uint32_t(palette().clips.size());
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      const double z = row == 0 ? -4.0 : row == 1 ? -40.0 : -110.0;
      const double spacing = row == 0 ? 1.2 : row == 1 ? 6.0 : 16.0;
      d.position = glm::dvec3((k - 3.5) * spacing, 0.0, z);
      d.variation_mask = 1u | (uint32_t(k) << 1);
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.1 * k;
      d.speed = 0.0f;
      d.color = glm::u8vec4(uint8_t(40 + 30 * k), uint8_t(200 - 20 * k), uint8_t(60 + 60 * row), 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
}

// Occlusion culling's scene: a dense wall of 3 staggered rows of 40 characters, shoulder to
// shoulder 2 units in front of wallCamera(), and a crowd of 600 behind it (seeded).
inline void populateWallCrowd(CrowdManager* crowd) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 40; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3(-6.0 + 0.3 * k + 0.15 * row, 0.0, -2.0 - 0.4 * row);
      d.clip = uint32_t(k % 2);
      d.time_seconds = u(rng);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
    }
  for (int k = 0; k < 600; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(-8.0 + 16.0 * u(rng), 0.0, -8.0 - 30.0 * u(rng));
    d.clip = uint32_t(k % 3);
    d.time_seconds = u(rng);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
  }
}
// At eye height in front of the wall, looking along -z.
inline Camera wallCamera() {
  return Camera::lookAt({0.0, 1.0, 2.0}, {0.0, 1.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

// One more character, close to the camera, crossfading from clip 0 to run over 1 s from the
// crowd clock's current time (the tests then advance it 0.3 s).
inline void addFadingCharacter(CrowdManager* crowd, PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
  InstanceHandle fading;
  InstanceDesc d;
  d.position = glm::dvec3(0.5, 0.0, -2.0);
  ASSERT_TRUE(crowd->add(d, &fading).isOk());
  ASSERT_TRUE(crowd->crossfade(fading, uint32_t(palette(format).findClip("run")), 1.0).isOk());
}

// Sixteen characters of impostorCharacter() in two rows of 8, `spacing` apart, the first row at
// z = -`z` (in front of lodCamera()) and the second `row_step` further, every one at the
// impostor level (each mesh level's line 2 radii after the last), updated 0.2 s.
inline void impostorRowsCrowd(double spacing, double z, double row_step, CrowdManager* crowd) {
  const uint32_t levels = uint32_t(impostorCharacter().mesh.maxLodCount());
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = levels;
  cd.character_radius = 1.0f;
  for (uint32_t l = 1; l < levels; ++l) cd.lod_distances_radii.push_back(2.0f * float(l));
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = levels - 1;
  ASSERT_TRUE(crowd->init(cd).isOk());
  for (int k = 0; k < 16; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3((k % 8 - 3.5) * spacing, 0.0, -z - row_step * (k / 8));
    d.rotation = glm::angleAxis(0.7f * float(k), glm::vec3(0, 1, 0));
    d.clip = uint32_t(k) % uint32_t(palette().clips.size());
    d.color = glm::u8vec4(uint8_t(40 + 12 * k), 200, 90, 255);
    InstanceHandle h;
    ASSERT_TRUE(crowd->add(d, &h).isOk());
  }
  ASSERT_TRUE(crowd->update(0.2, lodCamera()).isOk());
  ASSERT_EQ(crowd->view().stats().per_lod[levels - 1], 16u);
}

// The CPU's selection of the last update(): (dense index as CrowdExport::state orders it, LOD) per
// visible instance.
inline std::vector<glm::uvec2> cpuSelection(const CrowdManager& crowd) {
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> dense;
  si::CrowdExport(crowd).state(&state, &dense);
  std::map<uint32_t, uint32_t> dense_of;  // handle id -> dense index
  for (uint32_t i = 0; i < dense.size(); ++i) dense_of[dense[i].id] = i;
  std::vector<glm::uvec2> out;
  for (InstanceHandle h : crowd.view().visibleHandles()) {
    uint32_t lod = 0;
    EXPECT_TRUE(crowd.view().lodOf(h, &lod).isOk());
    out.push_back(glm::uvec2(dense_of[h.id], lod));
  }
  return out;
}

inline Camera lodCamera() {
  return Camera::lookAt({0.0, 3.0, 6.0}, {0.0, 0.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

}  // namespace si::test
