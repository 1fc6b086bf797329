// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The glTF metallic-roughness material on the GPU: a normal-mapped patch whose child joint
// turns (tests/gltf/pbr_asset.h) gives, at every covered pixel, the shading normal a CPU
// reference builds from the reference evaluator's skinned normal and tangent (the seed's
// tangent frame: tangent skinned as the normal, bitangent from their cross product) and the
// normal map's texel; alpha-masked texels are discarded; the built-in material lights it.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "gltf/pbr_asset.h"
#include "render/render_fixture.h"
#include "render/two_targets.h"
#include "si/core/impostor_level.h"
#include "si/core/reference_evaluator.h"
#include "si/gltf/gltf_import.h"

namespace si {
namespace {

using namespace test;

// Output 0: the surface's shading normal; output 1: its uv0, the tangent's w, coverage.
constexpr const char* kSurfaceProbe = R"(
layout(location = 0) out vec4 o_normal;
layout(location = 1) out vec4 o_uv;
void siMaterial(SiSurface s) {
  o_normal = vec4(s.normal, 1.0);
  o_uv = vec4(s.uv0, s.tangent.w, 1.0);
})";

class PbrMaterialTest : public RenderTest {
 protected:
  void SetUp() override {
    RenderTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    load(PbrAssetDesc{});
  }
  void load(const PbrAssetDesc& desc) {
    desc_ = desc;
    const std::string json = pbrAsset(desc);
    GltfImportReport report;
    const Status s = importGltfMemory(
        Span<const uint8_t>(reinterpret_cast<const uint8_t*>(json.data()), json.size()), "", {},
        &character_, &report);
    ASSERT_TRUE(s.isOk()) << s.toString();
    BakeDesc bd;
    bd.rate_mode = RateMode::kFixed;
    bd.sample_rate_hz = 30.0f;
    ASSERT_TRUE(bakePalette(character_, bd, &palette_, nullptr).isOk());
  }
  // The patch at kTime (the child joint turned) on `kind`, seen by `view` (from the front by
  // default), through `material_source` (nullptr: the built-in material); depth only with
  // `depth_only` (the instanced and both GPU-driven kinds).
  void drawPatch(PathKind kind, const char* material_source, Renderer* r, bool depth_only = false,
                 const Camera& view = camera()) {
    crowd_ = CrowdManager();  // A fresh crowd for each draw.
    RendererDesc rd;
    rd.skinning_path = kind == PathKind::kCompute || kind == PathKind::kGpuDrivenCompute
                           ? SkinningPath::kCompute : SkinningPath::kVertexShader;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(character_, palette_, &id).isOk());
    if (material_source != nullptr) {
      MaterialDesc md;
      md.name = "surface probe";
      md.source = material_source;
      MaterialId mid;
      const Status added = r->addMaterial(md, &mid);
      ASSERT_TRUE(added.isOk()) << added.toString();
      ASSERT_TRUE(r->setMaterial(id, mid).isOk());
    }
    CrowdDesc cd;
    cd.palette = &palette_;
    cd.sub_mesh_count = 1;
    cd.lod_count = 1;
    ASSERT_TRUE(crowd_.init(cd).isOk());
    InstanceDesc d;
    d.clip = 0;
    d.time_seconds = kTime;
    d.speed = 0.0f;
    InstanceHandle h;
    ASSERT_TRUE(crowd_.add(d, &h).isOk());
    ASSERT_TRUE(crowd_.update(0.0, view).isOk());
    DrawStats stats;
    const Status s = depth_only && kind == PathKind::kGpuDrivenCompute
                         ? r->drawCrowdGpuCulled(crowd_, view, &stats, DrawMode::kDepthOnly)
                         : drawOnPath(*r, kind, crowd_, view, &stats, depth_only);
    ASSERT_TRUE(s.isOk()) << s.toString();
  }
  static Camera camera() {
    return Camera::lookAt({0.1, 0.6, 1.6}, {0.0, 0.55, 0.0}, glm::vec3(0, 1, 0), 0.9f, 1.0f, 0.1f,
                          20.0f);
  }

