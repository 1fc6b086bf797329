// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Render tests through si::headless on each back-end: golden images, instanced equals
// non-instanced, GPU equals CPU (transform feedback vs. the CPU emulation and the double
// reference), and batching under a forced 16 KiB uniform block. Skips with a printed reason when
// a back-end has no context; SI_REQUIRE_GL (a list of back-end names) turns that into a failure.
// SI_UPDATE_GOLDEN=1 rewrites the golden images (from llvmpipe) instead of comparing;
// SI_GOLDEN_DIR overrides where they are read.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/log.h"
#include "si/core/reference_evaluator.h"
#include "si/gl/renderer.h"
#include "render/render_test_helpers.h"
#include "si/headless/headless_context.h"

#ifndef SI_GOLDEN_DIR
#error "SI_GOLDEN_DIR must name tests/render/golden"
#endif

namespace si {
namespace {

constexpr uint32_t kSize = 256;
// Image comparison: a pixel differs when a channel is off by more than kPixelTolerance; an image
// matches when at most kMaxDifferingShare of its pixels differ.
constexpr int kPixelTolerance = 8;
constexpr double kMaxDifferingShare = 0.005;

using test::requireGl;

const Character& character() {
  static const Character c = [] {
    Character out;
    if (!makeDefaultCharacter({}, &out).isOk()) std::abort();
    return out;
  }();
  return c;
}

const BakedPalette& palette(PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
  static BakedPalette cache[4];
  BakedPalette& p = cache[size_t(format)];
  if (p.clips.empty()) {
    BakeDesc d;
    d.rate_mode = RateMode::kFixed;
    d.sample_rate_hz = 30.0f;
    d.format = format;
    if (!bakePalette(character(), d, &p, nullptr).isOk()) std::abort();
  }
  return p;
}

struct Diff {
  double share = 0.0;
  int max_channel = 0;
};

Diff compare(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
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

class RenderTest : public ::testing::TestWithParam<HeadlessBackend> {
 protected:
  void SetUp() override {
    HeadlessDesc d;
    d.width = kSize;
    d.height = kSize;
    d.backend = GetParam();
    const Status s = HeadlessContext::create(d, &context_);
    if (!s.isOk()) {
      if (requireGl(GetParam())) FAIL() << s.toString();
      GTEST_SKIP() << "no " << headlessBackendName(GetParam()) << " context: " << s.message();
    }
    ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, context_.get(), &info_).isOk());
  }

  // A renderer with the default character uploaded (block size 0: the context's limit).
  // The skinning path is explicit (the vertex shader) unless `rd_in` says otherwise.
  void makeRenderer(Renderer* r, uint32_t block_size = 0,
                    PaletteFormat format = PaletteFormat::kMatrix3x4F32,
                    const RendererDesc* rd_in = nullptr) {
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    if (rd_in) rd = *rd_in;
    rd.uniform_block_size_bytes = block_size;
    const Status init = r->init(info_, rd);
    ASSERT_TRUE(init.isOk()) << init.toString();
    ASSERT_TRUE(r->uploadPalette(palette(format)).isOk());
    ASSERT_TRUE(r->uploadCharacter(character(), palette(format)).isOk());
  }

  void makeCrowd(CrowdManager* crowd, PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
    CrowdDesc cd;
    cd.palette = &palette(format);
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    ASSERT_TRUE(crowd->init(cd).isOk());
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
    const Status s =
        path == Path::kTraditional  ? r.drawTraditional(crowd, camera, &stats)
        : path == Path::kCpuSkinned ? r.drawCpuSkinned(crowd, camera, &stats)
        : path == Path::kCompute ? r.drawCrowd(crowd, batcher, camera, &stats, DrawMode::kComputeSkinned)
                                 : r.drawCrowd(crowd, batcher, camera, &stats);
    EXPECT_TRUE(s.isOk()) << s.toString();
    if (out) *out = stats;
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
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
                               headlessBackendName(GetParam());
      (void)writePng(base + "_actual.png", kSize, kSize, rgba);
      (void)writePng(base + "_diff.png", kSize, kSize, diff);
      ADD_FAILURE() << name << ": " << d.share * 100 << " % of pixels differ (max channel "
                    << d.max_channel << "); actual " << base << "_actual.png, diff " << base
                    << "_diff.png, golden " << golden;
    }
  }

