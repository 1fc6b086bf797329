// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The GPU-driven path: cull, commands and scatter passes; pre-skinning and a vertex-pulling
// multi-draw, and a vertex-shader multi-draw for what the ring does not hold.
#include "gl/paths/gpu_culled_path.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/paths/dispatch_grid.h"
#include "gl/paths/gpu_culled_layout.h"
#include "gl/paths/impostor_draw.h"
#include "gl/paths/layer_compose_pass.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_export.h"

namespace si::detail {

Status GpuCulledPath::uploadFrame(const DrawResources& r, const PathFrame& f) {
  const CrowdManager& crowd = *f.crowd;
  const CrowdDesc& cd = crowd.desc();
  const uint32_t buckets = cd.lod_count * cd.sub_mesh_count;
  if (buckets > kMaxBuckets || cd.sub_mesh_count > r.character->sub_meshes.size())
    return {StatusCode::kInvalidArgument,
            strCat("drawCrowdGpuCulled: ", cd.sub_mesh_count, " sub-meshes x ", cd.lod_count,
                   " LODs do not fit the uploaded character (", r.character->sub_meshes.size(),
                   " sub-meshes) or 256 buckets")};
  const uint32_t n = crowd.size();
  staging_ = &r.scratch->uploads;
  staging_->prepare(r.programs[ProgramId::kUploadScatter].id, *r.info);
  DispatchGrid grid;
  if (!dispatchGrid((uint64_t(n) + 63) / 64, r.info->max_compute_groups_x,
                    r.info->max_compute_groups_y, &grid))
    return {StatusCode::kLimitExceeded,
            strCat("drawCrowdGpuCulled: ", n, " instances need more compute groups than "
                   "GL_MAX_COMPUTE_WORK_GROUP_COUNT (", r.info->max_compute_groups_x, " x ",
                   r.info->max_compute_groups_y, ")")};
  // The uploads and clears below rewrite buffers the last passes wrote (a view's LODs and
  // flags, its drawn records): GL orders buffer updates after incoherent shader writes only
  // past this barrier.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  // The one crowd this state is of: GpuCulledCrowds keys it by identity, so another crowd (or
  // this one re-initialized) has a state of its own and never inherits what was drawn here.
  crowd_identity_ = crowd.identity();
  // A new frame: the crowd stepped (CrowdManager::stepCount(), dt 0 included), as the CPU
  // paths' selections do. Draws between two steps are one frame.
  if (!framed_ || crowd.stepCount() != frame_steps_) {
    ++frame_;
    frame_steps_ = crowd.stepCount();
    framed_ = true;
  }
  // The whole state when the crowd, its shape or the character changed (or as asked); else
  // what changed since the last upload.
  const bool reshaped = crowd_ != &crowd || uploaded_identity_ != crowd.identity() ||
                        n > capacity_ || shrinks(n) || sub_meshes_ != cd.sub_mesh_count ||
                        buckets_ != buckets || vertex_source_ != r.character->vertex_buffer ||
                        vao_ == kNoObject;
  const bool changed = version_ != CrowdExport(crowd).stateVersion() || instances_ != n;
  if (reshaped || (changed && r.desc->gpu_state_upload == GpuStateUpload::kWhole)) {
    Status s = uploadState(r, crowd, buckets);
    if (!s.isOk()) return s;
  } else if (changed) {
    Status s = uploadChanges(*r.info, crowd);
    if (!s.isOk()) return s;
  }
  Status live = uploadLivePoses(crowd);
  if (!live.isOk()) return live;
  if (f.preskin) {
    Status s = ensureRing(r, f.motion);
    if (!s.isOk()) return s;
  }
  Status view = prepareView(f);
  if (!view.isOk()) return view;
  Status motion = prepareMotion(r, f);
  if (!motion.isOk()) return motion;
  compose_lanes_ = 0;
  if (layers_) {  // Every frame: drawCrowd of another crowd may have replaced the tables.
    Status s = r.scratch->uploadMaskTable(layerMaskTable(crowd.layerMasks()));
    // Both skinnings read composed rows (layer_compose_pass.h), by visible index.
    if (s.isOk()) s = prepareComposedRows(r, crowd.layerMasks(), n, motion_, &compose_lanes_);
    if (s.isOk()) s = extrasNeedComposing("drawCrowdGpuCulled", extras_, compose_lanes_);
    if (!s.isOk()) return s;
  }

  // Per-frame parameters: the same CullParams CrowdView::select() uses.
  const CullParams p = CrowdExport::cullParams(*f.view, f.camera);
  const GLuint cull = r.programs[ProgramId::kCull].id;
  const GLuint commands = r.programs[ProgramId::kCullCommands].id;
  const GLuint scatter = r.programs[ProgramId::kCullScatter].id;
  glProgramUniform4fv(cull, 0, 6, &p.planes[0][0]);
  glProgramUniform3d(cull, 6, f.camera.position.x, f.camera.position.y, f.camera.position.z);
  glProgramUniform1d(cull, 7, crowd.clockSeconds());
  glProgramUniform4f(cull, 8, p.radius, p.max_distance_radii, p.hysteresis, 0.0f);
  glProgramUniform1fv(cull, 9, 7, p.lod_lines);
  const GLuint counts[4] = {n, cd.lod_count, cd.sub_mesh_count,
                            r.palette->palette()->layout.frame_stride_texels};
  for (ProgramId skin : {ProgramId::kGpuSkin, ProgramId::kGpuSkinLayers, ProgramId::kGpuSkinMotion,
                         ProgramId::kGpuSkinMotionLayers, ProgramId::kGpuSkinComposed,
                         ProgramId::kGpuSkinMotionComposed})
    glProgramUniform4uiv(r.programs[skin].id, 16, 1, counts);
  for (GLuint program : {cull, commands, scatter}) glProgramUniform4uiv(program, 16, 1, counts);
  glProgramUniform1ui(cull, 23, layers_ ? 1u : 0u);
  glProgramUniform1ui(cull, 38, extraBase());
  glProgramUniform1ui(cull, 39, previousExtraBase());
  glProgramUniform1ui(cull, 17, p.animation_lod_start);
  glProgramUniform1d(cull, 18, p.animation_step_seconds);
  glProgramUniform1ui(cull, 28, p.lod_bias);
  GLuint drawn_parts[8] = {};
  for (uint32_t lod = 0; lod < cd.lod_count && lod < 8; ++lod)
    for (uint32_t sm = 0; sm < cd.sub_mesh_count && sm < r.character->sub_meshes.size(); ++sm)
      if (r.character->lodRange(sm, lod).index_count > 0) drawn_parts[lod] |= 1u << sm;
  glProgramUniform1uiv(cull, 29, 8, drawn_parts);
  glProgramUniform1ui(cull, 37, f.impostor_lod);
  glProgramUniform1ui(commands, 37,
                      f.impostor_lod != 0 ? f.impostor_lod * cd.sub_mesh_count : 0xFFFFFFFFu);
  glProgramUniform1ui(commands, 19,
                      f.preskin ? uint32_t(r.scratch->gpu_driven_ring.vertices) : 0u);
  // The scatter and pre-skinning passes' rows (their counts are the GPU's: in rows of this many
  // groups they fit whenever the cull pass's, checked above, does).
  glProgramUniform1ui(commands, 27,
                      r.info->max_compute_groups_x == 0 ? 65535u : r.info->max_compute_groups_x);
  const glm::mat4 vp = f.camera.viewProjection();
  glProgramUniformMatrix4fv(cull, 21, 1, GL_FALSE, &vp[0][0]);
  return Status::ok();
}

Status GpuCulledPath::uploadLivePoses(const CrowdManager& crowd) {
  const CrowdExport exported(crowd);
  if (live_poses_ != kNoObject && !live_held_.update(exported, crowd.identity()))
    return Status::ok();  // The slots go whole: no span of changed texels.
  const DenseRange all{0, crowd.desc().live_pose_capacity};
  const uint32_t slots = std::max<uint32_t>(1, all.count);
  if (live_poses_ == kNoObject || slots > live_capacity_) {
    Status s = recreate(&live_poses_, size_t(slots) * sizeof(GpuLivePose), nullptr,
                        "drawCrowdGpuCulled: the live poses");
    if (!s.isOk()) {
      live_held_.forget();
      return s;
    }
    live_capacity_ = slots;
  }
  // 80 bytes a slot (80 KB for a thousand), exported straight into the staging ring, as the
  // state is: the last frame's passes may still read the slots (glNamedBufferSubData alone was
  // not ordered after them on the H100's driver: upload_ring.h).
  if (all.count == 0) return Status::ok();
  std::vector<BufferPiece> pieces{{0, size_t(all.count) * sizeof(GpuLivePose), nullptr}};
  const Status s = uploadWritten(
      *staging_, live_poses_, &pieces, pieces[0].bytes, &live_bytes_, [&](uint8_t* out) {
        exported.livePoses(Span<const DenseRange>(&all, 1), reinterpret_cast<GpuLivePose*>(out));
      });
  if (!s.isOk()) {
    live_held_.forget();  // All of them again next time.
    return {s.code(), "drawCrowdGpuCulled: the live poses: " + s.message()};
  }
  return Status::ok();
}

Status GpuCulledPath::prepareMotion(const DrawResources& r, const PathFrame& f) {
  GpuViewSlot& v = *view_;
  if (v.frame != frame_) {  // The view's first draw of this frame.
    // Its last frame's motion camera is the previous one if it drew motion vectors then.
    v.previous_known = v.camera_frame == frame_ - 1 && v.camera_frame != 0;
    v.previous_camera = v.camera;
    v.previous_view_projection = v.view_projection;
    v.frame = frame_;
  }
  motion_ = f.motion;
  const GLuint cull = r.programs[ProgramId::kCull].id;
  glProgramUniform1ui(cull, 24, motion_ ? 1u : 0u);
  // Only draws with motion vectors set the view's camera, as only they write drawn records.
  if (!motion_) return Status::ok();
  v.camera = f.camera;
  v.view_projection = f.motion_view_projection;
  v.camera_frame = frame_;
  if (!v.previous_known) {  // No previous frame with motion vectors: no camera motion either.
    v.previous_camera = v.camera;
    v.previous_view_projection = v.view_projection;
  }
  Status s = v.ensureDrawn(slots_needed_, r.info->max_shader_storage_block_size_bytes);
  if (!s.isOk()) return s;
  if (capacity_ != previous_capacity_) {  // Grown or shrunk with the state.
    previous_capacity_ = 0;
    s = recreate(&previous_out_, size_t(capacity_) * kInstanceRecordSize, nullptr,
                 "motion vectors: the previous records");
    if (s.isOk())
      s = recreate(&previous_layers_out_,
                   size_t(capacity_) * (1 + kExtraLayerRecords) * kLayerRecordSize, nullptr,
                   "motion vectors: the previous layer records");
    if (!s.isOk()) return s;
    previous_capacity_ = capacity_;
  }
  glProgramUniform2ui(cull, 25, frame_, v.drawn_slots);
  // The fallback moves the current record from this camera's origin to the previous one's.
  const glm::vec3 shift = previousRecordShift(v.camera.position, v.previous_camera.position);
  glProgramUniform3fv(cull, 26, 1, &shift[0]);
  return Status::ok();
}

Status GpuCulledPath::ensureRing(const DrawResources& r, bool motion) {
  const uint64_t largest = r.info->max_shader_storage_block_size_bytes;
  const uint64_t bytes = std::min<uint64_t>(
      r.desc->gpu_driven_ring_bytes != 0 ? r.desc->gpu_driven_ring_bytes : uint64_t(256) << 20,
      std::min<uint64_t>(largest, uint64_t(0xFFFFFFFFu) * 16));
  const uint64_t vertices = bytes / 16;
  if (vertices < r.preskin->max_lod_vertices)
    return {StatusCode::kLimitExceeded,
            strCat("drawCrowdGpuCulled: the pre-skinned ring of ", bytes,
                   " bytes does not hold one instance of the largest LOD (",
                   r.preskin->max_lod_vertices, " vertices)")};
  Status s = r.scratch->gpu_driven_ring.ensure(vertices, true, "GPU-driven pre-skinning: the ring");
  if (s.isOk() && r.preskin->tangents)
    s = r.scratch->gpu_driven_tangent_ring.ensure(vertices, true,
                                                  "GPU-driven pre-skinning: the tangent ring");
  if (s.isOk() && motion)
    s = r.scratch->gpu_driven_previous_ring.ensure(vertices, true,
                                                   "GPU-driven pre-skinning: the previous ring");
  return s;
}

Status GpuCulledPath::draw(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  st->draw_calls = 0;
  st->state_bytes_uploaded = uploaded_bytes_;
  st->view_seed_bytes = seed_bytes_;
  uploaded_bytes_ = seed_bytes_ = 0;
  two_phases_ = r.desc->gpu_occlusion_culling;
  if (!two_phases_) {
    runPasses(r, f, 0, st);
    return Status::ok();
  }
  // Phase 1: what was visible last frame. Then the pyramid of the depth it left (and of what
  // the application drew before), and phase 2: every instance in the frustum tested against it.
  runPasses(r, f, 1, st);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // The counters the passes wrote, then copied.
  glCopyNamedBufferSubData(counters_, counts_read_back_, 0, GLintptr(kCounterWords) * 4,
                           GLsizeiptr(kCounterWords) * 4);
  // Window depth as the draws wrote it: the camera's clip depth through the host's depth range.
  GLfloat range[2] = {0.0f, 1.0f};
  glGetFloatv(GL_DEPTH_RANGE, range);
  const bool reversed = f.camera.depth == DepthConvention::kReversedZeroToOne;
  const bool far_is_max = reversed == (range[1] < range[0]);
  DepthPyramid& pyramid = view_->pyramid;
  Status s = pyramid.build(*r.programs.set, far_is_max);
  markPass(r, GpuPass::kDepthPyramid);
  if (!s.isOk()) return s;
  const GLuint cull = r.programs[ProgramId::kCull].id;
  glProgramUniform3i(cull, 22, pyramid.width(), pyramid.height(), pyramid.levels());
  glProgramUniform2i(cull, 40, GLint(f.camera.depth), far_is_max ? 1 : 0);
  glProgramUniform2f(cull, 41, range[0], range[1]);
  glBindTextureUnit(1, pyramid.texture());
  runPasses(r, f, 2, st);
  return Status::ok();
}

void GpuCulledPath::runPasses(const DrawResources& r, const PathFrame& f, uint32_t phase,
                              DrawStats* st) {
  const uint32_t n = instances_;
  const GLuint cull = r.programs[ProgramId::kCull].id;
  const GLuint commands = r.programs[ProgramId::kCullCommands].id;
  const GLuint scatter = r.programs[ProgramId::kCullScatter].id;
  // Zero the visible count and the bucket counts (after the first phase's writes to them).
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glClearNamedBufferSubData(counters_, GL_R32UI, 0, GLsizeiptr(kBucketCountWord + kMaxBuckets) * 4,
                            GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  const GLuint ssbo[] = {state_, clips_, times_, counters_, records_, entries_, visible_,
                         commands_, ranges_, bucket_info_};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 10, ssbo);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 16, view_->instances);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 25, live_poses_);
  glProgramUniform1ui(cull, 20, phase);
  const GLuint preskin_ssbo[] = {entry_data_, r.scratch->gpu_driven_ring.buffer,
                                 r.character->vertex_buffer,
                                 r.preskin->lod_vertex_list};
  if (f.preskin) {
    glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 12, 4, preskin_ssbo);
    // The tangent ring (the vertex ring stands in, never read, for a character without).
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 28,
                     r.preskin->tangents ? r.scratch->gpu_driven_tangent_ring.buffer
                                         : r.scratch->gpu_driven_ring.buffer);
  } else {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, entry_data_);
  }
  if (layers_) {
    const GLuint layer_ssbo[] = {overlays_, layers_out_};
    glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 17, 2, layer_ssbo);
  }
  if (motion_) {
    const GLuint motion_ssbo[] = {view_->drawn, previous_out_, previous_layers_out_};
    glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 19, 3, motion_ssbo);
    if (f.preskin)
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 22, r.scratch->gpu_driven_previous_ring.buffer);
  }
  // Motion vectors: this frame's camera of the view and its previous frame's.
  const glm::mat4& now = view_->view_projection;
  const glm::mat4& then = view_->previous_view_projection;
  const auto set_motion = [&](const Program& p) {
    if (!motion_) return;
    if (p.motion_view_projection >= 0)
      glProgramUniformMatrix4fv(p.id, p.motion_view_projection, 1, GL_FALSE, &now[0][0]);
    if (p.previous_view_projection >= 0)
      glProgramUniformMatrix4fv(p.id, p.previous_view_projection, 1, GL_FALSE, &then[0][0]);
  };
  // Also orders last frame's (or the first phase's) reads of the ring, records, entries and
  // commands before these passes' writes.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                  GL_COMMAND_BARRIER_BIT);
  glUseProgram(cull);
  // uploadFrame() checked that the instances' groups fit (dispatchGroups cannot fail here).
  (void)dispatchGroups(*r.info, (uint64_t(n) + 63) / 64, "drawCrowdGpuCulled: the cull pass");
  markPass(r, GpuPass::kCull);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(commands);
  glDispatchCompute(1, 1, 1);
  markPass(r, GpuPass::kCommands);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glUseProgram(scatter);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, counters_);
  glDispatchComputeIndirect(GLintptr(kDispatchWord) * 4);
  markPass(r, GpuPass::kScatter);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_);
  // The skinning passes read the mask table where the command pass read the ranges.
  if (layers_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, r.scratch->mask_table.buffer);
  const bool composed = compose_lanes_ > 0;
  if (composed) {
    composeGpuLayers(r, motion_, compose_lanes_, n, extraBase(), previousExtraBase(), st);
    markPass(r, GpuPass::kCompose);
  }
  if (f.preskin) {
    // Every pre-skinned entry's vertices into the ring, then one vertex-pulling multi-draw.
    const Program& skin = r.programs[preSkinningProgram(true, motion_, layers_, composed)];
    glUseProgram(skin.id);
    r.palette->bind();
    glProgramUniform2ui(skin.id, 6, 0u, r.preskin->drawLayout());
    glDispatchComputeIndirect(GLintptr(kSkinDispatchWord) * 4);
    markPass(r, GpuPass::kSkin);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    const Program& pulled =
        r.programs[f.depth_only ? ProgramId::kGpuPulledDepthOnly
                                : pullingProgram(true, motion_, r.preskin->tangents)];
    bindShading(r, pulled, f.camera, f.light);
    set_motion(pulled);
    glProgramUniform2ui(pulled.id, 6, 0u, r.preskin->drawLayout());
    glBindVertexArray(preskin_vao_);
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                                reinterpret_cast<const void*>(kPreskinnedCommands),
                                GLsizei(buckets_), 0);
    ++st->draw_calls;
  }
  // Vertex-shader skinning: every instance without pre-skinning, those past the ring with.
  const Program& skinned =
      r.programs[skinningProgram(true, f.depth_only, motion_, layers_, composed)];
  bindShading(r, skinned, f.camera, f.light);
  set_motion(skinned);
  glBindVertexArray(vao_);
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr, GLsizei(buckets_), 0);
  ++st->draw_calls;
  markPass(r, GpuPass::kDraw);
  drawImpostorsIndirect(r, f, vao_, impostor_quads_, GLintptr(kImpostorDispatchWord) * 4,
                        kImpostorCommand, st);
}

