// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Every path that skins a character, as draws of one view with one camera: what the tests
// comparing each path with the CPU emulation (drawCpuSkinned) loop over.

#include <functional>
#include <vector>

#include "render/image_compare.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"
#include "si/headless/headless_context.h"

namespace si::test {

struct PathDraw {
  const char* name;
  std::function<Status()> draw;
};

/// The vertex-shader, compute, GPU-driven (vertex-shader and compute skinning) and traditional
/// draws of character `id` for `view` (kept by reference: call them while it lives).
inline std::vector<PathDraw> everySkinningPath(Renderer& r, CharacterId id, const CrowdView& view,
                                               const InstanceBatcher& batcher,
                                               const Camera& camera) {
  return {
      {"vertex shader",
       [&r, id, &view, &batcher, camera] {
         return r.drawCrowd(id, view, batcher, camera, nullptr, DrawMode::kSkinned);
       }},
      {"compute",
       [&r, id, &view, &batcher, camera] {
         return r.drawCrowd(id, view, batcher, camera, nullptr, DrawMode::kComputeSkinned);
       }},
      {"GPU-driven",
       [&r, id, &view, camera] {
         return r.drawCrowdGpuCulled(id, view, camera, nullptr, DrawMode::kSkinned);
       }},
      {"GPU-driven compute",
       [&r, id, &view, camera] {
         return r.drawCrowdGpuCulled(id, view, camera, nullptr, DrawMode::kComputeSkinned);
       }},
      {"traditional",
       [&r, id, &view, camera] { return r.drawTraditional(id, view, camera, nullptr); }},
  };
}

/// Draws every skinning path of character `id` over `background` and expects each image
/// (read from `context`) within kMaxDifferingShare of `expected`.
inline void expectEveryPathDraws(Renderer& r, CharacterId id, const CrowdView& view,
                                 const InstanceBatcher& batcher, const Camera& camera,
                                 const glm::vec4& background, HeadlessContext& context,
                                 const std::vector<uint8_t>& expected) {
  for (const PathDraw& path : everySkinningPath(r, id, view, batcher, camera)) {
    SCOPED_TRACE(path.name);
    r.clear(background);
    const Status s = path.draw();
    ASSERT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> image;
    ASSERT_TRUE(context.readPixels(&image).isOk());
    EXPECT_LE(compare(image, expected, nullptr).share, kMaxDifferingShare);
  }
}

}  // namespace si::test
