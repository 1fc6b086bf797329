// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What the draw paths share.
#include "gl/paths/draw_path.h"

#include "core/str_cat.h"
#include "gl/paths/dispatch_grid.h"
#include "si/crowd/record_emulation.h"


namespace si::detail {

void bindAppearance(const DrawResources& r, const Program& program) {
  r.character->bindMaterials();
  // Unit 2 is sampled only while a custom array is set (u_custom_layers > 0); binding 0 there
  // would unbind every target of the unit.
  if (r.custom_texture != kNoObject) glBindTextureUnit(2, r.custom_texture);
  if (program.custom_layers >= 0)
    glProgramUniform1ui(program.id, program.custom_layers, r.custom_layers);
}

void setCameraUniforms(const Program& program, const Camera& camera, const glm::vec3& light) {
  const glm::mat4 vp = camera.viewProjection();
  if (program.view_projection >= 0)
    glProgramUniformMatrix4fv(program.id, program.view_projection, 1, GL_FALSE, &vp[0][0]);
  if (program.light_direction >= 0)
    glProgramUniform3fv(program.id, program.light_direction, 1, &light[0]);
}

void bindShading(const DrawResources& r, const Program& program, const Camera& camera,
                 const glm::vec3& light) {
  glUseProgram(program.id);
  glBindVertexArray(r.character->vao);
  r.palette->bind();
  bindAppearance(r, program);
  setCameraUniforms(program, camera, light);
}

void setMotionUniforms(const Program& program, const PathFrame& f) {
  if (!f.motion) return;
  if (program.motion_view_projection >= 0)
    glProgramUniformMatrix4fv(program.id, program.motion_view_projection, 1, GL_FALSE,
                              &f.motion_view_projection[0][0]);
  if (program.previous_view_projection >= 0)
    glProgramUniformMatrix4fv(program.id, program.previous_view_projection, 1, GL_FALSE,
                              &f.previous_view_projection[0][0]);
}

void bindPreviousRecords(const DrawResources& r, const Program& program, const PathFrame& f) {
  r.ring->bindRegion(f.previous_base, f.previous_bytes, 25);
  glProgramUniform3ui(program.id, 8, f.previous_words.x, f.previous_words.y, f.previous_words.z);
  glProgramUniform3f(program.id, 9, f.previous_shift.x, f.previous_shift.y, f.previous_shift.z);
}

void bindSlotHandles(const DrawResources& r, const PathFrame& f) {
  if (f.handles) r.ring->bindRegion(f.handle_base, f.handle_bytes, 29);
}

void setBatchSlot(const Program& program, const DrawBatch& d) {
  if (program.batch_slot >= 0)
    glProgramUniform1ui(program.id, program.batch_slot, d.layer_byte_offset / kLayerRecordSize);
}

Status dispatchGroups(const GlInfo& info, uint64_t groups, const char* what) {
  DispatchGrid grid;
  if (!dispatchGrid(groups, info.max_compute_groups_x, info.max_compute_groups_y, &grid))
    return {StatusCode::kLimitExceeded,
            strCat(what, ": ", groups, " compute groups exceed GL_MAX_COMPUTE_WORK_GROUP_COUNT (",
                   info.max_compute_groups_x, " x ", info.max_compute_groups_y, ")")};
  glDispatchCompute(grid.x, grid.y, 1);
  return Status::ok();
}

namespace {
// The instance's kExtraLayerRecords extra layer records (a 2D blend's) in `view`, or none.
Span<const LayerRecord> recordExtras(const CrowdView& view, size_t record) {
  const Span<const LayerRecord> extras = view.extraLayerRecords();
  return extras.empty() ? Span<const LayerRecord>()
                        : Span<const LayerRecord>(extras.data() + record * kExtraLayerRecords,
                                                  kExtraLayerRecords);
}
}  // namespace

glm::mat4 recordJointMatrix(const BakedPalette& palette, const CrowdView& view, size_t record,
                            uint32_t slot) {
  const Span<const LayerRecord> layers = view.layerRecords();
  if (layers.empty()) return emulateRecordMatrix(palette, view.records()[record], slot);
  return emulateLayeredRecordMatrix(palette, view.records()[record], layers[record],
                                    recordExtras(view, record), view.crowd()->layerMasks(), slot);
}

Status recordMorphWeights(const BakedPalette& palette, const CrowdView& view, size_t record,
                          Span<float> out) {
  const Span<const LayerRecord> layers = view.layerRecords();
  if (layers.empty()) return emulateRecordMorphWeights(palette, view.records()[record], out);
  return emulateLayeredMorphWeights(palette, view.records()[record], layers[record],
                                    recordExtras(view, record), view.crowd()->layerMasks(), out);
}

PathFrame viewFrame(const CrowdView& view, const Camera& camera, const glm::vec3& light) {
  PathFrame f;
  f.crowd = view.crowd();
  f.view = &view;
  f.camera = camera;
  f.light = light;
  f.impostor_lod = f.crowd != nullptr ? f.crowd->desc().impostor_lod : 0;
  f.motion_view_projection = view.camera().viewProjection();
  f.previous_view_projection = view.previousCamera().viewProjection();
  return f;
}

void placeRingFrame(const RingFrame& plan, size_t base, const PreviousBinding& previous,
                    PathFrame* f) {
  f->ring_base = base;
  f->ring_bytes = plan.end;
  f->motion = plan.motion;
  f->previous_base = previous.base;
  f->previous_bytes = previous.bytes;
  f->previous_words = previous.words;
  f->layers = plan.layers;
  f->layer_base = base + plan.layer_records;
  f->previous_layer_base = base + plan.previous_layers;
  f->extras = plan.extras;
  f->extra_layer_base = base + plan.extra_layers;
  f->previous_extra_base = base + plan.previous_extras;
  f->compose_entries_base = base + plan.compose_entries;
  f->compose_slots_base = base + plan.compose_slots;
  f->compose_slot_bytes = plan.layer_slots * 4;
  f->handles = plan.handles;
  f->handle_base = base + plan.handle_words;
  f->handle_bytes = plan.handles_end - plan.handle_words;
}

}  // namespace si::detail