void GpuCulledPath::readCounts(const DrawResources& r, const CrowdDesc& cd, DrawStats* st) const {
  st->gpu_visible = 0;
  st->skinned_vertices = 0;
  st->impostors_left_out = 0;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // Reads of what the passes wrote.
  // Through a buffer of their own: a buffer the CPU has read is kept where clearing it waits
  // for the GPU (the H200's driver: the next frame's second occlusion phase waited there for
  // the first, 5.4 ms of CPU at 100k), and the passes clear the counters every frame.
  glCopyNamedBufferSubData(counters_, counts_read_back_, 0, 0, GLsizeiptr(kCounterWords) * 4);
  std::vector<uint32_t> all(size_t(kCounterWords) * (two_phases_ ? 2 : 1));
  glGetNamedBufferSubData(counts_read_back_, 0, GLsizeiptr(all.size() * 4), all.data());
  for (size_t phase = 0; phase * kCounterWords < all.size(); ++phase) {
    const uint32_t* counters = &all[phase * kCounterWords];
    st->gpu_visible += counters[0];
    const uint32_t buckets = cd.lod_count * cd.sub_mesh_count;
    for (uint32_t b = 0; b < buckets; ++b) {
      const uint32_t instances = counters[kBucketCountWord + b];
      const IndexRange range = r.character->lodRange(b % cd.sub_mesh_count, b / cd.sub_mesh_count);
      const bool impostors = cd.impostor_lod != 0 && b == cd.impostor_lod * cd.sub_mesh_count;
      // Impostors: the quads the impostor quads pass kept (impostor_draw.h).
      const uint32_t drawn =
          impostors ? std::min(instances, counters[kImpostorsDrawnWord]) : instances;
      st->impostors_left_out += instances - drawn;
      st->triangles += uint64_t(impostors ? 2 : range.index_count / 3) * drawn;
      st->instances += drawn;
      st->vertex_shader_instances += instances - counters[kFittedWord + b];
    }
    st->skinned_vertices += counters[kThreadBaseWord + buckets];
  }
}

