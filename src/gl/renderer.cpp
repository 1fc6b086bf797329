// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::Renderer: validates, uploads, and dispatches each draw to its path (src/gl/paths/), with
// the shared timing and record-ring fencing. The technique is B. Dudash, "Skinned Instancing"
// (NVIDIA, 2007); the paths' files cite their own sources.
#include "si/gl/renderer.h"

#include <glad/gl.h>

#include <algorithm>

#include "core/str_cat.h"
#include "crowd/ring_frame.h"
#include "gl/host_errors.h"
#include "gl/paths/layer_compose_pass.h"
#include "gl/renderer_impl.h"
#include "si/crowd/crowd_export.h"

namespace si {
using detail::strCat;

namespace {

Status noRenderer(const char* what) {
  return {StatusCode::kInvalidArgument,
          strCat(what, ": init and addCharacter first")};
}

const char* textureTargetName(GLint target) {
  switch (target) {
    case GL_TEXTURE_1D: return "GL_TEXTURE_1D";
    case GL_TEXTURE_2D: return "GL_TEXTURE_2D";
    case GL_TEXTURE_3D: return "GL_TEXTURE_3D";
    case GL_TEXTURE_CUBE_MAP: return "GL_TEXTURE_CUBE_MAP";
    case GL_TEXTURE_1D_ARRAY: return "GL_TEXTURE_1D_ARRAY";
    case GL_TEXTURE_CUBE_MAP_ARRAY: return "GL_TEXTURE_CUBE_MAP_ARRAY";
    case GL_TEXTURE_RECTANGLE: return "GL_TEXTURE_RECTANGLE";
    case GL_TEXTURE_BUFFER: return "GL_TEXTURE_BUFFER";
    case GL_TEXTURE_2D_MULTISAMPLE: return "GL_TEXTURE_2D_MULTISAMPLE";
    case GL_TEXTURE_2D_MULTISAMPLE_ARRAY: return "GL_TEXTURE_2D_MULTISAMPLE_ARRAY";
  }
  return "texture of an unknown target";
}

}  // namespace

const char* skinningPathName(SkinningPath path) {
  switch (path) {
    case SkinningPath::kAutomatic: return "automatic";
    case SkinningPath::kVertexShader: return "vertex-shader";
    case SkinningPath::kCompute: return "compute";
  }
  return "unknown";
}

Renderer::Renderer() = default;
Renderer::~Renderer() { shutdown(); }

Status Renderer::init(const GlInfo& info, const RendererDesc& desc) {
  shutdown();
  if (glGetString == nullptr || glGetString(GL_VERSION) == nullptr)
    return {StatusCode::kBackend,
            "Renderer::init: no GL context is current (make one current and call loadGl first)"};
  const uint64_t ring_bytes = desc.compute_ring_bytes == 0 ? uint64_t(32) << 20
                                                           : desc.compute_ring_bytes;
  if (info.es) {
    const Status refused = detail::esRefusesDesc(desc);
    if (!refused.isOk()) return refused;
  } else if (ring_bytes > info.max_shader_storage_block_size_bytes)
    return {StatusCode::kLimitExceeded,
            strCat("RendererDesc.compute_ring_bytes ", ring_bytes,
                   " exceeds GL_MAX_SHADER_STORAGE_BLOCK_SIZE ",
                   info.max_shader_storage_block_size_bytes)};
  if (!(desc.morph_lod_share >= 0.0f && desc.morph_lod_share <= 1.0f))
    return {StatusCode::kInvalidArgument, strCat("RendererDesc.morph_lod_share ",
                                                 desc.morph_lod_share, " is not within 0 and 1")};
  auto impl = std::make_unique<Impl>();
  impl->info = info;
  impl->desc = desc;
#ifdef NDEBUG
  impl->debug = desc.debug_checks == 1;
#else
  impl->debug = desc.debug_checks != 2;
#endif
  const uint32_t limit = std::min<uint32_t>(info.max_uniform_block_size_bytes, 1u << 20);
  impl->block_size = desc.uniform_block_size_bytes == 0 ? limit : desc.uniform_block_size_bytes;
  if (impl->block_size < 16384 || impl->block_size > limit)
    return {StatusCode::kInvalidArgument,
            strCat("RendererDesc.uniform_block_size_bytes ", impl->block_size,
                   " must be within 16384 and the context's limit ", limit)};
  impl->capacity = impl->block_size / kInstanceRecordSize;
  impl->alignment = std::max<uint32_t>(16, info.uniform_buffer_offset_alignment);
  impl->ring_frames = desc.ring_frames;
  impl->ring.configure(impl->block_size, impl->alignment, impl->ringFrames(),
                       info.storage_buffer_offset_alignment);
  if (impl->debug) detail::takeHostErrors("Renderer::init");
  if (desc.debug_messages && info.has_khr_debug) impl->debug_chain.install();
  detail::ShaderConfig config;
  config.max_instances = impl->capacity;
  config.max_joints = detail::kMaxTraditionalJoints;
  config.es = info.es;
  Status s = impl->programs.build(config);
  if (s.isOk()) {
    if (!info.es) impl->timer.create();  // ES 3.0 has no timer queries (measure_gpu_time).
    s = impl->check("Renderer::init");
  }
  impl_ = std::move(impl);
  if (!s.isOk()) shutdown();
  return s;
}

void Renderer::shutdown() {
  if (!impl_) return;
  Impl& m = *impl_;
  m.debug_chain.remove();
  for (auto& c : m.characters) c->release();
  m.vertex_path.release();
  m.traditional_path.release();
  m.ring.release();
  m.drawn.clear();
  m.scratch.release();
  m.timer.release();
  m.pass_timer.release();
  m.programs.release();
  impl_.reset();
}

BatchLimits Renderer::batchLimits() const {
  BatchLimits l;
  if (!impl_) return l;
  l.max_uniform_block_size_bytes = impl_->block_size;
  l.uniform_buffer_offset_alignment = impl_->alignment;
  return l;
}

Status Renderer::setCustomTextureArray(uint32_t texture) {
  if (!impl_) return {StatusCode::kInvalidArgument, "Renderer: init() first"};
  Impl& m = *impl_;
  if (texture == detail::kNoObject) {
    m.custom_texture = detail::kNoObject;
    m.custom_layers = 0;
    return Status::ok();
  }
  detail::takeHostErrors("setCustomTextureArray");
  if (glIsTexture(texture) != GL_TRUE)
    return {StatusCode::kInvalidArgument,
            strCat("setCustomTextureArray: ", texture, " is not a texture name")};
  GLint target = 0, layers = 0;
  glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
  if (target != GL_TEXTURE_2D_ARRAY)
    return {StatusCode::kInvalidArgument,
            strCat("setCustomTextureArray: texture ", texture, " is a ", textureTargetName(target),
                   ", not a GL_TEXTURE_2D_ARRAY")};
  glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_DEPTH, &layers);
  if (layers <= 0)
    return {StatusCode::kInvalidArgument,
            strCat("setCustomTextureArray: texture ", texture, " has no storage (no layers)")};
  Status s = checkGlErrors("setCustomTextureArray");
  if (!s.isOk()) return s;
  m.custom_texture = texture;
  m.custom_layers = std::min<uint32_t>(uint32_t(layers), kMaxCustomLayers);
  return Status::ok();
}

