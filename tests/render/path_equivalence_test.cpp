// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Every draw path draws the same image: instanced, traditional, CPU-skinned, compute
// pre-skinning, 16 KiB batches; depth-only and rigid programs; the automatic path choice.
#include "render/render_fixture.h"
#include "si/core/log.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

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

// The CPU-skinning baseline draws the crowd's sub-meshes (CrowdDesc::sub_mesh_count), as every
// other path does, also for a character with more.
TEST_P(RenderTest, CpuSkinningDrawsTheCrowdsSubMeshesOnly) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 2;  // Of the character's 4.
  cd.lod_count = 3;
  ASSERT_TRUE(crowd.init(cd).isOk());
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  DrawStats instanced_stats, traditional_stats, cpu_stats;
  const std::vector<uint8_t> a = draw(r, crowd, lodCamera(), 0, false, &instanced_stats);
  (void)draw(r, crowd, lodCamera(), 0, true, &traditional_stats);
  const std::vector<uint8_t> c =
      draw(r, crowd, lodCamera(), 0, false, &cpu_stats, Path::kCpuSkinned);
  EXPECT_GT(instanced_stats.triangles, 0u);
  EXPECT_EQ(cpu_stats.triangles, instanced_stats.triangles);
  EXPECT_EQ(cpu_stats.triangles, traditional_stats.triangles);
  EXPECT_LE(compare(a, c, nullptr).share, 0.001);
}

// One LOD of more vertices than the CPU-skinning stream's 8 MiB chunk holds (262,144 of 32
// bytes): the stream grows to hold it and draws what the vertex shader draws.
TEST_P(RenderTest, CpuSkinningStreamsALodLargerThanItsChunk) {
  Character big = character();  // The same skeleton: the palette baked for it plays.
  SkinnedMesh& m = big.mesh;
  const glm::u16vec4 joints = m.joints[0];
  const glm::vec4 weights = m.weights[0];
  const uint32_t side = 520, n = side * side;  // 270,400 vertices.
  m.positions.resize(n);
  for (uint32_t y = 0; y < side; ++y)
    for (uint32_t x = 0; x < side; ++x)
      m.positions[y * side + x] = glm::vec3(-0.6f + 1.2f * x / side, 0.2f + 1.2f * y / side, 0.0f);
  m.normals.assign(n, glm::vec3(0.0f, 0.0f, 1.0f));
  if (!m.tangents.empty()) m.tangents.assign(n, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  if (!m.texcoords.empty()) m.texcoords.assign(n, glm::vec2(0.5f));
  if (!m.vertex_materials.empty()) m.vertex_materials.assign(n, 0);
  m.joints.assign(n, joints);
  m.weights.assign(n, weights);
  m.indices.clear();
  for (uint32_t y = 0; y + 1 < side; ++y)
    for (uint32_t x = 0; x + 1 < side; ++x) {
      const uint32_t a = y * side + x;
      m.indices.insert(m.indices.end(), {a, a + 1, a + side + 1, a, a + side + 1, a + side});
    }
  m.sub_meshes.resize(1);
  m.sub_meshes[0].lods = {IndexRange{0, uint32_t(m.indices.size())}};
  m.sub_meshes[0].lod_error_units = {0.0f};
  ASSERT_TRUE(m.validate(big.skeleton.jointCount()).isOk());
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(big, palette(), &id).isOk());
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette();
  cd.sub_mesh_count = 1;
  cd.lod_count = 1;
  ASSERT_TRUE(crowd.init(cd).isOk());
  InstanceDesc d;
  d.position = glm::dvec3(0.0, 0.0, -2.0);
  InstanceHandle h;
  ASSERT_TRUE(crowd.add(d, &h).isOk());
  const Camera camera = Camera::lookAt({0.0, 0.8, 0.5}, {0.0, 0.8, -2.0}, glm::vec3(0, 1, 0),
                                       1.0f, 1.0f, 0.1f, 100.0f);
  ASSERT_TRUE(crowd.update(0.2, camera).isOk());
  DrawStats vs_stats, cpu_stats;
  const std::vector<uint8_t> a = draw(r, crowd, camera, 0, false, &vs_stats);
  const std::vector<uint8_t> c = draw(r, crowd, camera, 0, false, &cpu_stats, Path::kCpuSkinned);
  EXPECT_EQ(cpu_stats.triangles, vs_stats.triangles);
  EXPECT_EQ(cpu_stats.draw_calls, 1u);
  EXPECT_LE(compare(a, c, nullptr).share, 0.001);
  size_t covered = 0;  // The grid covers a good part of the view: an empty frame cannot pass.
  for (size_t p = 0; p < c.size(); p += 4) covered += c[p] != a[0] || c[p + 1] != a[1];
  EXPECT_GT(covered, size_t(kSize) * kSize / 8);
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
  ASSERT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), &stats, DrawMode::kDepthOnly)
          .isOk());
  std::vector<uint8_t> depth_only;
  ASSERT_TRUE(context_->readPixels(&depth_only).isOk());
  EXPECT_EQ(compare(depth_only, std::vector<uint8_t>(depth_only.size(), 0), nullptr).max_channel, 0)
      << "depth-only must not write colour";
  const std::vector<uint8_t> skinned = draw(r, crowd, closeCamera(), 0);
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  ASSERT_TRUE(
      r.drawCrowd(CharacterId{}, crowd.view(), batcher, closeCamera(), &stats, DrawMode::kRigid)
          .isOk());
  std::vector<uint8_t> rigid;
  ASSERT_TRUE(context_->readPixels(&rigid).isOk());
  EXPECT_GT(compare(skinned, rigid, nullptr).share, 0.01);  // The raised arm moves pixels.
}