  std::unique_ptr<HeadlessContext> context_;
  GlInfo info_;
};

Camera closeCamera() {
  return Camera::lookAt({0.0, 1.2, 3.2}, {0.0, 1.0, 0.0}, glm::vec3(0, 1, 0), 0.75f, 1.0f, 0.1f,
                        200.0f);
}

TEST_P(RenderTest, GoldenSingleCharacter) {
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

// Every LOD, every variation and several tints: 3 rows at LOD distances, 8 masks each.
void populateLodCrowd(CrowdManager* crowd) {
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

// One more character, close to the camera, crossfading from clip 0 to run over 1 s from the
// crowd clock's current time (the tests then advance it 0.3 s).
void addFadingCharacter(CrowdManager* crowd, PaletteFormat format = PaletteFormat::kMatrix3x4F32) {
  InstanceHandle fading;
  InstanceDesc d;
  d.position = glm::dvec3(0.5, 0.0, -2.0);
  ASSERT_TRUE(crowd->add(d, &fading).isOk());
  ASSERT_TRUE(crowd->crossfade(fading, uint32_t(palette(format).findClip("run")), 1.0).isOk());
}

// The CPU's selection of the last update(): (dense index as exportGpuState orders it, LOD) per
// visible instance.
std::vector<glm::uvec2> cpuSelection(const CrowdManager& crowd) {
  std::vector<GpuInstanceState> state;
  std::vector<InstanceHandle> dense;
  crowd.exportGpuState(&state, &dense);
  std::map<uint32_t, uint32_t> dense_of;  // handle id -> dense index
  for (uint32_t i = 0; i < dense.size(); ++i) dense_of[dense[i].id] = i;
  std::vector<glm::uvec2> out;
  for (InstanceHandle h : crowd.visibleHandles()) {
    uint32_t lod = 0;
    EXPECT_TRUE(crowd.lodOf(h, &lod).isOk());
    out.push_back(glm::uvec2(dense_of[h.id], lod));
  }
  return out;
}

Camera lodCamera() {
  return Camera::lookAt({0.0, 3.0, 6.0}, {0.0, 0.0, -40.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                        500.0f);
}

TEST_P(RenderTest, GoldenCrowdWithEveryLodVariationAndTint) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  for (int l = 0; l < 3; ++l) EXPECT_GT(crowd.stats().per_lod[l], 0u) << "LOD " << l;
  expectGolden("crowd_lods", draw(r, crowd, lodCamera(), 0));
}

TEST_P(RenderTest, GoldenCrossfadeMidpoint) {
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
  std::memcpy(&weight, &crowd.records()[0].blend[2], 4);
  ASSERT_NEAR(weight, 0.5f, 1e-6f);
  expectGolden("crossfade_mid", draw(r, crowd, closeCamera(), 0));
}

TEST_P(RenderTest, InstancedEqualsTraditionalAndCpuSkinned) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  addFadingCharacter(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  DrawStats instanced_stats, traditional_stats;
  const std::vector<uint8_t> a = draw(r, crowd, lodCamera(), 0, false, &instanced_stats);
  const std::vector<uint8_t> b = draw(r, crowd, lodCamera(), 0, true, &traditional_stats);
  const Diff diff = compare(a, b, nullptr);
  EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
  EXPECT_EQ(instanced_stats.triangles, traditional_stats.triangles);
  EXPECT_LT(instanced_stats.draw_calls, traditional_stats.draw_calls);
  // The CPU-skinning baseline draws the same image too.
  DrawStats cpu_stats;
  const std::vector<uint8_t> c = draw(r, crowd, lodCamera(), 0, false, &cpu_stats, Path::kCpuSkinned);
  const Diff cpu_diff = compare(a, c, nullptr);
  EXPECT_LE(cpu_diff.share, 0.001) << "max channel difference " << cpu_diff.max_channel;
  EXPECT_EQ(cpu_stats.triangles, instanced_stats.triangles);
}

TEST_P(RenderTest, SixteenKiBBatchesGiveTheSameImage) {
  Renderer r64, r16;
  makeRenderer(&r64);
  CrowdManager crowd;
  makeCrowd(&crowd);
  // 600 instances in view: more than 204 (a 16 KiB block) per bucket.
  for (int i = 0; i < 600; ++i) {
    InstanceDesc d;
    d.position = glm::dvec3((i % 30) * 1.0 - 15.0, 0.0, -5.0 - (i / 30) * 1.0);
    d.variation_mask = 1u | (uint32_t(i) % 16u << 1 & 0xE);
    d.time_seconds = 0.01 * i;
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(d, &h).isOk());
  }
  const Camera camera = Camera::lookAt({0.0, 8.0, 4.0}, {0.0, 0.0, -15.0}, glm::vec3(0, 1, 0),
                                       1.0f, 1.0f, 0.1f, 500.0f);
  ASSERT_TRUE(crowd.update(0.0, camera).isOk());
  DrawStats s64, s16;
  const std::vector<uint8_t> a = draw(r64, crowd, camera, 0, false, &s64);
  r64.shutdown();
  makeRenderer(&r16, 16384);
  const std::vector<uint8_t> b = draw(r16, crowd, camera, 16384, false, &s16);
  EXPECT_GT(s16.draw_calls, s64.draw_calls);
  EXPECT_EQ(s16.triangles, s64.triangles);
  EXPECT_EQ(compare(a, b, nullptr).max_channel, 0);  // Same records, same draws: identical.
}

TEST_P(RenderTest, GpuEqualsCpu) {
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16,
                               PaletteFormat::kQuatTranslationF32}) {
    Renderer r;
    makeRenderer(&r, 0, format);
    const BakedPalette& p = palette(format);
    const SkinnedMesh& mesh = character().mesh;
    SkinnedMesh gpu_mesh = mesh;  // The weights the vertex format stores.
    for (glm::vec4& w : gpu_mesh.weights) w = dequantizeWeights(quantizeWeights(w));
    BakeReport report;
    BakedPalette measured;
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    bd.format = format;
    ASSERT_TRUE(bakePalette(character(), bd, &measured, &report).isOk());
    for (uint32_t c = 0; c < p.clips.size(); ++c) {
      const BakedClip& clip = p.clips[c];
      // A frame midpoint, where interpolation matters most.
      const double t = clip.frame_count > 2 ? clip.frame_interval_seconds * 3.5 : 0.0;
      const FrameSample s = sampleFrames(clip, t);
      InstanceRecord rec{};
      rec.frames[0] = rec.frames[2] = clip.first_texel + s.frame * p.layout.frame_stride_texels;
      rec.frames[1] = rec.frames[3] = clip.first_texel + s.next_frame * p.layout.frame_stride_texels;
      std::memcpy(&rec.blend[0], &s.fraction, 4);
      std::memcpy(&rec.blend[1], &s.fraction, 4);
      std::vector<glm::vec3> gpu;
      ASSERT_TRUE(r.captureSkinnedPositions(rec, &gpu).isOk());
      std::vector<glm::mat4> mats(character().skeleton.jointCount());
      ASSERT_TRUE(emulateSkinningMatrices(p, c, s, mats).isOk());
      std::vector<glm::vec3> cpu(mesh.vertexCount());
      ASSERT_TRUE(emulateSkinning(gpu_mesh, mats, cpu, {}).isOk());
      ReferencePose pose;
      const Clip& source = character().clips[size_t(character().findClip(clip.name))];
      ASSERT_TRUE(evaluateLocalPose(character().skeleton, source, t, &pose).isOk());
      std::vector<glm::dvec3> ref(mesh.vertexCount());
      ASSERT_TRUE(skinVertices(mesh, pose.skinning, ref, {}, {}).isOk());
      double max_cpu = 0.0, max_ref = 0.0;
      for (size_t v = 0; v < gpu.size(); ++v) {
        max_cpu = std::max(max_cpu, double(glm::length(gpu[v] - cpu[v])));
        max_ref = std::max(max_ref, glm::length(glm::dvec3(gpu[v]) - ref[v]));
      }
      // Float rounding: a few ulps of coordinates up to 2 units.
      EXPECT_LT(max_cpu, 2e-5) << paletteFormatName(format) << " " << clip.name;
      // Within the bake's reported error for this clip, plus the same rounding.
      EXPECT_LE(max_ref, report.clips[c].max_error_units + 2e-5)
          << paletteFormatName(format) << " " << clip.name;
    }
  }
}

