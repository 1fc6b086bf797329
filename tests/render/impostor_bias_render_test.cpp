// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The impostor's mip level (ImpostorDesc::lod_bias): impostors some 8 pixels tall read through a
// bias of -1 keep the limbs that trilinear filtering's level averages below half coverage and
// discards (their covered pixels come closer to the meshes'), and their image comes closer to
// the meshes' at LOD 0 (SSIM, as crowd_bench's quality table measures it), on the instanced and
// GPU-driven paths alike.
#include <glad/gl.h>

#include <cstdio>
#include <string>

#include "common/image_metrics.h"
#include "render/impostor_fixture.h"
#include "si/crowd/crowd_manager.h"

namespace si {
namespace {

using namespace test;

// A grid of 20 x 8 characters some 8 pixels tall in front of flatCamera(), each at its own
// clip, time and turn: every one an impostor (`impostors`) or at LOD 0.
void smallCrowd(bool impostors, CrowdManager* crowd) {
  ASSERT_NO_FATAL_FAILURE(initEveryOneAt(impostors, crowd));
  for (int k = 0; k < 160; ++k)
    ASSERT_NO_FATAL_FAILURE(addHeld(crowd, {(k % 20 - 9.5) * 3.0, (k / 20 - 3.5) * 3.0, -66.0},
                                    0.7f * float(k), uint32_t(k), 0.07 * double(k % 11)));
  ASSERT_TRUE(crowd->advance(0.2).isOk());
  ASSERT_TRUE(crowd->update(0.0, flatCamera()).isOk());
}

// Covered pixels: those not of the background (the first pixel's colour, a corner no character
// reaches).
size_t coveredPixels(const std::vector<uint8_t>& rgba) {
  size_t n = 0;
  for (size_t p = 0; p < rgba.size(); p += 4)
    n += rgba[p] != rgba[0] || rgba[p + 1] != rgba[1] || rgba[p + 2] != rgba[2] ? 1 : 0;
  return n;
}

TEST_P(RenderTest, ANegativeLodBiasKeepsTheThinPartsOfSmallImpostors) {
  const auto image = [&](bool impostors, float bias) {
    CrowdManager crowd;
    smallCrowd(impostors, &crowd);
    Renderer r;
    ImpostorDesc desc;  // The default atlas (16 azimuths at 3 elevations, 8 frames a clip).
    desc.lod_bias = bias;
    impostorRenderer(info_, desc, &r);
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    std::vector<uint8_t> rgba;
    for (PathKind kind : {PathKind::kInstanced, PathKind::kGpuDriven}) {
      const Status s = drawOnPath(r, kind, crowd, flatCamera(), nullptr);
      EXPECT_TRUE(s.isOk()) << s.toString();
      if (kind == PathKind::kInstanced) {
        EXPECT_TRUE(context_->readPixels(&rgba).isOk());
        r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      }
    }
    std::vector<uint8_t> driven;
    EXPECT_TRUE(context_->readPixels(&driven).isOk());
    EXPECT_LE(compare(rgba, driven, nullptr).share, kMaxDifferingShare)
        << "the instanced and GPU-driven paths read the atlas alike";
    return rgba;
  };
  const std::vector<uint8_t> meshes = image(false, 0.0f);
  const std::vector<uint8_t> trilinear = image(true, 0.0f), sharper = image(true, -1.0f);
  if (HasFatalFailure()) return;
  EXPECT_GT(compare(trilinear, sharper, nullptr).share, 0.001) << "the bias reads other levels";
  const size_t mesh_pixels = coveredPixels(meshes), at_0 = coveredPixels(trilinear),
               at_minus_1 = coveredPixels(sharper);
  const double ssim_0 = examples::ssim(trilinear, meshes, kSize, kSize);
  const double ssim_minus_1 = examples::ssim(sharper, meshes, kSize, kSize);
  std::printf(
      "[ impostor bias ] covered pixels: meshes %zu, impostors %zu at bias 0, %zu at -1; "
      "SSIM against LOD 0 %.4f and %.4f\n",
      mesh_pixels, at_0, at_minus_1, ssim_0, ssim_minus_1);
  const auto apart = [&](size_t n) { return n > mesh_pixels ? n - mesh_pixels : mesh_pixels - n; };
  EXPECT_LT(2 * apart(at_minus_1), apart(at_0)) << "the finer level keeps limbs the coarser drops";
  EXPECT_GT(ssim_minus_1, ssim_0);
}

}  // namespace
}  // namespace si
