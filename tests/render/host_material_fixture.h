// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The host material render tests' fixture: a material of the host's writing two render targets
// (kTwoTargets, lit by the host's uniform block HostLight), renderers drawing it, and the check
// that every path draws the instanced path's two images.
#include <glad/gl.h>

#include <set>
#include <utility>
#include <vector>

#include "render/render_fixture.h"
#include "render/two_targets.h"

namespace si::test {

// Output 0: the built-in albedo under the host's light and tone (its uniform block at binding
// 7); output 1: where the fragment is (fract of its camera-relative position) and, in alpha,
// its LOD + 1 in eighths (the impostors': 1; the cleared background: 0).
constexpr const char* kTwoTargets = R"(
layout(location = 0) out vec4 o_lit;
layout(location = 1) out vec4 o_surface;
layout(std140, binding = 7) uniform HostLight {
  vec4 host_direction;
  vec4 host_tone;
};
void siMaterial(SiSurface s) {
  float diffuse = max(dot(s.normal, -host_direction.xyz), 0.0);
  o_lit = vec4(siSurfaceAlbedo(s) * host_tone.rgb * (0.25 + 0.75 * diffuse), 1.0);
  o_surface = vec4(fract(s.position * 0.73), s.impostor ? 1.0 : float(s.lod + 1u) / 8.0);
})";

// The host's uniform block of kTwoTargets, bound at uniform buffer binding 7.
class HostLight {
 public:
  HostLight(const glm::vec3& direction, const glm::vec3& tone) {
    const glm::vec4 data[2] = {glm::vec4(glm::normalize(direction), 0.0f), glm::vec4(tone, 1.0f)};
    glCreateBuffers(1, &buffer_);
    glNamedBufferStorage(buffer_, sizeof(data), data, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, 7, buffer_);
  }
  ~HostLight() { glDeleteBuffers(1, &buffer_); }

 private:
  GLuint buffer_ = 0;
};

// Pixels whose alpha channels differ (compare() looks at RGB only).
inline size_t differingAlpha(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  size_t n = 0;
  for (size_t p = 3; p < a.size() && p < b.size(); p += 4) n += a[p] != b[p];
  return n;
}

class HostMaterialTest : public RenderTest {
 protected:
  // A renderer on `path` with the default character (or `c`) and the two-target material set
  // on it.
  void makeMaterialRenderer(Renderer* r, SkinningPath path, const Character* c = nullptr,
                            bool depth_discard = false, const char* source = kTwoTargets,
                            bool instance_handle = false) {
    RendererDesc rd;
    rd.skinning_path = path;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(c ? *c : character(), palette(), &id).isOk());
    MaterialDesc md;
    md.name = "two targets";
    md.source = source;
    md.depth_discard = depth_discard;
    md.instance_handle = instance_handle;
    MaterialId material;
    const Status s = r->addMaterial(md, &material);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_NE(material, kBuiltinMaterial);
    ASSERT_TRUE(r->setMaterial(id, material).isOk());
    EXPECT_EQ(r->material(id), material);
  }

  // Draws `crowd` with `r` on `kind` (depth only when `depth_only`) seen by `camera` into
  // `targets` after clearing them.
  void drawInto(Renderer& r, PathKind kind, const CrowdManager& crowd, const TwoTargets& targets,
                bool depth_only = false, const Camera& camera = lodCamera()) {
    targets.clear();
    DrawStats stats;
    const Status s = drawOnPath(r, kind, crowd, camera, &stats, depth_only);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_GT(stats.draw_calls, 0u);
  }

  // The two-target material on the instanced path, seen by `camera` into `targets` (`resolved`:
  // multisampled ones), then on every other path (vertex-shader and compute renderers `vs` and
  // `cs`), each drawing the same two images; the instanced path's images.
  std::pair<std::vector<uint8_t>, std::vector<uint8_t>> expectTheSameImagesOnEveryPath(
      Renderer& vs, Renderer& cs, const CrowdManager& crowd, const TwoTargets& targets,
      const Camera& camera, bool resolved = false) {
    drawInto(vs, PathKind::kInstanced, crowd, targets, false, camera);
    const std::vector<uint8_t> lit = targets.read(0), surface = targets.read(1);
    // The material drew: the host's tone (red only) everywhere the crowd is, every LOD in the
    // second target's alpha. Resolved, edges blend with the background, and far characters
    // cover no whole pixel: only what is drawn is checked there.
    size_t drawn = 0, green_or_blue = 0;
    std::set<uint8_t> lods;
    for (size_t p = 0; p < lit.size(); p += 4) {
      if (surface[p + 3] == 0) continue;  // Background.
      ++drawn;
      green_or_blue += lit[p + 1] != 0 || lit[p + 2] != 0;
      lods.insert(surface[p + 3]);
    }
    EXPECT_GT(drawn, 2000u);
    if (!resolved) {
      EXPECT_EQ(green_or_blue, 0u);
      EXPECT_EQ(lods, (std::set<uint8_t>{32, 64, 96})) << "LOD + 1 in eighths: the crowd's 3 LODs";
    }

    struct Case {
      const char* name;
      Renderer* r;
      PathKind kind;
      bool occlusion;
    };
    for (const Case& k :
         {Case{"compute", &cs, PathKind::kCompute, false},
          Case{"gpu-driven", &vs, PathKind::kGpuDriven, false},
          Case{"gpu-driven compute", &cs, PathKind::kGpuDrivenCompute, false},
          Case{"gpu-driven occlusion", &vs, PathKind::kGpuDriven, true},
          Case{"gpu-driven compute occlusion", &cs, PathKind::kGpuDrivenCompute, true},
          Case{"traditional", &vs, PathKind::kTraditional, false},
          Case{"cpu-skinned", &vs, PathKind::kCpu, false}}) {
      SCOPED_TRACE(k.name);
      k.r->setGpuOcclusionCulling(k.occlusion);
      drawInto(*k.r, k.kind, crowd, targets, false, camera);
      if (k.occlusion)  // Last frame's visible set.
        drawInto(*k.r, k.kind, crowd, targets, false, camera);
      k.r->setGpuOcclusionCulling(false);
      const std::vector<uint8_t> lit_k = targets.read(0), surface_k = targets.read(1);
      const Diff d0 = compare(lit_k, lit, nullptr), d1 = compare(surface_k, surface, nullptr);
      EXPECT_LE(d0.share, 0.001) << "target 0, max channel difference " << d0.max_channel;
      EXPECT_LE(d1.share, 0.002) << "target 1, max channel difference " << d1.max_channel;
      EXPECT_LE(differingAlpha(surface_k, surface), lit.size() / 4 / 1000) << "the LODs";
    }
    return {lit, surface};
  }

  // The crowd of these tests: the LOD rows and a crossfading character.
  void sceneCrowd(CrowdManager* crowd) {
    makeCrowd(crowd);
    populateLodCrowd(crowd);
    addFadingCharacter(crowd);
    ASSERT_TRUE(crowd->update(0.3, lodCamera()).isOk());
  }
};

}  // namespace si::test