uint32_t Renderer::customTextureLayers() const { return impl_ ? impl_->custom_layers : 0; }

void Renderer::setGpuOcclusionCulling(bool on) {
  if (impl_) impl_->desc.gpu_occlusion_culling = on;
}

void Renderer::setMotionVectors(bool on) {
  if (impl_) impl_->desc.motion_vectors = on;
}
void Renderer::setRestoreState(bool on) {
  if (impl_) impl_->desc.restore_state = on;
}
void Renderer::setComposeLayers(bool on) {
  if (impl_) impl_->desc.compose_layers = on;
}
bool Renderer::motionVectors() const { return impl_ && impl_->desc.motion_vectors; }
void Renderer::setGpuMotionProjection(const glm::mat4* projection) {
  if (!impl_) return;
  impl_->has_motion_projection = projection != nullptr;
  if (projection != nullptr) impl_->motion_projection = *projection;
}

uint64_t Renderer::computeRingBytes() const {
  return impl_ ? impl_->scratch.compute_ring.vertices * 16 : 0;
}

void Renderer::clear(const glm::vec4& color, float depth) {
  GLint framebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glClearNamedFramebufferfv(GLuint(framebuffer), GL_COLOR, 0, &color[0]);
  glClearNamedFramebufferfv(GLuint(framebuffer), GL_DEPTH, 0, &depth);
}