Status GpuCulledPath::readSelection(std::vector<glm::uvec2>* selection) const {
  selection->clear();
  if (counters_ == kNoObject) return Status::ok();
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // Reads of what the passes wrote.
  uint32_t visible = 0;
  glCopyNamedBufferSubData(counters_, counts_read_back_, 0, 0, 4);  // As readCounts() does.
  glGetNamedBufferSubData(counts_read_back_, 0, 4, &visible);
  std::vector<glm::uvec4> rows(visible);
  if (visible > 0)
    glGetNamedBufferSubData(visible_, 0, GLsizeiptr(size_t(visible) * 16), rows.data());
  selection->reserve(visible);
  for (const glm::uvec4& row : rows) selection->push_back(glm::uvec2(row.x, row.y));
  return Status::ok();
}

void GpuCulledPath::memory(CrowdGpuMemory* out) const {
  *out = CrowdGpuMemory();
  out->crowd = crowd_identity_;
  out->capacity = capacity_;
  out->views = uint32_t(views_.size());
  for (GLuint b : buffers()) out->state_bytes += bufferBytes(b);
  out->view_bytes = views_.gpuBytes();
}

void GpuCulledPath::release() {
  const std::array<GLuint, 19> all = buffers();
  glDeleteBuffers(GLsizei(all.size()), all.data());
  const GLuint arrays[] = {vao_, preskin_vao_};
  glDeleteVertexArrays(2, arrays);
  views_.clear();
  *this = GpuCulledPath();
}

}  // namespace si::detail