  // The CPU reference of the shading normal at texture coordinate `uv`: the patch point it
  // maps to, its triangle's skinned normals and tangents (compareNormals) interpolated as the
  // rasterizer does, the tangent frame built, the map's texel applied.
  glm::dvec3 referenceNormal(const glm::dvec2& uv, const std::vector<glm::dvec3>& normals,
                             const std::vector<glm::dvec4>& tangents) const {
    const int n = desc_.cells;
    const double gx = uv.x * n, gy = (1.0 - uv.y) * n;  // Grid coordinates (y up the patch).
    const int i = std::clamp(int(gx), 0, n - 1), j = std::clamp(int(gy), 0, n - 1);
    const double fx = gx - i, fy = gy - j;
    const auto at = [&](int a, int b) { return size_t(b * (n + 1) + a); };
    size_t v[3];
    double w[3];
    if (fx >= fy) {  // Triangle (i, j), (i + 1, j), (i + 1, j + 1).
      v[0] = at(i, j), v[1] = at(i + 1, j), v[2] = at(i + 1, j + 1);
      w[0] = 1.0 - fx, w[1] = fx - fy, w[2] = fy;
    } else {  // Triangle (i, j), (i + 1, j + 1), (i, j + 1).
      v[0] = at(i, j), v[1] = at(i + 1, j + 1), v[2] = at(i, j + 1);
      w[0] = 1.0 - fy, w[1] = fx, w[2] = fy - fx;
    }
    glm::dvec3 normal(0.0), tangent(0.0);
    for (int k = 0; k < 3; ++k) {
      normal += w[k] * normals[v[k]];
      tangent += w[k] * glm::dvec3(tangents[v[k]]);
    }
    normal = glm::normalize(normal);
    tangent = glm::normalize(tangent - normal * glm::dot(normal, tangent));
    const glm::dvec3 bitangent = tangents[v[0]].w * glm::cross(normal, tangent);
    // The map's texel as stored (8 bits a channel), scaled in x and y as the material says.
    const uint32_t tx = std::min(uint32_t(uv.x * desc_.texture_size), desc_.texture_size - 1);
    const std::vector<float> t = pbrAssetNormal(tx, 0);
    glm::dvec3 m;
    for (int c = 0; c < 3; ++c) m[c] = std::lround((t[size_t(c)] * 0.5 + 0.5) * 255.0) / 255.0 * 2.0 - 1.0;
    m.x *= 0.8;
    m.y *= 0.8;
    return glm::normalize(m.x * tangent + m.y * bitangent + m.z * normal);
  }

