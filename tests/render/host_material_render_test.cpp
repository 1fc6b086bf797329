// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Host materials (si/gl/material.h): a material of the host's writing two render targets, lit by
// the host's own uniform block, draws the same two images on every path (instanced, compute
// pre-skinning, GPU-driven with and without pre-skinning and occlusion culling, the traditional
// and CPU-skinning baselines) and on impostors; depth-only draws take its discards; its compile
// errors name its own lines; what it may not declare is refused by name.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "render/host_material_fixture.h"

namespace si {
namespace {

using namespace test;

TEST_P(HostMaterialTest, AHostMaterialWritingTwoTargetsDrawsTheSameImagesOnEveryPath) {
  TwoTargets targets(kSize);
  ASSERT_TRUE(targets.complete());
  HostLight light(glm::vec3(0.3f, -1.0f, -0.5f), glm::vec3(1.0f, 0.0f, 0.0f));  // Red only.
  CrowdManager crowd;
  sceneCrowd(&crowd);
  Renderer vs, cs;
  makeMaterialRenderer(&vs, SkinningPath::kVertexShader);
  makeMaterialRenderer(&cs, SkinningPath::kCompute);
  const std::vector<uint8_t> lit =
      expectTheSameImagesOnEveryPath(vs, cs, crowd, targets, lodCamera()).first;

  // The same renderer with the built-in material draws the built-in image into target 0.
  ASSERT_TRUE(vs.setMaterial(CharacterId{}, kBuiltinMaterial).isOk());
  drawInto(vs, PathKind::kInstanced, crowd, targets);
  EXPECT_GT(compare(targets.read(0), lit, nullptr).share, 0.01);
  Renderer builtin;
  makeRenderer(&builtin);
  drawInto(builtin, PathKind::kInstanced, crowd, targets);
  const std::vector<uint8_t> builtin_image = targets.read(0);
  drawInto(vs, PathKind::kInstanced, crowd, targets);
  EXPECT_EQ(compare(targets.read(0), builtin_image, nullptr).max_channel, 0);
}

// The same into the host's targets multisampled (4 samples, resolved for the comparison) and
// y-flipped (a render texture's projection: the standard images upside down).
TEST_P(HostMaterialTest, EveryPathDrawsTheSameImagesIntoMultisampledAndYFlippedTargets) {
  HostLight light(glm::vec3(0.3f, -1.0f, -0.5f), glm::vec3(1.0f, 0.0f, 0.0f));
  CrowdManager crowd;
  sceneCrowd(&crowd);
  Renderer vs, cs;
  makeMaterialRenderer(&vs, SkinningPath::kVertexShader);
  makeMaterialRenderer(&cs, SkinningPath::kCompute);
  {
    SCOPED_TRACE("4 samples");
    TwoTargets multisampled(kSize, GL_RGBA8, 4);
    ASSERT_TRUE(multisampled.complete());
    const std::vector<uint8_t> surface =
        expectTheSameImagesOnEveryPath(vs, cs, crowd, multisampled, lodCamera(), true).second;
    size_t blended = 0;  // Edges resolved to a blend of a LOD's alpha and the background's 0.
    for (size_t p = 3; p < surface.size(); p += 4)
      blended += surface[p] != 0 && surface[p] != 32 && surface[p] != 64 && surface[p] != 96;
    EXPECT_GT(blended, 100u) << "the target is multisampled";
  }
  {
    SCOPED_TRACE("y-flipped");
    TwoTargets standard(kSize);
    drawInto(vs, PathKind::kInstanced, crowd, standard);
    const std::vector<uint8_t> upright = standard.read(0);
    const std::vector<uint8_t> lit =
        expectTheSameImagesOnEveryPath(vs, cs, crowd, standard, yFlipped(lodCamera())).first;
    const Diff d = compare(lit, flipped(upright), nullptr);
    EXPECT_LE(d.share, 0.001) << "the standard image upside down; max channel " << d.max_channel;
  }
}

// A mesh's texture coordinates 1 and vertex colours reach the material on every path: a
// material writing uv1 and the colour's blue (target 1) and the albedo's red (target 0: the
// colour multiplies the base colour) draws the same images on every path; a
// mesh without them hands the material 0 and white.
TEST_P(HostMaterialTest, SecondTextureCoordinatesAndVertexColoursReachTheMaterialOnEveryPath) {
  constexpr const char* kVertexWords = R"(
layout(location = 0) out vec4 o_lit;
layout(location = 1) out vec4 o_surface;
void siMaterial(SiSurface s) {
  o_lit = vec4(siSurfaceAlbedo(s).r, 0.0, 0.0, 1.0);
  o_surface = vec4(s.uv1, s.color.b, s.impostor ? 1.0 : float(s.lod + 1u) / 8.0);
})";
  TwoTargets targets(kSize);
  CrowdManager crowd;
  sceneCrowd(&crowd);
  Character painted = character();
  for (const glm::vec3& p : painted.mesh.positions) {
    painted.mesh.texcoords1.push_back(
        glm::clamp(glm::vec2(p.y * 0.5f, p.x + 0.5f), glm::vec2(0.0f), glm::vec2(1.0f)));
    painted.mesh.colors.push_back(glm::vec4(0.3f + 0.7f * glm::fract(p.y * 2.3f), 1.0f,
                                            0.2f + 0.8f * glm::fract(p.x * 3.1f + p.z), 1.0f));
  }
  Renderer vs, cs, plain;
  makeMaterialRenderer(&vs, SkinningPath::kVertexShader, &painted, false, kVertexWords);
  makeMaterialRenderer(&cs, SkinningPath::kCompute, &painted, false, kVertexWords);
  std::vector<uint8_t> lit, surface;
  std::tie(lit, surface) = expectTheSameImagesOnEveryPath(vs, cs, crowd, targets, lodCamera());
  // The plain character (every path's fragment stage decides by the same flags).
  makeMaterialRenderer(&plain, SkinningPath::kVertexShader, nullptr, false, kVertexWords);
  drawInto(plain, PathKind::kInstanced, crowd, targets);
  const std::vector<uint8_t> plain_lit = targets.read(0), plain_surface = targets.read(1);
  // What reached the material: uv1 and the colour's blue spread over their ranges; without
  // them, 0 and 1 everywhere.
  std::set<uint8_t> u, v, blue;
  size_t plain_drawn = 0, plain_wrong = 0;
  uint64_t red = 0, plain_red = 0;
  for (size_t p = 0; p < surface.size(); p += 4) {
    if (surface[p + 3] != 0) {
      u.insert(surface[p]);
      v.insert(surface[p + 1]);
      blue.insert(surface[p + 2]);
      red += lit[p];
    }
    if (plain_surface[p + 3] != 0) {
      ++plain_drawn;
      plain_wrong +=
          plain_surface[p] != 0 || plain_surface[p + 1] != 0 || plain_surface[p + 2] != 255;
      plain_red += plain_lit[p];
    }
  }
  EXPECT_GT(u.size(), 40u);
  EXPECT_GT(v.size(), 40u);
  EXPECT_GT(blue.size(), 40u);
  EXPECT_GT(plain_drawn, 2000u);
  EXPECT_EQ(plain_wrong, 0u);
  // The colour's red (0.3 to 1) multiplies the base colour.
  EXPECT_LT(double(red), 0.9 * double(plain_red));
}

TEST_P(HostMaterialTest, ImpostorsHandTheirSurfaceToTheHostMaterial) {
  TwoTargets targets(kSize);
  HostLight light(glm::vec3(0.3f, -1.0f, -0.5f), glm::vec3(0.0f, 1.0f, 0.0f));  // Green only.
  CrowdManager crowd;
  impostorRowsCrowd(3.0, 30.0, 20.0, &crowd);
  Renderer r;
  makeMaterialRenderer(&r, SkinningPath::kVertexShader, &impostorCharacter());
  ImpostorDesc id;
  id.azimuths = 8;
  id.frames_per_clip = 4;
  ASSERT_TRUE(r.buildImpostor(CharacterId{}, id).isOk());
  drawInto(r, PathKind::kInstanced, crowd, targets);
  const std::vector<uint8_t> lit = targets.read(0), surface = targets.read(1);
  size_t impostor_pixels = 0, red_or_blue = 0;
  for (size_t p = 0; p < lit.size(); p += 4) {
    if (surface[p + 3] == 0) continue;
    impostor_pixels += surface[p + 3] == 255;
    red_or_blue += lit[p] != 0 || lit[p + 2] != 0;
  }
  EXPECT_GT(impostor_pixels, 100u);  // SiSurface.impostor reached the material,
  EXPECT_EQ(red_or_blue, 0u);        // which lit them with the host's tone.
  // The GPU-driven impostors draw the same.
  drawInto(r, PathKind::kGpuDriven, crowd, targets);
  EXPECT_LE(compare(targets.read(0), lit, nullptr).share, 0.001);
  EXPECT_LE(compare(targets.read(1), surface, nullptr).share, 0.001);
}

// A material that discards the upper half of the character (above 1 unit: an alpha test's
// stand-in): depth-only draws with depth_discard leave that depth unwritten, on the instanced
// and the GPU-driven path alike; without it they write every covered fragment.
TEST_P(HostMaterialTest, DepthOnlyDrawsTakeTheMaterialsDiscards) {
  constexpr const char* kCut = R"(
layout(location = 0) out vec4 o_color;
void siMaterial(SiSurface s) {
  if (s.normal.y > 0.2) discard;
#ifndef SI_DEPTH_ONLY
  o_color = vec4(siSurfaceAlbedo(s), 1.0);
#endif
})";
  TwoTargets targets(kSize);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  ASSERT_TRUE(crowd.update(0.3, lodCamera()).isOk());
  const auto written = [](const std::vector<float>& depth) {
    return size_t(std::count_if(depth.begin(), depth.end(), [](float z) { return z < 1.0f; }));
  };
  Renderer cut, whole;
  makeMaterialRenderer(&cut, SkinningPath::kVertexShader, nullptr, true, kCut);
  makeMaterialRenderer(&whole, SkinningPath::kVertexShader, nullptr, false, kCut);
  drawInto(whole, PathKind::kInstanced, crowd, targets, true);
  const std::vector<float> all = targets.readDepth();
  drawInto(cut, PathKind::kInstanced, crowd, targets, true);
  const std::vector<float> some = targets.readDepth();
  EXPECT_GT(written(all), 2000u);
  EXPECT_LT(written(some), written(all) * 9 / 10);
  EXPECT_GT(written(some), written(all) / 10);
  // The colour pass covers what the depth-only pass wrote.
  drawInto(cut, PathKind::kInstanced, crowd, targets);
  EXPECT_LE(differingDepths(targets.readDepth(), some), some.size() / 1000);
  // The GPU-driven depth-only pass (vertex-shader skinning and pre-skinning) discards alike.
  drawInto(cut, PathKind::kGpuDriven, crowd, targets, true);
  EXPECT_LE(differingDepths(targets.readDepth(), some), some.size() / 1000);
  Renderer cut_compute;
  makeMaterialRenderer(&cut_compute, SkinningPath::kCompute, nullptr, true, kCut);
  drawInto(cut_compute, PathKind::kGpuDriven, crowd, targets, true);
  EXPECT_LE(differingDepths(targets.readDepth(), some), some.size() / 1000);
}

