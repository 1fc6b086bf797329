// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Image error per LOD level: the character drawn in a grid of cells (one per pose and view
// direction) by an orthographic camera, at each level, each level's cells compared with LOD 0's.
#include "si/gl/image_lod_error.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/str_cat.h"
#include "crowd/view_rotation.h"
#include "gl/host_errors.h"
#include "gl/image_lod_curve.h"
#include "gl/profile/gl_profile.h"
#include "gl/state/gl_state_guard.h"
#include "si/core/lod_error.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/renderer.h"

namespace si {
using detail::strCat;

namespace {

constexpr double kPi = 3.14159265358979323846;
// A cell spans this many character heights: room for poses and tilted views.
constexpr double kCellHeights = 1.5;

struct Pose {
  uint32_t clip;
  double time;
};

// The offscreen colour and depth target, deleted with it.
struct Target {
  GLuint framebuffer = 0, color = 0, depth = 0;
  ~Target() {
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &color);
    glDeleteRenderbuffers(1, &depth);
  }
  Status create(GLsizei w, GLsizei h) {
    glCreateRenderbuffers(1, &color);
    glNamedRenderbufferStorage(color, GL_RGBA8, w, h);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, w, h);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferRenderbuffer(framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum complete = glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER);
    if (complete != GL_FRAMEBUFFER_COMPLETE)
      return {StatusCode::kBackend,
              strCat("measureImageLodErrors: the offscreen framebuffer is incomplete (0x",
                     std::hex, complete, ")")};
    return checkGlErrors("measureImageLodErrors: the offscreen framebuffer");
  }
};

// Lines that put every instance at `level` (kDistance mode): the ones before it at almost
// zero, the ones after it out of reach.
std::vector<float> linesFor(uint32_t level, uint32_t levels) {
  std::vector<float> lines;
  for (uint32_t l = 1; l < levels; ++l)
    lines.push_back(l <= level ? 1e-6f * float(l) : 1e7f * float(l));
  return lines;
}

}  // namespace

