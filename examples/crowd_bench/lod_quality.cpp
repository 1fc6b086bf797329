// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/lod_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace si::bench {
namespace {

// One LOD choice's frames: the images and the triangles drawn.
Status drawFrames(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                  const std::string& scene, uint32_t count, const std::string& path,
                  uint32_t frames, const LodChoice& lod, std::vector<std::vector<uint8_t>>* images,
                  double* triangles) {
  CrowdManager crowd;
  Status s = makeCrowd(setup, palette, scene, count, lod, &crowd);
  if (!s.isOk()) return s;
  const std::vector<glm::dvec3> positions = scenePositions(scene, count);
  images->assign(frames, {});
  *triangles = 0.0;
  for (uint32_t f = 0; f < frames; ++f) {
    const Camera cam = cameraAt(setup, scene, positions, f, frames);
    DrawStats st;
    // The clock moves the same way for every choice; the LOD follows the camera.
    s = stepCrowd(crowd, path, cam, f == 0 ? 0.25 : 1.0 / 60.0);
    if (s.isOk()) s = drawPath(renderer, crowd, path, cam, &st);
    if (s.isOk()) s = setup.context->readPixels(&(*images)[f]);
    if (!s.isOk()) return s;
    *triangles += double(st.triangles);
  }
  *triangles /= double(std::max(1u, frames));
  return Status();
}

}  // namespace

Status measureLodQuality(Setup& setup, Renderer& renderer, const BakedPalette& palette,
                         const std::string& scene, uint32_t count, const std::string& path,
                         uint32_t frames, const std::vector<LodChoice>& choices,
                         const std::string& image_dir, std::vector<QualityRow>* rows) {
  LodChoice reference;
  reference.fixed_lod = 0;
  std::vector<std::vector<uint8_t>> ref_images;
  double ref_triangles = 0.0;
  Status s = drawFrames(setup, renderer, palette, scene, count, path, frames, reference,
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
    s = drawFrames(setup, renderer, palette, scene, count, path, frames, lod, &images,
                   &row.triangles);
    if (s.isOk() && !image_dir.empty())
      s = writePng(image_dir + "/" + scene + "_" + row.lod + ".png", setup.width, setup.height,
                   images[0]);
    if (!s.isOk()) return s;
    uint64_t differing = 0, pixels = 0, covered = 0;
    double squared = 0.0;
    for (uint32_t f = 0; f < frames; ++f) {
      const std::vector<uint8_t>& a = images[f];
      const std::vector<uint8_t>& b = ref_images[f];
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
    }
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
