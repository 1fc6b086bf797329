// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Renderer::buildImpostor: the character drawn into its impostor atlas, one cell per captured
// frame and view direction, by an orthographic camera over the whole grid (one drawCrowd with
// the capture program writing both layers).
#include <glad/gl.h>

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/str_cat.h"
#include "gl/renderer_impl.h"
#include "gl/resources/gl_allocation.h"
#include "gl/resources/impostor_coverage.h"
#include "gl/view_rotation.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/handle_pool.h"
#include "si/crowd/instance_batcher.h"

namespace si {
using detail::strCat;

namespace {

constexpr double kPi = 3.14159265358979323846;

// One captured frame: the clip and its baked frame.
struct CapturedFrame {
  uint32_t clip, frame;
};

// The capture framebuffer: the atlas's three layers and a depth buffer, deleted with it.
struct CaptureTarget {
  GLuint framebuffer = 0, depth = 0;
  ~CaptureTarget() {
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &depth);
  }
  Status create(GLuint atlas, GLsizei w, GLsizei h) {
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, w, h);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT0, atlas, 0, 0);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT1, atlas, 0, 1);
    glNamedFramebufferTextureLayer(framebuffer, GL_COLOR_ATTACHMENT2, atlas, 0, 2);
    glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(framebuffer, 3, buffers);
    const GLenum complete = glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER);
    if (complete != GL_FRAMEBUFFER_COMPLETE)
      return {StatusCode::kBackend,
              strCat("buildImpostor: the capture framebuffer is incomplete (0x", std::hex,
                     complete, ")")};
    return checkGlErrors("buildImpostor: the capture framebuffer");
  }
};

}  // namespace

bool Renderer::hasImpostor(CharacterId id) const {
  return impl_ && id.index < impl_->characters.size() &&
         impl_->characters[id.index]->impostor.ready();
}