Status Renderer::drawCrowd(CharacterId id, const CrowdView& view, const InstanceBatcher& batcher,
                           const Camera& camera, DrawStats* stats, DrawMode mode) {
  if (!impl_) return noRenderer("drawCrowd");
  Impl& m = *impl_;
  detail::CharacterSlot* c = nullptr;
  Status s = m.find(id, "drawCrowd", &c, view);
  if (s.isOk()) s = m.depthMatches(camera, "drawCrowd");
  if (!s.isOk()) return s;
  const CrowdManager& crowd = *view.crowd();
  if (batcher.capacityPerDraw() > m.capacity)
    return {StatusCode::kInvalidArgument,
            strCat("drawCrowd: the batcher's ", batcher.capacityPerDraw(),
                   " instances per draw exceed the shader's ", m.capacity,
                   " (init the batcher with batchLimits())")};
  if (batcher.alignment() == 0 || batcher.alignment() % m.alignment != 0)
    return {StatusCode::kInvalidArgument,
            strCat("drawCrowd: the batcher's offset alignment ", batcher.alignment(),
                   " is not a multiple of the context's GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT ",
                   m.alignment, " (init the batcher with batchLimits())")};
  if (mode == DrawMode::kDefault)
    mode = c->path == SkinningPath::kCompute ? DrawMode::kComputeSkinned : DrawMode::kSkinned;
  if (mode == DrawMode::kComputeSkinned)
    s = m.esRefuses("drawCrowd", "compute shaders (kComputeSkinned)");
  if (s.isOk() && !view.layerRecords().empty())
    s = m.esRefuses("drawCrowd", "storage buffers (layered animation's mask table)");
  if (!s.isOk()) return s;
  // Motion vectors: the skinned colour modes (depth-only and rigid draws write none).
  const bool motion = m.desc.motion_vectors &&
                      (mode == DrawMode::kSkinned || mode == DrawMode::kComputeSkinned);
  if (motion && !view.desc().previous_records)
    return {StatusCode::kInvalidArgument,
            "drawCrowd: motion vectors (RendererDesc::motion_vectors) need a crowd that keeps its "
            "previous records (CrowdDesc::previous_records; a view: CrowdViewDesc::previous_records)"};
  s = m.impostorsDrawable(*c, crowd, "drawCrowd", motion);
  if (!s.isOk()) return s;
  // Layered animation: the view's last selection wrote layer records.
  const bool layers = !view.layerRecords().empty() && mode != DrawMode::kRigid;
  const auto t0 = std::chrono::steady_clock::now();
  // Live poses (CrowdManager::setLivePose): their frames after the palette's, uploaded when
  // they changed (the unpack state then in the footprint).
  detail::GlFootprint footprint = detail::drawFootprint();
  footprint.unpack = Impl::holdsLivePoses(crowd);
  Impl::Guard guard = m.enter("drawCrowd", footprint, &camera);
  s = m.uploadLivePoses(*c, crowd, "drawCrowd");
  if (!s.isOk()) return s;
  m.sizeRing();  // setMotionVectors may have changed the default region count.
  // The ring region (resources/ring_frame.h); its blocks start where storage buffers may too.
  // Motion vectors read the previous records where the previous selection's draw left them
  // while that region survives (resources/drawn_regions.h), else copy them.
  const uint64_t storage_limit = m.info.max_shader_storage_block_size_bytes;
  detail::RingFrame plan;
  const detail::DrawnRegion* last = nullptr;
  detail::RingContents contents;
  contents.motion = motion;
  contents.layers = layers;
  contents.handles = m.programs.readsInstanceHandle(c->material);  // MaterialDesc::instance_handle
  s = detail::reserveRingFrame(batcher, view,
                               std::max(m.alignment, m.info.storage_buffer_offset_alignment),
                               contents, storage_limit, m.drawn, &m.ring, &plan, &last);
  size_t base = 0;
  if (s.isOk()) s = m.ring.acquire(&base);
  if (s.isOk())
    s = detail::writeRingFrame(
        batcher, view, plan, m.ring.mapped(base), m.ring.writableBytes(),
        last != nullptr ? Span<const uint32_t>(last->places) : Span<const uint32_t>(), &m.batches);
  const detail::PreviousBinding previous = detail::previousBinding(plan, base, last);
  if (s.isOk() && last != nullptr) m.ring.borrow(last->serial);
  if (s.isOk() && layers) s = m.scratch.uploadMaskTable(layerMaskTable(crowd.layerMasks()));
  // Composed layers: the skinning passes' rows, where they fit (paths/layer_compose_pass.h; the
  // pass reads the region as a storage buffer).
  uint32_t compose_lanes = 0;
  if (s.isOk() && layers && plan.end <= storage_limit)
    s = detail::prepareComposedRows(m.resources(*c), crowd.layerMasks(), view.records().size(),
                                    motion, &compose_lanes);
  if (s.isOk()) s = detail::extrasNeedComposing("drawCrowd", plan.extras, compose_lanes);
  if (!s.isOk()) return s;
  detail::PathFrame frame = detail::viewFrame(view, camera, light_direction_);
  detail::placeRingFrame(plan, base, previous, &frame);
  frame.program = mode == DrawMode::kRigid
                      ? detail::ProgramId::kRigid
                      : detail::skinningProgram(false, mode == DrawMode::kDepthOnly, motion, layers,
                                                compose_lanes > 0);
  if (m.program_override != detail::ProgramId::kCount) frame.program = m.program_override;
  frame.batches = &m.batches;
  frame.previous_shift = previousRecordShift(view);
  frame.composed = compose_lanes > 0;
  frame.compose_lanes = compose_lanes;
  if (frame.composed)
    detail::writeComposePlaces(m.resources(*c), batcher, view, m.ring.mapped(base), &frame);
  m.ring.publish(base, plan.end);
  if (mode == DrawMode::kRigid) frame.impostor_lod = 0;  // Rigid draws are meshes only.
  detail::DrawPath& path = mode == DrawMode::kComputeSkinned
                               ? static_cast<detail::DrawPath&>(c->compute_path)
                               : m.vertex_path;
  DrawStats st;
  s = m.runPath(*c, path, frame, t0, stats != nullptr, &st, guard);
  st.previous_records_copied = plan.previous_copied ? view.previousRecords().size() : 0;
  // Where the records are, for the view's next draw: only once they were drawn (a draw that
  // failed earlier leaves its region to the next draw, which would be read as this one).
  if (s.isOk() && m.desc.motion_vectors && view.desc().previous_records)
    s = m.drawn.keep(batcher, view, m.ring, base, base + plan.records_end);
  m.ring.finishFrame();
  if (s.isOk()) s = m.check("drawCrowd");
  if (stats != nullptr) *stats = st;
  return s;
}