TEST_P(RenderTest, DepthOnlyAndRigidProgramsDraw) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  InstanceDesc d;
  d.clip = uint32_t(palette().findClip("wave"));
  d.time_seconds = 1.2;
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  ASSERT_TRUE(crowd.update(0.0, closeCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  DrawStats stats;
  r.clear(glm::vec4(0.0f));
  ASSERT_TRUE(r.drawCrowd(crowd, batcher, closeCamera(), &stats, DrawMode::kDepthOnly).isOk());
  std::vector<uint8_t> depth_only;
  ASSERT_TRUE(context_->readPixels(&depth_only).isOk());
  EXPECT_EQ(compare(depth_only, std::vector<uint8_t>(depth_only.size(), 0), nullptr).max_channel, 0)
      << "depth-only must not write colour";
  const std::vector<uint8_t> skinned = draw(r, crowd, closeCamera(), 0);
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  ASSERT_TRUE(r.drawCrowd(crowd, batcher, closeCamera(), &stats, DrawMode::kRigid).isOk());
  std::vector<uint8_t> rigid;
  ASSERT_TRUE(context_->readPixels(&rigid).isOk());
  EXPECT_GT(compare(skinned, rigid, nullptr).share, 0.01);  // The raised arm moves pixels.
}

// The compute pre-skinning path draws the vertex-shader path's image: every LOD, variation,
// tint and a crossfade, in each palette format, with the default ring and with a ring so small
// that the crowd is skinned and drawn in many chunks.
TEST_P(RenderTest, ComputePreSkinningEqualsTheVertexShaderPath) {
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16,
                               PaletteFormat::kQuatTranslationF32}) {
    SCOPED_TRACE(paletteFormatName(format));
    CrowdManager crowd;
    makeCrowd(&crowd, format);
    populateLodCrowd(&crowd);
    addFadingCharacter(&crowd, format);
    ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
    for (uint64_t ring_bytes : {uint64_t(0), uint64_t(64) << 10}) {
      SCOPED_TRACE(ring_bytes);
      Renderer r;
      RendererDesc rd;
      rd.skinning_path = SkinningPath::kVertexShader;
      rd.compute_ring_bytes = ring_bytes;
      makeRenderer(&r, 0, format, &rd);
      DrawStats vs_stats, cs_stats;
      const std::vector<uint8_t> a = draw(r, crowd, lodCamera(), 0, false, &vs_stats);
      const std::vector<uint8_t> b =
          draw(r, crowd, lodCamera(), 0, false, &cs_stats, Path::kCompute);
      const Diff diff = compare(a, b, nullptr);
      std::printf("[ compute  ] %s, ring %llu: %.4f %% of pixels differ, max channel %d\n",
                  paletteFormatName(format), static_cast<unsigned long long>(ring_bytes),
                  diff.share * 100.0, diff.max_channel);
      EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
      EXPECT_LE(diff.max_channel, 24);
      EXPECT_EQ(cs_stats.triangles, vs_stats.triangles);
      EXPECT_EQ(cs_stats.instances, vs_stats.instances);
      EXPECT_GE(cs_stats.compute_dispatches, vs_stats.draw_calls);
      EXPECT_GT(cs_stats.skinned_vertices, 0u);
      EXPECT_LE(cs_stats.ring_bytes_used, r.computeRingBytes());
      if (ring_bytes != 0) {
        EXPECT_EQ(r.computeRingBytes(), ring_bytes);  // Bounded as asked (one LOD 0 body fits).
        EXPECT_GT(cs_stats.compute_chunks, 1u);
      } else {
        EXPECT_EQ(cs_stats.compute_chunks, 1u);
      }
      EXPECT_EQ(vs_stats.compute_dispatches, 0u);
    }
  }
}