TEST_P(HostMaterialTest, ACompileErrorNamesTheMaterialsOwnLine) {
  Renderer r;
  makeRenderer(&r);
  MaterialDesc md;
  md.name = "broken";
  md.source = "layout(location = 0) out vec4 o_color;\n"
              "void siMaterial(SiSurface s) {\n"
              "  o_color = vec4(s.no_such_field, 1.0);\n"
              "}\n";
  MaterialId id;
  const Status s = r.addMaterial(md, &id);
  EXPECT_EQ(s.code(), StatusCode::kBackend);
  EXPECT_NE(s.message().find("material 'broken'"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("numbered from 1"), std::string::npos) << s.message();
  if (info_.renderer.find("llvmpipe") != std::string::npos) {  // Mesa: "0:3(17): error: ..."
    EXPECT_NE(s.message().find(":3(17): error"), std::string::npos) << s.message();
  }
  EXPECT_EQ(r.setMaterial(CharacterId{}, MaterialId{1}).code(), StatusCode::kInvalidArgument);
}

TEST_P(HostMaterialTest, ResourcesTheLibraryCannotLeaveAloneAreRefusedByName) {
  Renderer r;
  makeRenderer(&r);
  const auto refusal = [&](const char* source) {
    MaterialDesc md;
    md.name = "refused";
    md.source = source;
    MaterialId id;
    const Status s = r.addMaterial(md, &id);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    return s.message();
  };
  EXPECT_NE(refusal("uniform float u_gain;\nlayout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { o = vec4(u_gain); }")
                .find("'u_gain' is a loose uniform"),
            std::string::npos);
  EXPECT_NE(refusal("layout(binding = 1) uniform sampler2D host_map;\n"
                    "layout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { o = texture(host_map, s.uv0); }")
                .find("sampler 'host_map' is at texture unit 1, where the library's draws bind "
                      "their own 'u_base_color'"),
            std::string::npos);
  // The morph targets' unit, which only the programs of a character with targets declare.
  EXPECT_NE(refusal("layout(binding = 5) uniform sampler2D host_map;\n"
                    "layout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { o = texture(host_map, s.uv0); }")
                .find("sampler 'host_map' is at texture unit 5, where the library's draws bind "
                      "their own 'si_morphs'"),
            std::string::npos);
  EXPECT_NE(refusal("layout(std140, binding = 4) uniform Host { vec4 gain; };\n"
                    "layout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { o = gain; }")
                .find("uniform block 'Host' is at uniform buffer binding 4"),
            std::string::npos);
  EXPECT_NE(refusal("layout(std430, binding = 10) readonly buffer Host { vec4 gain[]; };\n"
                    "layout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { o = gain[0]; }")
                .find("storage block 'Host' is at shader storage binding 10"),
            std::string::npos);
  EXPECT_NE(refusal("layout(binding = 0, rgba8) writeonly uniform image2D host_image;\n"
                    "layout(location = 0) out vec4 o;\n"
                    "void siMaterial(SiSurface s) { imageStore(host_image, ivec2(0), vec4(1));"
                    " o = vec4(1); }")
                .find("image 'host_image' is at image unit 0"),
            std::string::npos);
  EXPECT_NE(refusal("#version 450\nvoid siMaterial(SiSurface s) {}").find("#version"),
            std::string::npos);
  MaterialDesc unnamed;
  unnamed.source = "void siMaterial(SiSurface s) {}";
  MaterialId id;
  EXPECT_EQ(r.addMaterial(unnamed, &id).code(), StatusCode::kInvalidArgument);
  // The refusals added nothing: the next material is 1.
  MaterialDesc fine;
  fine.name = "fine";
  fine.source = "layout(location = 0) out vec4 o;\nvoid siMaterial(SiSurface s) { o = s.base_color; }";
  ASSERT_TRUE(r.addMaterial(fine, &id).isOk());
  EXPECT_EQ(id.index, 1u);
}

INSTANTIATE_TEST_SUITE_P(Backends, HostMaterialTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
