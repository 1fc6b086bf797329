// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// One draw per character and sub-mesh, its palette in a uniform block: the baseline instancing
// is measured against.
#include "gl/paths/traditional_path.h"

#include <algorithm>
#include <cstring>

#include "gl/resources/gl_allocation.h"

namespace si::detail {

Status TraditionalPath::prepare(const DrawResources&) {
  if (block_buffer_ != kNoObject) return Status::ok();
  // std140: 3 vec4 world rows, a uint padded to 16, the morph target weights (a character
  // that has targets), then the joint rows.
  block_.assign(48 + 16 + size_t(kTraditionalMorphTargets) * 4 + size_t(kMaxTraditionalJoints) * 48,
                0);
  return createBuffer(&block_buffer_, block_.size(), nullptr, GL_DYNAMIC_STORAGE_BIT,
                      "the traditional path's joint block");
}

Status TraditionalPath::draw(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  // Records of posed instances name live frames after the palette's texels.
  const BakedPalette& palette = live_palette_.of(*r.palette->palette(), *f.crowd);
  const uint32_t slots = palette.layout.joint_count;
  if (slots > kMaxTraditionalJoints)
    return {StatusCode::kLimitExceeded, "drawTraditional: more joints than the uniform block holds"};
  // The weights' rows (vec4s) before the joint rows, where the character has targets (at most
  // kMaxMorphTargets: PaletteLayout refuses more).
  const uint32_t targets = std::min(palette.layout.morph_target_count, kTraditionalMorphTargets);
  const size_t joints_at = 64 + (targets > 0 ? size_t(kTraditionalMorphTargets) * 4 : 0);
  morph_weights_.resize(targets);
  const CrowdManager& crowd = *f.crowd;
  const CrowdView& view = *f.view;
  const Program& program = r.programs[ProgramId::kTraditional];
  bindShading(r, program, f.camera, f.light);
  glBindBufferBase(GL_UNIFORM_BUFFER, 1, block_buffer_);
  const Span<const InstanceRecord> records = view.records();
  const uint32_t sub_meshes = view.subMeshCount();
  const size_t block_bytes = joints_at + size_t(slots) * 48;
  for (size_t v = 0; v < records.size(); ++v) {
    const InstanceRecord& rec = records[v];
    uint8_t* block = block_.data();
    std::memcpy(block, rec.world_rows, 48);
    std::memcpy(block + 48, &rec.blend[3], 4);
    // The CPU does what the instanced shader does per vertex, once per joint per character.
    for (uint32_t slot = 0; slot < slots; ++slot) {
      const glm::mat4 mat = recordJointMatrix(palette, view, v, slot);
      float rows[12];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) rows[row * 4 + col] = mat[col][row];
      std::memcpy(block + joints_at + size_t(slot) * 48, rows, 48);
    }
    if (targets > 0) {
      const Status s = recordMorphWeights(palette, view, v, morph_weights_);
      if (!s.isOk()) return s;
      std::memcpy(block + 64, morph_weights_.data(), size_t(targets) * 4);
    }
    glNamedBufferSubData(block_buffer_, 0, GLsizeiptr(block_bytes), block);
    // This instance's worn sub-meshes at the view's LOD.
    uint32_t lod = 0;
    if (!view.lodOf(view.visibleHandles()[v], &lod).isOk()) continue;
    if (program.lod >= 0) glProgramUniform1ui(program.id, program.lod, lod);
    if (program.instance_handle >= 0)
      glProgramUniform1ui(program.id, program.instance_handle, view.visibleHandles()[v].id);
    InstanceDesc desc;
    if (!crowd.get(view.visibleHandles()[v], &desc).isOk()) continue;
    for (uint32_t sm = 0; sm < sub_meshes && sm < r.character->sub_meshes.size(); ++sm) {
      if (!((desc.variation_mask >> sm) & 1u)) continue;
      const IndexRange range = r.character->lodRange(sm, lod);
      if (range.index_count == 0) continue;  // Dropped at this LOD (si::buildPartLods).
      glDrawElements(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4));
      ++st->draw_calls;
      st->triangles += range.index_count / 3;
      ++st->instances;
    }
  }
  return Status::ok();
}

void TraditionalPath::release() {
  if (block_buffer_ != kNoObject) glDeleteBuffers(1, &block_buffer_);
  block_buffer_ = kNoObject;
  block_.clear();
}

uint64_t TraditionalPath::gpuBytes() const {
  return bufferBytes(block_buffer_);
}

}  // namespace si::detail