// The automatic choice measures both paths in a framebuffer of its own, says what it measured,
// leaves the application's framebuffer alone, and draws the same image by its choice.
TEST_P(RenderTest, AutomaticSkinningPathIsMeasuredAndLogged) {
  std::vector<std::string> log;
  setLogCallback(
      [](LogLevel, const char* m, void* user) {
        static_cast<std::vector<std::string>*>(user)->push_back(m);
      },
      &log);
  const glm::vec4 clear(0.2f, 0.25f, 0.3f, 1.0f);
  Renderer r;
  RendererDesc rd;  // kAutomatic by default.
  ASSERT_EQ(rd.skinning_path, SkinningPath::kAutomatic);
  ASSERT_TRUE(r.init(info_, rd).isOk());
  r.clear(clear);
  std::vector<uint8_t> before;
  ASSERT_TRUE(context_->readPixels(&before).isOk());
  ASSERT_TRUE(r.uploadPalette(palette()).isOk());
  ASSERT_TRUE(r.uploadCharacter(character(), palette()).isOk());
  setLogCallback(nullptr, nullptr);
  std::vector<uint8_t> after;
  ASSERT_TRUE(context_->readPixels(&after).isOk());
  EXPECT_EQ(compare(before, after, nullptr).max_channel, 0);
  EXPECT_NE(r.skinningPath(), SkinningPath::kAutomatic);
  std::printf("[ path     ] %s: %s\n", skinningPathName(r.skinningPath()),
              r.skinningPathReason().c_str());
  EXPECT_NE(r.skinningPathReason().find("vertex shader"), std::string::npos) << r.skinningPathReason();
  EXPECT_NE(r.skinningPathReason().find("compute"), std::string::npos);
  bool logged = false;
  for (const std::string& m : log)
    logged |= m.find(std::string("skinning path ") + skinningPathName(r.skinningPath())) !=
              std::string::npos;
  EXPECT_TRUE(logged);
  // Whichever it chose draws what the vertex shader draws.
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  const std::vector<uint8_t> chosen = draw(r, crowd, lodCamera(), 0);
  Renderer vs;
  makeRenderer(&vs);
  const std::vector<uint8_t> reference = draw(vs, crowd, lodCamera(), 0);
  EXPECT_LE(compare(chosen, reference, nullptr).share, 0.001);
  // An explicit setting is kept and says so.
  Renderer explicit_compute;
  RendererDesc cd;
  cd.skinning_path = SkinningPath::kCompute;
  makeRenderer(&explicit_compute, 0, PaletteFormat::kMatrix3x4F32, &cd);
  EXPECT_EQ(explicit_compute.skinningPath(), SkinningPath::kCompute);
  EXPECT_EQ(explicit_compute.skinningPathReason(), "explicit setting");
}

