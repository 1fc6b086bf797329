// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The glTF metallic-roughness material on the GPU: a normal-mapped patch whose child joint
// turns (tests/gltf/pbr_asset.h) gives, at every covered pixel, the shading normal a CPU
// reference builds from the reference evaluator's skinned normal and tangent (the seed's
// tangent frame: tangent skinned as the normal, bitangent from their cross product) and the
// normal map's texel; alpha-masked texels are discarded; the built-in material lights it.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render/pbr_material_fixture.h"
#include "render/pbr_probe.h"

namespace si {
namespace {

using namespace test;

// The seed's tangent frame on every mesh path: the drawn shading normal within 0.01 degrees of
// the CPU reference on average and 0.05 at worst (float math; measured 0.0000 mean and 0.0002
// max on llvmpipe for the vertex-shader paths, the pre-skinning paths' packed tangent adding
// its rounding). With the tangent left unskinned (only the instance's world transform applied)
// the error is 7.9 degrees on average and 17 at worst: the test sees the frame.
// The file's bitangent sign -1 (a mirrored mapping's) is followed too, on one path of each
// skinning code (the vertex shader, pre-skinning's packed tangent, the CPU); +1 on every path.
TEST_P(PbrMaterialTest, NormalMappedShadingFollowsTheSkinnedTangentFrame) {
  std::vector<std::pair<float, PathKind>> runs = {
      {-1.0f, PathKind::kInstanced}, {-1.0f, PathKind::kGpuDrivenCompute}, {-1.0f, PathKind::kCpu}};
  for (PathKind kind : kEveryPath) runs.emplace_back(1.0f, kind);
  for (const auto& [sign, kind] : runs) {
    SCOPED_TRACE(std::string(pathKindName(kind)) + (sign < 0.0f ? ", bitangent -1" : ""));
    PbrAssetDesc desc;
    desc.bitangent_sign = sign;
    load(desc);
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    Renderer r;
    drawPatch(kind, kSurfaceProbe, &r);
    if (HasFatalFailure()) return;
    const AngleStats st = compareNormals(targets);
    EXPECT_GT(st.pixels, size_t(kSize) * kSize / 20) << "the patch covers 5 % of the view";
    EXPECT_LT(st.mean_degrees, 0.01);
    EXPECT_LT(st.max_degrees, 0.05);
    const std::string name = pathKindName(kind) + std::string(sign < 0.0f ? "_mirrored" : "");
    RecordProperty("mean_degrees_" + name, std::to_string(st.mean_degrees));
    RecordProperty("max_degrees_" + name, std::to_string(st.max_degrees));
    std::printf(
        "[ normals  ] %s, bitangent %+.0f: %zu pixels, mean %.4f, max %.4f degrees from "
        "the CPU reference\n",
        pathKindName(kind), double(sign), st.pixels, st.mean_degrees, st.max_degrees);
  }
}

// Alpha MASK: the base colour alpha's left half (0) is cut, the right half drawn; the same
// patch opaque draws both halves.
TEST_P(PbrMaterialTest, AlphaMaskedTexelsAreDiscarded) {
  const auto coverage = [&](bool mask) {
    PbrAssetDesc d;
    d.mask = mask;
    load(d);
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    Renderer r;
    drawPatch(PathKind::kInstanced, kSurfaceProbe, &r);
    size_t left = 0, right = 0;
    for (const glm::vec4& t : targets.readFloat(1))
      if (t.a != 0.0f) (t.x < 0.5f ? left : right) += 1;
    return std::make_pair(left, right);
  };
  const auto opaque = coverage(false), masked = coverage(true);
  EXPECT_GT(opaque.first, 1000u);
  EXPECT_GT(opaque.second, 1000u);
  EXPECT_LT(masked.first, opaque.first / 50) << "the masked half is discarded";
  EXPECT_GT(masked.second, opaque.second * 9 / 10) << "the opaque half is drawn";
}

// Alpha MASK in depth-only draws (shadow maps, depth pre-passes): exactly the colour draw's
// covered pixels get depth, on the vertex-shader, GPU-driven and GPU-driven pre-skinned depth
// programs; the opaque patch's depth-only draw covers the masked half too (so the comparison
// sees a depth-only draw that ignores the mask).
TEST_P(PbrMaterialTest, AlphaMaskedTexelsAreDiscardedFromDepthOnlyDraws) {
  const auto covered = [&](bool mask, PathKind kind, bool depth_only) {
    PbrAssetDesc d;
    d.mask = mask;
    load(d);
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    Renderer r;
    drawPatch(kind, kSurfaceProbe, &r, depth_only);
    std::vector<bool> out;
    if (depth_only) {
      for (const float z : targets.readDepth()) out.push_back(z < 1.0f);
    } else {
      for (const glm::vec4& t : targets.readFloat(1)) out.push_back(t.a != 0.0f);
    }
    return out;
  };
  const auto count = [](const std::vector<bool>& v) {
    return std::count(v.begin(), v.end(), true);
  };
  const std::vector<bool> colour = covered(true, PathKind::kInstanced, false);
  ASSERT_GT(count(colour), 1000);
  for (PathKind kind : {PathKind::kInstanced, PathKind::kGpuDriven, PathKind::kGpuDrivenCompute}) {
    SCOPED_TRACE(pathKindName(kind));
    const std::vector<bool> masked = covered(true, kind, true);
    const std::vector<bool> opaque = covered(false, kind, true);
    if (HasFatalFailure()) return;
    size_t differing = 0;
    for (size_t p = 0; p < colour.size(); ++p) differing += masked[p] != colour[p] ? 1 : 0;
    EXPECT_EQ(differing, 0u)
        << "depth-only pixels where the colour draw has none, or none where it has";
    EXPECT_GT(count(opaque), count(colour) * 3 / 2)
        << "the opaque patch's depth covers both halves";
  }
}

// Alpha MASK in the impostor capture: the masked patch's impostor covers about half what the
// opaque patch's does (the atlas keeps the mask's coverage); capturing without the discard
// gives the same coverage for both.
TEST_P(PbrMaterialTest, AlphaMaskedTexelsAreLeftOutOfTheImpostorAtlas) {
  const auto impostorCoverage = [&](bool mask) -> size_t {
    PbrAssetDesc d;
    d.mask = mask;
    load(d);
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    Renderer r;
    makeImpostorRenderer(kSurfaceProbe, &r);
    drawImpostorLevel(r, true);
    size_t covered = 0;
    for (const glm::vec4& t : targets.readFloat(1)) covered += t.a != 0.0f ? 1 : 0;
    return covered;
  };
  const size_t opaque = impostorCoverage(false), masked = impostorCoverage(true);
  std::printf("[ impostor ] covered pixels: opaque %zu, masked %zu\n", opaque, masked);
  EXPECT_GT(opaque, 1000u);
  EXPECT_GT(masked, opaque * 3 / 10);
  EXPECT_LT(masked, opaque * 7 / 10) << "the masked half is not in the atlas";
}

// Impostors carry the surface a material reads: drawn as an impostor, the patch hands the
// material the metallic, roughness and occlusion its mesh does (means over the covered pixels
// within 0.05; the atlas keeps 8 bits and filters them) and the mesh's material index.
TEST_P(PbrMaterialTest, ImpostorsHandTheMaterialTheMeshesMetallicRoughnessOcclusionAndIndex) {
  Renderer r;
  makeImpostorRenderer(kPbrProbe, &r);
  if (HasFatalFailure()) return;
  struct Means {
    size_t pixels = 0, impostor = 0, index_one = 0;
    glm::dvec3 pbr{0.0};
  };
  const auto draw = [&](bool as_impostor) {
    TwoTargets targets(kSize, GL_RGBA32F);
    targets.clear(glm::vec4(0.0f));
    drawImpostorLevel(r, as_impostor);
    Means m;
    const std::vector<glm::vec4> pbr = targets.readFloat(0), index = targets.readFloat(1);
    for (size_t p = 0; p < pbr.size(); ++p) {
      if (index[p].a == 0.0f) continue;
      ++m.pixels;
      m.pbr += glm::dvec3(glm::vec3(pbr[p]));
      m.impostor += index[p].y == 1.0f ? 1 : 0;
      m.index_one += index[p].x == 1.0f ? 1 : 0;  // The patch's material (0: the default).
    }
    if (m.pixels > 0) m.pbr /= double(m.pixels);
    return m;
  };
  const Means mesh = draw(false), impostor = draw(true);
  std::printf(
      "[ impostor ] metallic, roughness, occlusion: mesh %.3f %.3f %.3f, impostor %.3f "
      "%.3f %.3f\n",
      mesh.pbr.x, mesh.pbr.y, mesh.pbr.z, impostor.pbr.x, impostor.pbr.y, impostor.pbr.z);
  ASSERT_GT(mesh.pixels, 1000u);
  ASSERT_GT(impostor.pixels, 1000u);
  EXPECT_EQ(mesh.impostor, 0u);
  EXPECT_EQ(impostor.impostor, impostor.pixels);
  EXPECT_EQ(mesh.index_one, mesh.pixels);
  EXPECT_EQ(impostor.index_one, impostor.pixels) << "the impostor hands the mesh's material index";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(impostor.pbr[c], mesh.pbr[c], 0.05) << "channel " << c;
}

// glTF doubleSided: seen from behind, a single-sided patch is culled, a double-sided one is
// drawn on every path with its shading normal turned towards the viewer.
TEST_P(PbrMaterialTest, DoubleSidedMaterialsDrawTheirBackFaces) {
  const Camera behind = Camera::lookAt({-0.1, 0.6, -1.6}, {0.0, 0.55, 0.0}, glm::vec3(0, 1, 0),
                                       0.9f, 1.0f, 0.1f, 20.0f);
  for (const bool double_sided : {false, true}) {
    PbrAssetDesc d;
    d.double_sided = double_sided;
    load(d);
    for (PathKind kind : kEveryPath) {
      // Single-sided: the culling every path shares, seen once.
      if (!double_sided && kind != PathKind::kInstanced) continue;
      SCOPED_TRACE(std::string(pathKindName(kind)) + (double_sided ? ", double-sided" : ""));
      TwoTargets targets(kSize, GL_RGBA32F);
      targets.clear(glm::vec4(0.0f));
      Renderer r;
      drawPatch(kind, kSurfaceProbe, &r, false, behind);
      if (HasFatalFailure()) return;
      const std::vector<glm::vec4> normals = targets.readFloat(0), uvs = targets.readFloat(1);
      size_t covered = 0, facing = 0;
      for (size_t p = 0; p < normals.size(); ++p) {
        if (uvs[p].a == 0.0f) continue;
        ++covered;
        facing += normals[p].z < 0.0f ? 1 : 0;  // Towards the camera behind the patch.
      }
      if (!double_sided) {
        EXPECT_EQ(covered, 0u) << "back faces of a single-sided material are culled";
      } else {
        EXPECT_GT(covered, size_t(kSize) * kSize / 20);
        EXPECT_EQ(facing, covered) << "the back face's normal is turned";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, PbrMaterialTest, test::allBackends(), test::backendTestName);

// The OpenGL ES profile's depth-only draws take the alpha mask too (its one depth-only program,
// built for a masked character from the ES surface stage). ES 3.0 reads no depth back, so the
// depth is seen through a colour pass: after the masked patch's depth-only draw, the opaque
// patch drawn with GL_LESS at the same depths shows only where the mask left no depth (the
// masked half); after the opaque patch's depth-only draw, almost nothing.

TEST_P(EsPbrMaterialTest, AlphaMaskedTexelsAreDiscardedFromDepthOnlyDraws) {
  const auto shownAfterDepth = [&](bool mask) -> size_t {
    PbrAssetDesc d;
    d.mask = mask;
    load(d);
    Renderer depth;
    depth.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    drawPatch(PathKind::kInstanced, nullptr, &depth, true);
    load(PbrAssetDesc{});
    Renderer colour;
    glDepthFunc(GL_LESS);
    drawPatch(PathKind::kInstanced, nullptr, &colour);
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    size_t shown = 0;
    for (size_t p = 0; p < rgba.size(); p += 4) shown += rgba[p] + rgba[p + 1] + rgba[p + 2] > 0;
    return shown;
  };
  const size_t masked = shownAfterDepth(true), opaque = shownAfterDepth(false);
  std::printf("[ ES depth ] shown after the masked depth %zu, after the opaque depth %zu\n", masked,
              opaque);
  EXPECT_GT(masked, 1000u) << "the masked half wrote no depth";
  EXPECT_LT(opaque, masked / 20) << "the opaque patch's depth hides its colour";
}

INSTANTIATE_TEST_SUITE_P(Backends, EsPbrMaterialTest, test::esBackends(), test::backendTestName);

}  // namespace
}  // namespace si