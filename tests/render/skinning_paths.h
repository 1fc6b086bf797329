// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Every path that skins a character, as draws of one view with one camera: what the tests
// comparing each path with the CPU emulation (drawCpuSkinned) loop over.

#include <algorithm>
#include <functional>
#include <string>
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

/// A record playing clip `clip` of `palette` at clip-local time `t` (both clips of its
/// crossfade the same, no world transform): what the capture tests hand captureSkinnedPositions.
inline InstanceRecord clipRecord(const BakedPalette& palette, uint32_t clip, double t) {
  const FrameSample s = sampleFrames(palette.clips[clip], t);
  InstanceRecord rec{};
  rec.frames[0] = rec.frames[2] = palette.layout.frameTexel(clip, s.frame);
  rec.frames[1] = rec.frames[3] = palette.layout.frameTexel(clip, s.next_frame);
  rec.blend[0] = rec.blend[1] = packFraction(s.fraction, s.mode);
  return rec;
}

/// Character `id`'s `view` drawn by the CPU emulation (drawCpuSkinned) over `background`: the
/// image read from `context` (empty, with a failure, when the draw fails).
inline std::vector<uint8_t> cpuSkinnedImage(Renderer& r, CharacterId id, const CrowdView& view,
                                            const Camera& camera, const glm::vec4& background,
                                            HeadlessContext& context) {
  r.clear(background);
  std::vector<uint8_t> image;
  const Status s = r.drawCpuSkinned(id, view, camera, nullptr);
  EXPECT_TRUE(s.isOk()) << s.toString();
  if (s.isOk()) {
    EXPECT_TRUE(context.readPixels(&image).isOk());
  }
  return image;
}

/// Draws every skinning path of character `id` over `background` and expects each image
/// (read from `context`) within kMaxDifferingShare of `expected`; the paths named in `refusing`
/// must refuse instead, kUnsupported.
inline void expectEveryPathDraws(Renderer& r, CharacterId id, const CrowdView& view,
                                 const InstanceBatcher& batcher, const Camera& camera,
                                 const glm::vec4& background, HeadlessContext& context,
                                 const std::vector<uint8_t>& expected,
                                 const std::vector<std::string>& refusing = {}) {
  for (const PathDraw& path : everySkinningPath(r, id, view, batcher, camera)) {
    SCOPED_TRACE(path.name);
    r.clear(background);
    const Status s = path.draw();
    if (std::find(refusing.begin(), refusing.end(), path.name) != refusing.end()) {
      EXPECT_EQ(s.code(), StatusCode::kUnsupported) << s.toString();
      continue;
    }
    ASSERT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> image;
    ASSERT_TRUE(context.readPixels(&image).isOk());
    EXPECT_LE(compare(image, expected, nullptr).share, kMaxDifferingShare);
  }
}

}  // namespace si::test