// GPU-driven culling selects exactly the instances and LODs CrowdManager::update() selects, on
// random scenes: positions near and past the far line, random rotations (not only headings),
// scales, clips, times, loop modes, crossfades running and ending, animation LOD, random
// cameras, and state changed between frames (which re-uploads the state).
TEST_P(RenderTest, GpuCullingSelectsWhatTheCpuSelects) {
  Renderer r;
  makeRenderer(&r);
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int scene = 0; scene < 3; ++scene) {
    SCOPED_TRACE(scene);
    CrowdDesc cd;
    cd.palette = &palette();
    cd.sub_mesh_count = 4;
    cd.lod_count = 3;
    cd.animation_lod_start = scene == 1 ? 1 : 0;
    cd.lod_hysteresis_ratio = scene == 2 ? 0.2f : 0.0f;
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
    uint32_t compared = 0;
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
      const Camera camera = Camera::lookAt(eye, target, glm::vec3(0, 1, 0),
                                           float(0.6 + u(rng)), 1.0f, 0.1f, 1000.0f);
      // The clock moves first; the GPU selects from the LODs of the previous frame, then the
      // CPU does the same at the same clock.
      ASSERT_TRUE(crowd.advanceClock(0.11).isOk());
      DrawStats stats;
      r.clear(glm::vec4(0.0f));
      ASSERT_TRUE(r.drawCrowdGpuCulled(crowd, camera, &stats).isOk());
      std::vector<glm::uvec2> gpu;
      ASSERT_TRUE(r.readGpuSelection(&gpu).isOk());
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
      std::printf("[ gpu cull ] scene %d frame %d: %zu visible, %zu mismatches\n", scene, frame,
                  cpu.size(), mismatches);
      EXPECT_EQ(crowd.stats().visible, cpu.size());
    }
    EXPECT_GT(compared, 500u);  // The scenes do show instances.
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
  const CullParams p = crowd.cullParams(camera);
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
    ASSERT_TRUE(crowd.advanceClock(0.0).isOk());
    ASSERT_TRUE(r.drawCrowdGpuCulled(crowd, camera, nullptr).isOk());
    std::vector<glm::uvec2> gpu;
    ASSERT_TRUE(r.readGpuSelection(&gpu).isOk());
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
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  rd.measure_gpu_time = true;  // Also reads back the visible count and triangles.
  makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  addFadingCharacter(&crowd);
  ASSERT_TRUE(crowd.advanceClock(0.3).isOk());
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  DrawStats gpu_stats;
  ASSERT_TRUE(r.drawCrowdGpuCulled(crowd, lodCamera(), &gpu_stats).isOk());
  std::vector<uint8_t> gpu_image;
  ASSERT_TRUE(context_->readPixels(&gpu_image).isOk());
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  DrawStats cpu_stats;
  const std::vector<uint8_t> cpu_image = draw(r, crowd, lodCamera(), 0, false, &cpu_stats);
  const Diff diff = compare(gpu_image, cpu_image, nullptr);
  EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
  EXPECT_EQ(gpu_stats.draw_calls, 1u);  // One multi-draw.
  EXPECT_EQ(gpu_stats.gpu_visible, crowd.stats().visible);
  EXPECT_EQ(gpu_stats.triangles, cpu_stats.triangles);
  EXPECT_EQ(gpu_stats.instances, cpu_stats.instances);
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
    ASSERT_TRUE(r.drawCrowdGpuCulled(*reused, lodCamera(), &gpu_stats).isOk());
    ASSERT_TRUE(reused->update(0.0, lodCamera()).isOk());
    EXPECT_EQ(gpu_stats.gpu_visible, reused->stats().visible) << k;
  }
  EXPECT_EQ(gpu_stats.gpu_visible, 0u);
  // A crowd with another palette is refused.
  CrowdManager other;
  CrowdDesc od;
  od.palette = &palette(PaletteFormat::kMatrix3x4F16);
  od.sub_mesh_count = 4;
  od.lod_count = 3;
  ASSERT_TRUE(other.init(od).isOk());
  EXPECT_EQ(r.drawCrowdGpuCulled(other, lodCamera(), &gpu_stats).code(),
            StatusCode::kInvalidArgument);
}

TEST_P(RenderTest, InitRejectsBadBlockSizes) {
  Renderer r;
  RendererDesc rd;
  rd.uniform_block_size_bytes = 8192;
  EXPECT_EQ(r.init(info_, rd).code(), StatusCode::kInvalidArgument);
  rd.uniform_block_size_bytes = info_.max_uniform_block_size_bytes + 16;
  EXPECT_EQ(r.init(info_, rd).code(), StatusCode::kInvalidArgument);
  CrowdManager crowd;
  makeCrowd(&crowd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init({65536, 256, 0}).isOk());
  DrawStats stats;
  EXPECT_EQ(r.drawCrowd(crowd, batcher, closeCamera(), &stats).code(), StatusCode::kInvalidArgument);
}

INSTANTIATE_TEST_SUITE_P(Backends, RenderTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kOsMesa, HeadlessBackend::kEglDevice),
                         [](const auto& param_info) {
                           std::string n = headlessBackendName(param_info.param);
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace si
