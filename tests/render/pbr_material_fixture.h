// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The glTF metallic-roughness material render tests' fixture: the generated patch
// (tests/gltf/pbr_asset.h) imported and baked, drawn on any path through the built-in or a
// probe material, with a CPU reference of its normal-mapped shading normal.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "gltf/pbr_asset.h"
#include "render/render_fixture.h"
#include "render/two_targets.h"
#include "si/core/impostor_level.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"

namespace si::test {

// Output 0: the surface's shading normal; output 1: its uv0, the tangent's w, coverage.
inline constexpr const char* kSurfaceProbe = R"(
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
                           ? SkinningPath::kCompute
                           : SkinningPath::kVertexShader;
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
                         ? r->drawCrowdGpuCulled(si::CharacterId{}, crowd_.view(), view, &stats,
                                                 DrawMode::kDepthOnly)
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
    for (int c = 0; c < 3; ++c)
      m[c] = std::lround((t[size_t(c)] * 0.5 + 0.5) * 255.0) / 255.0 * 2.0 - 1.0;
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
      tangents[v] =
          glm::dvec4(glm::normalize(m * glm::dvec3(mesh.tangents[v])), mesh.tangents[v].w);
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
      const double angle =
          glm::degrees(std::atan2(glm::length(glm::cross(got, expected)), glm::dot(got, expected)));
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
    ASSERT_EQ(crowd.view().stats().per_lod[as_impostor ? cd.impostor_lod : 0], 1u);
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

// The same on the OpenGL ES profile.
class EsPbrMaterialTest : public PbrMaterialTest {
 protected:
  bool es() const override { return true; }
};

}  // namespace si::test