// The compute pre-skinning path draws the vertex-shader path's image: every LOD, variation,
// tint and a crossfade, in each palette format, with the default ring and with a ring so small
// that the crowd is skinned and drawn in many chunks.
TEST_P(RenderTest, ComputePreSkinningEqualsTheVertexShaderPath) {
  const std::pair<PaletteFormat, InterpolationChoice> cases[] = {
      {PaletteFormat::kMatrix3x4F32, InterpolationChoice::kLinear},
      {PaletteFormat::kMatrix3x4F16, InterpolationChoice::kLinear},
      {PaletteFormat::kQuatTranslationF32, InterpolationChoice::kLinear},
      {PaletteFormat::kMatrix3x4F32, InterpolationChoice::kCubic},
      {PaletteFormat::kQuatTranslationF32, InterpolationChoice::kCubic}};
  for (const auto& [format, interpolation] : cases) {
    SCOPED_TRACE(std::string(paletteFormatName(format)) + " " +
                 interpolationChoiceName(interpolation));
    CrowdManager crowd;
    makeCrowd(&crowd, format, interpolation);
    populateLodCrowd(&crowd);
    addFadingCharacter(&crowd, format);
    ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
    for (uint64_t ring_bytes : {uint64_t(0), uint64_t(64) << 10}) {
      SCOPED_TRACE(ring_bytes);
      Renderer r;
      RendererDesc rd;
      rd.skinning_path = SkinningPath::kVertexShader;
      rd.compute_ring_bytes = ring_bytes;
      makeRenderer(&r, 0, format, &rd, interpolation);
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
  CharacterId id;
  ASSERT_TRUE(r.addCharacter(character(), palette(), &id).isOk());
  setLogCallback(nullptr, nullptr);
  std::vector<uint8_t> after;
  ASSERT_TRUE(context_->readPixels(&after).isOk());
  EXPECT_EQ(compare(before, after, nullptr).max_channel, 0);
  EXPECT_NE(r.skinningPath(CharacterId{}), SkinningPath::kAutomatic);
  std::printf("[ path     ] %s: %s\n", skinningPathName(r.skinningPath(CharacterId{})),
              r.skinningPathReason(CharacterId{}).c_str());
  EXPECT_NE(r.skinningPathReason(CharacterId{}).find("vertex shader"), std::string::npos)
      << r.skinningPathReason(CharacterId{});
  EXPECT_NE(r.skinningPathReason(CharacterId{}).find("compute"), std::string::npos);
  bool logged = false;
  for (const std::string& m : log)
    logged |= m.find(std::string("skinning path ") +
                     skinningPathName(r.skinningPath(CharacterId{}))) != std::string::npos;
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
  EXPECT_EQ(explicit_compute.skinningPath(CharacterId{}), SkinningPath::kCompute);
  EXPECT_EQ(explicit_compute.skinningPathReason(CharacterId{}), "explicit setting");
}

// GPU-driven culling selects exactly the instances and LODs CrowdManager::update() selects, on
// random scenes: positions near and past the far line, random rotations (not only headings),
// scales, clips, times, loop modes, crossfades running and ending, animation LOD, random
// cameras, and state changed between frames (which re-uploads the state).

TEST_P(RenderTest, InitRejectsBadBlockSizes) {
  Renderer r;
  RendererDesc rd;
  rd.uniform_block_size_bytes = 8192;
  EXPECT_EQ(r.init(info_, rd).code(), StatusCode::kInvalidArgument);
  rd.uniform_block_size_bytes = info_.max_uniform_block_size_bytes + 16;
  EXPECT_EQ(r.init(info_, rd).code(), StatusCode::kInvalidArgument);
}

// A batcher the renderer cannot bind is refused before anything is written: more records per
// draw than the shader's block holds, or batch offsets not aligned to the context's
// GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT (a binding there is GL_INVALID_VALUE on a GPU whose
// alignment is 256).
TEST_P(RenderTest, DrawsRefuseABatcherTheRendererCannotBind) {
  GlInfo aligned = info_;
  aligned.uniform_buffer_offset_alignment = 256;  // As NVIDIA's; a multiple of any real one.
  Renderer r;
  makeRenderer(&r, 16384);  // 204 records per draw.
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init({65536, 256, 0}).isOk());  // 819 per draw.
  const Status capacity = r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr);
  EXPECT_EQ(capacity.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(capacity.message().find("per draw"), std::string::npos) << capacity.message();
  Renderer strict;
  makeRenderer(&strict, aligned);
  for (uint32_t alignment : {16u, 64u, 128u}) {
    ASSERT_TRUE(batcher.init({16384, alignment, 0}).isOk());
    const Status s = strict.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << alignment;
    EXPECT_NE(s.message().find("GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT"), std::string::npos)
        << s.message();
  }
  for (uint32_t alignment : {256u, 512u}) {  // Multiples of the context's: drawn.
    ASSERT_TRUE(batcher.init({16384, alignment, 0}).isOk());
    EXPECT_TRUE(strict.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr).isOk())
        << alignment;
  }
  ASSERT_TRUE(batcher.init(strict.batchLimits()).isOk());
  EXPECT_TRUE(strict.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr).isOk());
}

}  // namespace
}  // namespace si
