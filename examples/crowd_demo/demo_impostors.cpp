// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's impostors (--impostors): the character's atlas, and where the crowd hands its far
// characters over to it (the impostor's image error against the mesh levels').
#include <cstdio>
#include <vector>

#include "demo_scene.h"
#include "si/core/lod_error.h"
#include "si/gl/image_lod_error.h"

namespace demo {

// The impostor atlas, and the impostor's image error (a quick measurement: 3 heights up to
// 16 px, 4 views, 2 poses, between the atlas's views and frames): where the crowd hands over.
si::Status DemoScene::buildImpostor(const si::GlInfo& info, si::CharacterId id) {
  si::ImpostorDesc impostor;  // ImpostorDesc's defaults, or the small atlas.
  if (options_.small_atlas) {
    impostor.azimuths = 8;
    impostor.elevations_degrees = {0.0f, 30.0f};
    impostor.frames_per_clip = 4;
  }
  si::ImpostorInfo atlas;
  si::Status s = renderer_.buildImpostor(id, impostor, &atlas);
  si::ImageLodErrorDesc d;
  d.heights_pixels = {4, 8, 16};
  d.azimuths = 4;
  d.azimuth_offset_degrees = 180.0f / float(impostor.azimuths ? impostor.azimuths : 16u);
  d.elevations_degrees = {20.0f};
  d.max_poses = 2;
  d.pose_phase = 0.5f;
  d.impostor = &impostor;
  si::ImageLodErrorReport r;
  if (s.isOk()) s = si::measureImageLodErrors(info, character_, palette_, d, &r);
  std::vector<float> geometric;
  if (s.isOk()) s = si::lodErrorsByLevel(character_.mesh, &geometric);
  if (!s.isOk()) return s;
  impostor_errors_units_ = si::impostorLodErrorsUnits(geometric, r, options_.lod_pixels);
  std::printf("Impostors: %u views x %u frames, %u x %u texels (%.1f MiB); image error %.3g units "
              "(one pixel of the character changes at %.3g px tall); they take over at %.3g "
              "units of projected error\n",
              atlas.views, atlas.frames, atlas.width, atlas.height,
              double(atlas.bytes) / 1048576.0, double(r.levels.back().image_units),
              r.levels.back().one_pixel_height, double(impostor_errors_units_.back()));
  return s;
}

}  // namespace demo