Status Renderer::buildImpostor(CharacterId id, const ImpostorDesc& desc, ImpostorInfo* info) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  detail::CharacterSlot* slot = nullptr;
  const Status found = m.find(id, "buildImpostor", &slot);
  if (!found.isOk()) return found;
  const Status es =
      m.esRefuses("buildImpostor", "impostor programs (their clip table is a storage buffer)");
  if (!es.isOk()) return es;
  detail::CharacterSlot& c = *slot;
  const BakedPalette& palette = *c.palette.palette();
  const uint32_t azimuths = desc.azimuths ? desc.azimuths : 16u;
  const std::vector<float> elevations =
      desc.elevations_degrees.empty() ? std::vector<float>{0.0f, 30.0f, 60.0f}
                                      : desc.elevations_degrees;
  const uint32_t per_clip = desc.frames_per_clip ? desc.frames_per_clip : 8u;
  const uint32_t cell = desc.cell_pixels ? desc.cell_pixels : 32u;
  const uint32_t sub_meshes = uint32_t(c.character.sub_meshes.size());
  const uint32_t all = sub_meshes >= 32 ? 0xFFFFFFFFu : (1u << sub_meshes) - 1u;
  const uint32_t mask = desc.variation_mask ? desc.variation_mask & all : all;
  if (elevations.size() > 4)
    return {StatusCode::kInvalidArgument,
            strCat("buildImpostor: ", elevations.size(), " elevations; at most 4")};
  for (size_t k = 0; k < elevations.size(); ++k)
    if (!(elevations[k] >= -90.0f && elevations[k] <= 90.0f) ||
        (k > 0 && !(elevations[k] > elevations[k - 1])))
      return {StatusCode::kInvalidArgument,
              "buildImpostor: elevations must increase, within [-90, 90] degrees"};
  if (mask == 0)
    return {StatusCode::kInvalidArgument,
            strCat("buildImpostor: variation mask 0x", std::hex, desc.variation_mask,
                   " wears none of the character's sub-meshes")};

  // The captured frames: per clip, min(frames, baked frames) spread over its baked frames.
  std::vector<CapturedFrame> frames;
  std::vector<glm::uvec4> clips;
  for (uint32_t k = 0; k < palette.clips.size(); ++k) {
    const BakedClip& clip = palette.clips[k];
    const uint32_t n = std::max<uint32_t>(clip.frame_count, 1);
    const uint32_t f = std::min(per_clip, n);
    clips.emplace_back(clip.first_texel, n, uint32_t(frames.size()), f);
    for (uint32_t j = 0; j < f; ++j)
      frames.push_back({k, f > 1 ? uint32_t((uint64_t(j) * (n - 1) + (f - 1) / 2) / (f - 1)) : 0u});
  }
  std::sort(clips.begin(), clips.end(),
            [](const glm::uvec4& a, const glm::uvec4& b) { return a.x < b.x; });
  const uint32_t views = azimuths * uint32_t(elevations.size());
  const uint64_t cells = uint64_t(frames.size()) * views;
  const uint32_t columns = uint32_t(std::ceil(std::sqrt(double(cells))));
  const uint32_t rows = uint32_t((cells + columns - 1) / columns);
  // The plan, reported (`info`) before anything is allocated, also when refused below.
  const uint64_t width = uint64_t(columns) * cell, height = uint64_t(rows) * cell;
  GLsizei levels = 1;
  while ((cell >> levels) > 0) ++levels;  // Down to one texel a cell.
  ImpostorInfo plan;
  plan.views = views;
  plan.frames = uint32_t(frames.size());
  plan.cells = uint32_t(std::min<uint64_t>(cells, UINT32_MAX));
  plan.width = uint32_t(std::min<uint64_t>(width, UINT32_MAX));
  plan.height = uint32_t(std::min<uint64_t>(height, UINT32_MAX));
  for (GLsizei l = 0; l < levels; ++l)
    plan.bytes += std::max<uint64_t>(width >> l, 1) * std::max<uint64_t>(height >> l, 1) * 4 *
                  detail::ImpostorAtlas::kLayers;
  plan.capture_bytes = width * height * 4;  // GL_DEPTH_COMPONENT24, padded to 4 bytes.
  if (info != nullptr) *info = plan;
  // The atlas is a texture, the capture's depth a renderbuffer, drawn through one viewport: the
  // smallest of their limits bounds each side (a viewport past its limit would be clamped
  // silently, leaving cells empty).
  const struct {
    uint32_t limit;
    const char* name;
  } sides[] = {
      {m.info.max_texture_size, "GL_MAX_TEXTURE_SIZE"},
      {m.info.max_renderbuffer_size, "GL_MAX_RENDERBUFFER_SIZE"},
      {std::min(m.info.max_viewport_width, m.info.max_viewport_height), "GL_MAX_VIEWPORT_DIMS"}};
  for (const auto& side : sides)
    if (width > std::max<uint32_t>(side.limit, 1) || height > std::max<uint32_t>(side.limit, 1))
      return {StatusCode::kLimitExceeded,
              strCat("buildImpostor: ", cells, " cells (", frames.size(), " frames x ", views,
                     " views) of ", cell, " texels need ", width, " x ", height, " texels, past ",
                     side.name, " (", side.limit, "): fewer frames, views or texels per cell")};
  // One capture instance per cell.
  if (cells > HandlePool::kMaxSlots)
    return {StatusCode::kLimitExceeded,
            strCat("buildImpostor: ", cells, " cells (", frames.size(), " frames x ", views,
                   " views), past the capture crowd's ", HandlePool::kMaxSlots,
                   " instances: fewer frames or views")};
  const uint64_t budget = desc.max_bytes ? desc.max_bytes : uint64_t(1) << 30;
  if (plan.bytes + plan.capture_bytes > budget)
    return {StatusCode::kLimitExceeded,
            strCat("buildImpostor: the atlas takes ", plan.bytes, " bytes with its mip levels and ",
                   "its capture ", plan.capture_bytes, " more, past the budget of ", budget,
                   " (ImpostorDesc::max_bytes): fewer frames, views or texels per cell, or a "
                   "larger budget")};

  // The views, and the cell: every clip's bounds about their centre, as wide and tall as the
  // widest view shows them.
  std::vector<glm::quat> rotations;
  for (uint32_t view = 0; view < views; ++view)
    rotations.push_back(detail::viewRotation(elevations[view / azimuths],
                                             2.0 * kPi * (view % azimuths) / azimuths));
  Aabb box = palette.clips[0].bounds;
  for (const BakedClip& clip : palette.clips) {
    box.min = glm::min(box.min, clip.bounds.min);
    box.max = glm::max(box.max, clip.bounds.max);
  }
  const glm::vec3 centre = 0.5f * (box.min + box.max), half = 0.5f * (box.max - box.min);
  float reach = 1e-6f;
  for (const glm::quat& q : rotations)
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner = q * (half * glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
      reach = std::max({reach, std::abs(corner.x), std::abs(corner.y)});
    }
  const float cell_units = 2.0f * reach * 1.02f;

  detail::GlFootprint footprint = detail::uploadFootprint();
  footprint.pack = true;  // The coverage read back.
  const auto guard = m.enter("buildImpostor", footprint, nullptr, true);
  detail::ImpostorAtlas atlas;
  const GLsizei w = GLsizei(width), h = GLsizei(height);
  Status s =
      detail::createTexture2DArray(&atlas.texture, levels, GL_RGBA8, w, h,
                                   detail::ImpostorAtlas::kLayers, "buildImpostor: the atlas");
  CaptureTarget target;
  if (s.isOk()) s = target.create(atlas.texture, w, h);

  // The crowd: one instance per cell, every cell's character at LOD 0.
  CrowdManager crowd;
  CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = sub_meshes;
  cd.max_distance_radii = -1.0f;
  cd.worker_threads = 1;
  if (s.isOk()) s = crowd.init(cd);
  for (uint64_t i = 0; i < cells && s.isOk(); ++i) {
    const CapturedFrame& f = frames[i / views];
    const uint32_t view = uint32_t(i % views);
    const BakedClip& clip = palette.clips[f.clip];
    InstanceDesc inst;
    inst.clip = f.clip;
    inst.time_seconds = clip.frame_times_seconds.empty()
                            ? double(f.frame) * clip.frame_interval_seconds
                            : clip.frame_times_seconds[f.frame];
    inst.loop_mode = LoopMode::kOnce;  // The last frame held, not wrapped to the first.
    inst.speed = 0.0f;
    inst.rotation = rotations[view];
    inst.variation_mask = mask;
    // Texture row i / columns from the bottom (row 0 at y = -rows cells).
    const glm::dvec3 cell_centre((double(i % columns) + 0.5) * cell_units,
                                 (double(i / columns) + 0.5 - double(rows)) * cell_units, 0.0);
    inst.position = cell_centre - glm::dvec3(inst.rotation * centre);
    InstanceHandle handle;
    s = crowd.add(inst, &handle);
  }
  Camera camera;
  camera.position = glm::dvec3(0.0, 0.0, 2.0 * cell_units);
  camera.projection = glm::ortho(0.0f, float(columns * cell_units), -float(rows * cell_units), 0.0f,
                                 0.0f, float(4.0 * cell_units));
  camera.viewport_height_pixels = float(h);
  if (s.isOk()) s = crowd.update(0.0, camera);
  InstanceBatcher batcher;
  if (s.isOk()) s = batcher.init(batchLimits());
  if (s.isOk()) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f}, far_depth = 1.0f;
    for (GLint layer = 0; layer < GLint(detail::ImpostorAtlas::kLayers); ++layer)
      glClearNamedFramebufferfv(target.framebuffer, GL_COLOR, layer, zero);
    glClearNamedFramebufferfv(target.framebuffer, GL_DEPTH, 0, &far_depth);
    const bool motion = m.desc.motion_vectors;
    m.desc.motion_vectors = false;
    m.program_override = detail::ProgramId::kImpostorCapture;
    s = drawCrowd(id, crowd.view(), batcher, camera, nullptr, DrawMode::kSkinned);
    m.program_override = detail::ProgramId::kCount;
    m.desc.motion_vectors = motion;
  }
  if (s.isOk()) {
    glGenerateTextureMipmap(atlas.texture);
    glTextureParameteri(atlas.texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(atlas.texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(atlas.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(atlas.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    s = checkGlErrors("buildImpostor: the atlas's mip levels");
  }
  // The clip table, then every cell's covered rectangle at every level (the quads' extent).
  std::vector<uint32_t> rects;
  if (s.isOk())
    s = detail::measureCoveredRects(atlas.texture, columns, rows, cell, uint32_t(levels), &rects);
  if (s.isOk()) {
    std::vector<uint32_t> table(clips.size() * 4 + (rects.size() + 3) / 4 * 4, 0u);
    std::copy_n(&clips[0].x, clips.size() * 4, table.begin());
    std::copy(rects.begin(), rects.end(), table.begin() + ptrdiff_t(clips.size() * 4));
    s = detail::createBuffer(&atlas.clips, table.size() * sizeof(uint32_t), table.data(), 0,
                             "buildImpostor: the clip table");
  }
  if (!s.isOk()) {
    atlas.release();
    return s;
  }
  atlas.clip_count = uint32_t(clips.size());
  atlas.columns = columns;
  atlas.rows = rows;
  atlas.azimuths = azimuths;
  atlas.elevations = uint32_t(elevations.size());
  for (size_t k = 0; k < elevations.size(); ++k)
    atlas.elevations_radians[k] = float(elevations[k] * kPi / 180.0);
  atlas.frame_stride_texels = palette.layout.frame_stride_texels;
  atlas.cell_texels = cell;
  atlas.levels = uint32_t(levels);
  atlas.centre = centre;
  atlas.cell_units = cell_units;
  c.impostor.release();
  c.impostor = atlas;
  return m.check("buildImpostor");
}

}  // namespace si