  struct AngleStats {
    size_t pixels = 0;
    double mean_degrees = 0.0, max_degrees = 0.0;
  };
  // The drawn normals against the reference at every covered pixel whose uv lies inside a
  // stripe of the map (away from the filtered borders between stripes).
  AngleStats compareNormals(const TwoTargets& targets) const {
    // Per vertex, the reference pose's blended skinning matrix M (doubles): M on the tangent,
    // its cofactor on the normal, so the skinned frame stays orthogonal (what the shaders do).
    ReferencePose pose;
    EXPECT_TRUE(evaluatePose(character_.skeleton, character_.clips[0], kTime, &pose).isOk());
    const SkinnedMesh& mesh = character_.mesh;
    std::vector<glm::dvec3> normals(mesh.vertexCount());
    std::vector<glm::dvec4> tangents(mesh.vertexCount());
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
      glm::dmat3 m(0.0);
      for (int k = 0; k < 4; ++k)
        m += double(mesh.weights[v][k]) * glm::dmat3(pose.skinning[mesh.joints[v][k]]);
      const glm::dmat3 cofactor = glm::determinant(m) * glm::transpose(glm::inverse(m));
      normals[v] = glm::normalize(cofactor * glm::dvec3(mesh.normals[v]));
      tangents[v] = glm::dvec4(glm::normalize(m * glm::dvec3(mesh.tangents[v])), mesh.tangents[v].w);
    }
    const std::vector<glm::vec4> drawn = targets.readFloat(0), uvs = targets.readFloat(1);
    AngleStats st;
    for (size_t p = 0; p < drawn.size(); ++p) {
      if (uvs[p].a == 0.0f) continue;  // Background.
      const double texel = uvs[p].x * desc_.texture_size;
      const double in_stripe = std::fmod(texel, 4.0);
      if (in_stripe < 1.0 || in_stripe > 3.0) continue;
      const glm::dvec3 expected = referenceNormal(glm::dvec2(uvs[p]), normals, tangents);
      const glm::dvec3 got = glm::normalize(glm::dvec3(glm::vec3(drawn[p])));
      const double angle = glm::degrees(std::atan2(glm::length(glm::cross(got, expected)),
                                                   glm::dot(got, expected)));
      st.mean_degrees += angle;
      st.max_degrees = std::max(st.max_degrees, angle);
      ++st.pixels;
    }
    if (st.pixels > 0) st.mean_degrees /= double(st.pixels);
    return st;
  }

  // A renderer (vertex-shader skinning) drawing the loaded patch, with an impostor level
  // appended, through `material_source`, its impostor atlas built (ImpostorDesc's defaults).
  void makeImpostorRenderer(const char* material_source, Renderer* r) {
    ASSERT_TRUE(appendImpostorLevel(&character_.mesh).isOk());
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(character_, palette_, &id).isOk());
    MaterialDesc md;
    md.name = "probe";
    md.source = material_source;
    MaterialId mid;
    ASSERT_TRUE(r->addMaterial(md, &mid).isOk());
    ASSERT_TRUE(r->setMaterial(id, mid).isOk());
    ASSERT_TRUE(r->buildImpostor(id, ImpostorDesc{}).isOk());
  }
  // The patch at kTime drawn by `r` (makeImpostorRenderer's) on the instanced path from the
  // front, as an impostor or as its mesh, into the bound framebuffer.
  void drawImpostorLevel(Renderer& r, bool as_impostor) {
    CrowdManager crowd;
    CrowdDesc cd;
    cd.palette = &palette_;
    cd.sub_mesh_count = 1;
    cd.lod_count = uint32_t(character_.mesh.maxLodCount());
    cd.impostor_lod = cd.lod_count - 1;
    cd.lod_distances_radii = {as_impostor ? 1e-3f : 1e6f};
    ASSERT_TRUE(crowd.init(cd).isOk());
    InstanceDesc inst;
    inst.time_seconds = kTime;
    inst.speed = 0.0f;
    InstanceHandle h;
    ASSERT_TRUE(crowd.add(inst, &h).isOk());
    ASSERT_TRUE(crowd.update(0.0, camera()).isOk());
    ASSERT_EQ(crowd.stats().per_lod[as_impostor ? cd.impostor_lod : 0], 1u);
    DrawStats stats;
    ASSERT_TRUE(drawOnPath(r, PathKind::kInstanced, crowd, camera(), &stats).isOk());
  }

  // Near the clip's end (1 s, looping: 1.0 is its start again): the child turned 90 % of the
  // way, 36 degrees about z and 22 about y.
  static constexpr double kTime = 0.9;
  PbrAssetDesc desc_;
  Character character_;
  BakedPalette palette_;
  CrowdManager crowd_;
};

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
  constexpr const char* kPbrProbe = R"(
layout(location = 0) out vec4 o_pbr;
layout(location = 1) out vec4 o_index;
void siMaterial(SiSurface s) {
  o_pbr = vec4(s.metallic, s.roughness, s.occlusion, 1.0);
  o_index = vec4(float(s.material), s.impostor ? 1.0 : 0.0, 0.0, 1.0);
})";
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
class EsPbrMaterialTest : public PbrMaterialTest {
 protected:
  bool es() const override { return true; }
};

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