// The crowd-only paths: the baselines and GPU-driven culling.
Status Renderer::drawTraditional(CharacterId id, const CrowdView& view, const Camera& camera,
                                 DrawStats* stats) {
  return impl_ ? impl_->drawBaseline(id, false, view, camera, light_direction_, stats)
               : noRenderer("drawTraditional");
}

Status Renderer::drawCpuSkinned(CharacterId id, const CrowdView& view, const Camera& camera,
                                DrawStats* stats) {
  return impl_ ? impl_->drawBaseline(id, true, view, camera, light_direction_, stats)
               : noRenderer("drawCpuSkinned");
}

Status Renderer::drawCrowdGpuCulled(CharacterId id, const CrowdView& view, const Camera& camera,
                                    DrawStats* stats, DrawMode mode) {
  if (!impl_) return noRenderer("drawCrowdGpuCulled");
  Impl& m = *impl_;
  detail::CharacterSlot* c = nullptr;
  Status s = m.find(id, "drawCrowdGpuCulled", &c, view);
  if (s.isOk()) s = m.esRefuses("drawCrowdGpuCulled", "compute shaders (GPU-driven culling)");
  if (s.isOk()) s = m.depthMatches(camera, "drawCrowdGpuCulled");
  if (!s.isOk()) return s;
  const CrowdManager& crowd = *view.crowd();
  if (mode == DrawMode::kRigid)
    return {StatusCode::kInvalidArgument,
            "drawCrowdGpuCulled: the GPU-driven path skins (kDefault, kSkinned, kComputeSkinned, "
            "kDepthOnly)"};
  const auto t0 = std::chrono::steady_clock::now();
  detail::GlFootprint footprint = detail::gpuDrivenFootprint();
  footprint.unpack = Impl::holdsLivePoses(crowd);
  Impl::Guard guard = m.enter("drawCrowdGpuCulled", footprint, &camera);
  s = m.uploadLivePoses(*c, crowd, "drawCrowdGpuCulled");
  if (!s.isOk()) return s;
  detail::PathFrame frame = detail::viewFrame(view, camera, light_direction_);
  frame.preskin = mode == DrawMode::kComputeSkinned ||
                  ((mode == DrawMode::kDefault || mode == DrawMode::kDepthOnly) &&
                   c->path == SkinningPath::kCompute);
  frame.depth_only = mode == DrawMode::kDepthOnly;
  // The path keeps what it drew: no previous records. Depth-only draws write no motion.
  frame.motion = m.desc.motion_vectors && !frame.depth_only;
  // Its motion's view-projection is this camera's (the path keeps the previous frame's).
  frame.motion_view_projection =
      (m.has_motion_projection ? m.motion_projection : camera.projection) * camera.view_rotation;
  s = m.impostorsDrawable(*c, crowd, "drawCrowdGpuCulled", frame.motion);
  if (!s.isOk()) return s;
  DrawStats st;
  detail::GpuCulledPath& path = *c->gpu_culled.find(crowd.identity());  // The crowd's own state.
  s = m.runPath(*c, path, frame, t0, stats != nullptr, &st, guard);
  // Visible instances and triangles: the counters, read back after the timer anyway blocked.
  if (s.isOk() && st.gpu_ms >= 0.0) path.readCounts(m.resources(*c), crowd.desc(), &st);
  if (s.isOk()) s = m.check("drawCrowdGpuCulled");
  if (stats != nullptr) *stats = st;
  return s;
}

Status Renderer::readGpuPasses(uint64_t ticket, GpuPassTimes* out) const {
  if (!impl_ || out == nullptr)
    return {StatusCode::kInvalidArgument, "readGpuPasses: init() first, non-null output"};
  return impl_->pass_timer.read(ticket, out);
}

Status Renderer::readGpuSelection(CharacterId id, std::vector<glm::uvec2>* selection) {
  if (!impl_ || selection == nullptr)
    return {StatusCode::kInvalidArgument, "readGpuSelection: init() first, non-null output"};
  detail::CharacterSlot* c = nullptr;
  Status s = impl_->find(id, "readGpuSelection", &c);
  if (s.isOk()) s = impl_->esRefuses("readGpuSelection", "compute shaders (GPU-driven culling)");
  if (s.isOk()) detail::takeHostErrors("readGpuSelection");
  const detail::GpuCulledPath* last = s.isOk() ? c->gpu_culled.last() : nullptr;
  if (last != nullptr)
    s = last->readSelection(selection);
  else if (s.isOk())
    selection->clear();  // Nothing drawn yet.
  return s.isOk() ? checkGlErrors("readGpuSelection") : s;
}

}  // namespace si
