// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/lod_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "common/image_metrics.h"

namespace si::bench {
namespace {

// Box-filters an RGBA8 image by ss x ss pixels (a partial block at the edge is dropped).
std::vector<uint8_t> downsample(const std::vector<uint8_t>& rgba, uint32_t w, uint32_t h,
                                uint32_t ss) {
  const uint32_t ow = w / ss, oh = h / ss;
  std::vector<uint8_t> out(size_t(ow) * oh * 4);
  for (uint32_t y = 0; y < oh; ++y)
    for (uint32_t x = 0; x < ow; ++x)
      for (uint32_t c = 0; c < 4; ++c) {
        uint32_t sum = 0;
        for (uint32_t dy = 0; dy < ss; ++dy)
          for (uint32_t dx = 0; dx < ss; ++dx)
            sum += rgba[(size_t(y * ss + dy) * w + x * ss + dx) * 4 + c];
        out[(size_t(y) * ow + x) * 4 + c] = uint8_t((sum + ss * ss / 2) / (ss * ss));
      }
  return out;
}

// One LOD choice's frames: the images and the triangles drawn.
Status drawFrames(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                  const std::string& scene, uint32_t count, const std::string& path,
                  uint32_t frames, uint32_t ss, const LodChoice& lod,
                  std::vector<std::vector<uint8_t>>* images, double* triangles) {
  CrowdManager crowd;
  InstanceBatcher batcher;
  const std::vector<glm::dvec3> positions = scenePositions(scene, count);
  Status s = makeCrowd(setup, palette, positions, lod, &crowd);
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;
  images->assign(frames, {});
  *triangles = 0.0;
  for (uint32_t f = 0; f < frames; ++f) {
    const Camera cam = cameraAt(setup, scene, positions, f, frames);
    DrawStats st;
    // The clock moves the same way for every choice; the LOD follows the camera.
    s = stepCrowd(crowd, path, cam, f == 0 ? 0.25 : 1.0 / 60.0);
    if (s.isOk()) s = drawPath(renderer, crowd, batcher, path, cam, &st);
    if (s.isOk()) s = setup.context->readPixels(&(*images)[f]);
    if (!s.isOk()) return s;
    if (ss > 1) (*images)[f] = downsample((*images)[f], setup.width, setup.height, ss);
    *triangles += double(st.triangles);
  }
  *triangles /= double(std::max(1u, frames));
  return Status();
}

}  // namespace

Status measureLodQuality(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                         const std::string& scene, uint32_t count, const std::string& path,
                         uint32_t frames, uint32_t supersample,
                         const std::vector<LodChoice>& choices, const std::string& image_dir,
                         std::vector<QualityRow>* rows) {
  const uint32_t ss = std::max(1u, supersample);
  LodChoice reference;
  reference.fixed_lod = 0;
  std::vector<std::vector<uint8_t>> ref_images;
  double ref_triangles = 0.0;
  Status s = drawFrames(setup, renderer, palette, scene, count, path, frames, ss, reference,
                        &ref_images, &ref_triangles);
  if (!s.isOk()) return s;
  std::vector<LodChoice> all = {reference};
  all.insert(all.end(), choices.begin(), choices.end());
  for (const LodChoice& lod : all) {
    std::vector<std::vector<uint8_t>> images;
    QualityRow row;
    row.scene = scene;
    row.lod = lod.name();
    row.instances = count;
    s = drawFrames(setup, renderer, palette, scene, count, path, frames, ss, lod, &images,
                   &row.triangles);
    if (s.isOk() && !image_dir.empty())
      s = writePng(image_dir + "/" + scene + "_" + row.lod + ".png", setup.width / ss,
                   setup.height / ss, images[0]);
    if (!s.isOk()) return s;
    uint64_t differing = 0, pixels = 0, covered = 0, shimmering = 0, pairs = 0;
    double squared = 0.0;
    for (uint32_t f = 0; f < frames; ++f) {
      const std::vector<uint8_t>& a = images[f];
      const std::vector<uint8_t>& b = ref_images[f];
      row.ssim += examples::ssim(a, b, setup.width / ss, setup.height / ss) / double(frames);
      covered += coveredPixels(a);
      for (size_t i = 0; i + 3 < a.size() && i + 3 < b.size(); i += 4) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
          const int d = std::abs(int(a[i + c]) - int(b[i + c]));
          worst = std::max(worst, d);
          squared += double(d) * double(d);
        }
        differing += worst > kQualityChannelTolerance;
        row.max_channel = std::max(row.max_channel, worst);
        ++pixels;
      }
      if (f == 0) continue;
      const size_t n = examples::shimmeringPixels(images[f - 1], a, ref_images[f - 1], b,
                                                  kQualityChannelTolerance);
      if (n != SIZE_MAX) shimmering += n, pairs += a.size() / 4;
    }
    row.temporal_share = pairs ? double(shimmering) / double(pairs) : 0.0;
    row.differing_share = pixels ? double(differing) / double(pixels) : 0.0;
    const double mse = pixels ? squared / (3.0 * double(pixels)) : 0.0;
    row.psnr_db = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse)
                            : std::numeric_limits<double>::infinity();
    row.triangles_per_pixel =
        covered ? row.triangles * double(frames) / double(covered) : 0.0;
    rows->push_back(row);
  }
  return Status();
}

}  // namespace si::bench
