// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What the morph target render tests share (morph_render_test.cpp, morph_blend_render_test.cpp):
// the embedded character with face-like targets (examples/common/face_targets.h), three heads of
// it, the camera close to them, the bakes at 30 Hz and the fixture.
#include "common/face_targets.h"
#include "render/render_fixture.h"
#include "si/crowd/crowd_manager.h"

namespace si::test {

// The morph tests' fixture.
class MorphRenderFixture : public RenderTest {
 protected:
  // A renderer with the default description, `c` added as `*id`, and a batcher for it.
  void initRenderer(const Character& c, const BakedPalette& palette, Renderer* r, CharacterId* id,
                    InstanceBatcher* batcher) {
    ASSERT_TRUE(r->init(info_, RendererDesc()).isOk());
    ASSERT_TRUE(r->addCharacter(c, palette, id).isOk());
    ASSERT_TRUE(batcher->init(r->batchLimits()).isOk());
  }
};

// The embedded character with `targets` face-like targets.
inline Character morphCharacter(size_t targets) {
  Character c = character();
  examples::addFaceTargets(&c, targets);
  return c;
}

// Three heads, at different times of the clip and tinted apart; the middle one crossfading
// into another clip. `lod_distances` as CrowdDesc::lod_distances_radii (empty: the defaults).
inline Status headCrowd(const Character& c, const BakedPalette& palette, CrowdManager* crowd,
                        std::vector<float> lod_distances = {}) {
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(c.mesh.maxLodCount());
  cd.lod_distances_radii = std::move(lod_distances);
  Status s = crowd->init(cd);
  for (int k = 0; k < 3 && s.isOk(); ++k) {
    InstanceDesc d;
    d.position = glm::dvec3(-0.5 + 0.5 * k, 0.0, -0.4 * std::abs(k - 1));
    d.time_seconds = 0.2 + 0.35 * k;
    d.color = glm::u8vec4(uint8_t(120 + 60 * k), 200, 160, 255);
    InstanceHandle h;
    s = crowd->add(d, &h);
    if (s.isOk() && k == 1) s = crowd->crossfade(h, 1, 0.5);
  }
  return s;
}

// Close to the heads, where the targets move them.
inline Camera headCamera(const Character& c) {
  const Aabb box = c.bindPoseBounds();
  const double y = box.min.y + 0.9 * (box.max.y - box.min.y);
  return Camera::lookAt({0.0, y + 0.1, 1.3}, {0.0, y, 0.0}, glm::vec3(0, 1, 0), 1.0f, 1.0f, 0.1f,
                        100.0f);
}

// The bakes at a fixed 30 Hz: what a render test compares is the draw, not the bake's choice.
inline BakedPalette bakeAt30(const Character& c, BakeReport* report = nullptr) {
  BakedPalette p;
  BakeDesc d;
  d.rate_mode = RateMode::kFixed;
  d.sample_rate_hz = 30.0f;
  if (!bakePalette(c, d, &p, report).isOk()) std::abort();
  return p;
}

}  // namespace si::test
