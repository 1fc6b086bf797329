// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// GPU equals CPU: the positions of both skinning paths (the vertex shader's through transform
// feedback, the compute pre-skinning pass's buffer) against the CPU emulation and the
// double-precision reference, in every palette format, linear and cubic.
#include "render/render_fixture.h"
#include "si/core/reference_evaluator.h"

namespace si {
namespace {

using namespace test;

TEST_P(RenderTest, GpuEqualsCpu) {
  for (InterpolationChoice interpolation : {InterpolationChoice::kLinear, InterpolationChoice::kCubic})
  for (PaletteFormat format : {PaletteFormat::kMatrix3x4F32, PaletteFormat::kMatrix3x4F16,
                               PaletteFormat::kQuatTranslationF32}) {
    SCOPED_TRACE(std::string(paletteFormatName(format)) + " " +
                 interpolationChoiceName(interpolation));
    Renderer r;
    makeRenderer(&r, 0, format, nullptr, interpolation);
    const BakedPalette& p = palette(format, interpolation);
    const SkinnedMesh& mesh = character().mesh;
    SkinnedMesh gpu_mesh = mesh;  // The weights the vertex format stores.
    for (glm::vec4& w : gpu_mesh.weights) w = dequantizeWeights(quantizeWeights(w));
    BakeReport report;
    BakedPalette measured;
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    bd.format = format;
    bd.interpolation = interpolation;
    ASSERT_TRUE(bakePalette(character(), bd, &measured, &report).isOk());
    for (uint32_t c = 0; c < p.clips.size(); ++c) {
      const BakedClip& clip = p.clips[c];
      // A frame midpoint, where interpolation matters most, and (cubic: each mode) a time in
      // the first and in the last interval.
      const double dt = clip.frame_interval_seconds;
      for (double t : {clip.frame_count > 4 ? dt * 3.5 : 0.0, 0.4 * dt,
                       clip.duration_seconds - 0.4 * dt}) {
        const FrameSample s = sampleFrames(clip, t);
        InstanceRecord rec{};
        rec.frames[0] = rec.frames[2] = clip.first_texel + s.frame * p.layout.frame_stride_texels;
        rec.frames[1] = rec.frames[3] = clip.first_texel + s.next_frame * p.layout.frame_stride_texels;
        rec.blend[0] = rec.blend[1] = packFraction(s.fraction, s.mode);
        // A world transform the compute capture must ignore (model space out on both paths).
        rec.world_rows[0][3] = 5.0f;
        rec.world_rows[1][1] = 2.0f;
        std::vector<glm::vec3> gpu_paths[2];
        ASSERT_TRUE(r.captureSkinnedPositions(CharacterId{}, rec, &gpu_paths[0],
                                              SkinningPath::kVertexShader)
                        .isOk());
        ASSERT_TRUE(
            r.captureSkinnedPositions(CharacterId{}, rec, &gpu_paths[1], SkinningPath::kCompute)
                .isOk());
        std::vector<glm::mat4> mats(character().skeleton.jointCount());
        ASSERT_TRUE(emulateSkinningMatrices(p, c, s, mats).isOk());
        std::vector<glm::vec3> cpu(mesh.vertexCount());
        ASSERT_TRUE(emulateSkinning(gpu_mesh, mats, cpu, {}).isOk());
        ReferencePose pose;
        const Clip& source = character().clips[size_t(character().findClip(clip.name))];
        ASSERT_TRUE(evaluateLocalPose(character().skeleton, source, t, &pose).isOk());
        std::vector<glm::dvec3> ref(mesh.vertexCount());
        ASSERT_TRUE(skinVertices(mesh, pose.skinning, ref, {}, {}).isOk());
        for (const std::vector<glm::vec3>& gpu : gpu_paths) {
          const char* path = &gpu == &gpu_paths[0] ? "vertex shader" : "compute";
          ASSERT_EQ(gpu.size(), cpu.size()) << path;
          double max_cpu = 0.0, max_ref = 0.0;
          for (size_t v = 0; v < gpu.size(); ++v) {
            max_cpu = std::max(max_cpu, double(glm::length(gpu[v] - cpu[v])));
            max_ref = std::max(max_ref, glm::length(glm::dvec3(gpu[v]) - ref[v]));
          }
          // Float rounding: a few ulps of coordinates up to 2 units.
          EXPECT_LT(max_cpu, 2e-5) << path << " " << clip.name << " t=" << t << " mode "
                                   << int(s.mode);
          // Within the bake's reported error for this clip, plus the same rounding.
          EXPECT_LE(max_ref, report.clips[c].max_error_units + 2e-5)
              << path << " " << clip.name << " t=" << t;
        }
      }
    }
  }
}

}  // namespace
}  // namespace si