Status measureImageLodErrors(const GlInfo& info, const Character& character,
                             const BakedPalette& palette, const ImageLodErrorDesc& desc_in,
                             ImageLodErrorReport* report) {
  if (info.es)
    return detail::esUnsupported("measureImageLodErrors", "compute or impostor programs");
  if (report == nullptr)
    return {StatusCode::kInvalidArgument, "measureImageLodErrors: report is null"};
  Status s = character.validate();
  if (!s.isOk()) return {StatusCode::kInvalidArgument, "measureImageLodErrors: " + s.message()};
  if (palette.clips.empty())
    return {StatusCode::kInvalidArgument, "measureImageLodErrors: the palette has no clips"};
  std::vector<float> geometric;
  s = lodErrorsByLevel(character.mesh, &geometric);
  if (!s.isOk()) return s;
  ImageLodErrorDesc d = desc_in;
  if (d.heights_pixels.empty()) d.heights_pixels = {4, 8, 16, 32, 64};
  const uint32_t ss = d.supersample ? d.supersample : 4u;
  if (d.azimuths == 0) d.azimuths = 8;
  if (d.elevations_degrees.empty()) d.elevations_degrees = {0.0f, 30.0f};
  const uint32_t per_clip = d.poses_per_clip ? d.poses_per_clip : 2u;
  const uint32_t max_poses = d.max_poses ? d.max_poses : 6u;
  const int tolerance = int(d.channel_tolerance ? d.channel_tolerance : 8u);
  for (uint32_t h : d.heights_pixels)
    if (h == 0) return {StatusCode::kInvalidArgument, "measureImageLodErrors: a height of 0"};
  if (!(d.pose_phase >= 0.0f && d.pose_phase < 1.0f) || !std::isfinite(d.azimuth_offset_degrees))
    return {StatusCode::kInvalidArgument,
            "measureImageLodErrors: pose_phase must be in [0, 1) and the azimuth offset finite"};
  if (d.impostor != nullptr && character.mesh.maxLodCount() < 2)
    return {StatusCode::kInvalidArgument,
            "measureImageLodErrors: an impostor needs its level past LOD 0 "
            "(si::appendImpostorLevel)"};

  std::vector<Pose> poses;
  for (uint32_t c = 0; c < palette.clips.size() && poses.size() < max_poses; ++c) {
    const double duration = palette.clips[c].duration_seconds;
    for (uint32_t k = 0; k < per_clip && poses.size() < max_poses; ++k)
      poses.push_back({c, duration * (double(k) + double(d.pose_phase)) / double(per_clip)});
  }
  std::vector<glm::quat> views;
  for (float elevation : d.elevations_degrees)
    for (uint32_t a = 0; a < d.azimuths; ++a)
      views.push_back(detail::viewRotation(
          elevation, 2.0 * kPi * a / d.azimuths + double(d.azimuth_offset_degrees) * kPi / 180.0));
  const uint32_t cells = uint32_t(poses.size() * views.size());
  const uint32_t columns = uint32_t(std::ceil(std::sqrt(double(cells))));
  const uint32_t rows = (cells + columns - 1) / columns;
  const uint32_t tallest = *std::max_element(d.heights_pixels.begin(), d.heights_pixels.end());
  const uint32_t widest_cell = uint32_t(std::ceil(kCellHeights * tallest)) * ss;
  const uint64_t max_side = std::max<uint64_t>(info.max_texture_size, 1);
  if (uint64_t(widest_cell) * std::max(columns, rows) > max_side)
    return {StatusCode::kLimitExceeded,
            strCat("measureImageLodErrors: ", columns, " x ", rows, " cells of ", widest_cell,
                   " pixels pass GL_MAX_TEXTURE_SIZE (", max_side, ")")};

  // The character: every sub-mesh worn, posed, its bounds' centre at its cell's centre.
  const float height_units = character.height();
  const Aabb bounds = character.bindPoseBounds();
  const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
  const double cell_units = kCellHeights * double(height_units);
  const uint32_t levels = uint32_t(character.mesh.maxLodCount());
  detail::takeHostErrors("measureImageLodErrors");  // It checks its own.
  Renderer renderer;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;
  s = renderer.init(info, rd);
  CharacterId id;
  if (s.isOk()) s = renderer.addCharacter(character, palette, &id);
  if (s.isOk() && d.material != nullptr) {
    MaterialId material;
    s = renderer.addMaterial(*d.material, &material);
    if (s.isOk()) s = renderer.setMaterial(id, material);
  }
  if (s.isOk() && d.impostor != nullptr) s = renderer.buildImpostor(id, *d.impostor);
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(character.mesh.sub_meshes.size());
  cd.lod_count = levels;
  cd.lod_distances_radii = linesFor(0, levels);
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = d.impostor != nullptr ? levels - 1 : 0;
  if (s.isOk()) s = crowd.init(cd);
  for (uint32_t i = 0; i < cells && s.isOk(); ++i) {
    const Pose& pose = poses[i / views.size()];
    InstanceDesc inst;
    inst.clip = pose.clip;
    inst.time_seconds = pose.time;
    inst.speed = 0.0f;
    inst.rotation = views[i % views.size()];
    inst.variation_mask = 0xFFFFFFFFu;
    const glm::dvec3 cell_centre((i % columns + 0.5) * cell_units,
                                 -(i / columns + 0.5) * cell_units, 0.0);
    inst.position = cell_centre - glm::dvec3(inst.rotation * centre);
    InstanceHandle h;
    s = crowd.add(inst, &h);
  }
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(renderer.batchLimits());
  if (!s.isOk()) return s;

  // Offscreen under its own raster state; the host's framebuffers, viewport, raster and pixel
  // pack state put back on return.
  detail::GlFootprint footprint;
  footprint.framebuffer = true;
  footprint.raster = true;
  footprint.pack = true;
  detail::GlStateGuard guard(footprint, true);
  Target target;
  s = target.create(GLsizei(widest_cell * columns), GLsizei(widest_cell * rows));
  if (!s.isOk()) return s;
  glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);

  ImageLodErrorReport out;
  out.heights_pixels = d.heights_pixels;
  out.character_height_units = height_units;
  out.views = uint32_t(views.size());
  out.impostor = d.impostor != nullptr;
  out.poses = uint32_t(poses.size());
  out.levels.resize(levels);
  for (uint32_t l = 0; l < levels; ++l) out.levels[l].geometric_units = geometric[l];
  std::vector<uint8_t> raw, reference, image;
  for (uint32_t height : d.heights_pixels) {
    const uint32_t cell = uint32_t(std::ceil(kCellHeights * height));  // Display pixels.
    const GLsizei w = GLsizei(cell * columns * ss), hgt = GLsizei(cell * rows * ss);
    glViewport(0, 0, w, hgt);
    // Camera-relative x from 0 to the grid's width, y from minus its height to 0.
    Camera camera;
    camera.position = glm::dvec3(0.0, 0.0, 4.0 * cell_units);
    camera.projection = glm::ortho(0.0f, float(columns * cell_units), -float(rows * cell_units),
                                   0.0f, 0.0f, float(8.0 * cell_units));
    camera.viewport_height_pixels = float(hgt);
    for (uint32_t l = 0; l < levels && s.isOk(); ++l) {
      const std::vector<float> lines = linesFor(l, levels);
      s = crowd.setLodDistances(lines, -1.0f);
      if (s.isOk()) s = crowd.update(0.0, camera);
      if (!s.isOk()) break;
      renderer.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
      DrawStats stats;
      s = renderer.drawCrowd(CharacterId{}, crowd.view(), batcher, camera, &stats,
                             DrawMode::kSkinned);
      if (!s.isOk()) break;
      raw.resize(size_t(w) * size_t(hgt) * 4);
      glReadPixels(0, 0, w, hgt, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
      s = checkGlErrors("measureImageLodErrors: reading the image back");
      if (!s.isOk()) break;
      // Box-filtered to display pixels (rounded), rows from the bottom.
      const uint32_t dw = uint32_t(w) / ss, dh = uint32_t(hgt) / ss;
      std::vector<uint8_t>& pixels = l == 0 ? reference : image;
      pixels.assign(size_t(dw) * dh * 3, 0);
      for (uint32_t y = 0; y < dh; ++y)
        for (uint32_t x = 0; x < dw; ++x)
          for (int k = 0; k < 3; ++k) {
            uint32_t sum = 0;
            for (uint32_t sy = 0; sy < ss; ++sy)
              for (uint32_t sx = 0; sx < ss; ++sx)
                sum += raw[((size_t(y) * ss + sy) * size_t(w) + size_t(x) * ss + sx) * 4 + k];
            pixels[(size_t(y) * dw + x) * 3 + k] = uint8_t((sum + ss * ss / 2) / (ss * ss));
          }
      if (l == 0) continue;
      // Per cell (cell row r spans the grid's top down, display rows from the bottom).
      double sum = 0.0, most = 0.0;
      for (uint32_t c = 0; c < cells; ++c) {
        const uint32_t x0 = (c % columns) * cell, y0 = dh - (c / columns + 1) * cell;
        uint32_t differing = 0;
        for (uint32_t y = y0; y < y0 + cell; ++y)
          for (uint32_t x = x0; x < x0 + cell; ++x) {
            const size_t p = (size_t(y) * dw + x) * 3;
            for (int k = 0; k < 3; ++k)
              if (std::abs(int(pixels[p + k]) - int(reference[p + k])) > tolerance) {
                ++differing;
                break;
              }
          }
        sum += differing;
        most = std::max(most, double(differing));
      }
      out.levels[l].mean_differing_pixels.push_back(sum / cells);
      out.levels[l].max_differing_pixels.push_back(most);
    }
    if (!s.isOk()) return s;
  }
  for (uint32_t l = 1; l < levels; ++l) {
    ImageLodLevel& level = out.levels[l];
    level.one_pixel_height = detail::onePixelHeight(d.heights_pixels, level.mean_differing_pixels);
    level.image_units = float(double(height_units) / level.one_pixel_height);
  }
  if (levels > 0) {  // LOD 0: nothing differs.
    out.levels[0].mean_differing_pixels.assign(d.heights_pixels.size(), 0.0);
    out.levels[0].max_differing_pixels.assign(d.heights_pixels.size(), 0.0);
  }
  *report = std::move(out);
  return Status::ok();
}

}  // namespace si
