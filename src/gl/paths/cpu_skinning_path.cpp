// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Skinning on the CPU, streamed to the GPU: the baseline that shows what instancing saves.
#include "gl/paths/cpu_skinning_path.h"

#include <algorithm>
#include <cstring>

#include "core/morph_entries.h"
#include "core/skinned_normal.h"
#include "gl/resources/gl_allocation.h"
#include "si/core/shader_inputs.h"
#include "si/crowd/record_emulation.h"

namespace si::detail {

namespace {
constexpr size_t kChunkBytes = size_t(8) << 20;  // The streaming buffer, at least.
}  // namespace

Status CpuSkinningPath::prepare(const DrawResources& r) {
  const SkinnedMesh& mesh = r.character->mesh;
  ranges_.clear();
  range_of_.assign(mesh.sub_meshes.size(), {});
  for (size_t sm = 0; sm < mesh.sub_meshes.size(); ++sm)
    for (const IndexRange& range : mesh.sub_meshes[sm].lods) {
      uint32_t lo = UINT32_MAX, hi = 0;
      for (uint32_t i = range.first_index; i < range.first_index + range.index_count; ++i) {
        lo = std::min(lo, mesh.indices[i]);
        hi = std::max(hi, mesh.indices[i]);
      }
      range_of_[sm].push_back(uint32_t(ranges_.size()));
      ranges_.push_back(glm::uvec2(lo, hi - lo + 1));
    }
  // A chunk holds at least one instance of the largest range: a LOD past 8 MiB of streamed
  // vertices (262,144) is streamed whole, never written past the buffer.
  // Position, normal, texcoord as floats; then, where the mesh has them, the tangent (4
  // floats), texture coordinates 1 (2 floats) and the colour (4 x unorm8).
  tangent_offset_ = mesh.tangents.empty() ? 0 : 32;
  vertex_bytes_ = mesh.tangents.empty() ? 32 : 48;
  texcoord1_offset_ = mesh.texcoords1.empty() ? 0 : vertex_bytes_;
  vertex_bytes_ += mesh.texcoords1.empty() ? 0 : 8;
  color_offset_ = mesh.colors.empty() ? 0 : vertex_bytes_;
  vertex_bytes_ += mesh.colors.empty() ? 0 : 4;
  // Each vertex's morph entries, as the shaders' morph stream orders them (by effect, with
  // their tails), and each LOD level's cut.
  morph_first_.clear();
  morph_entries_.clear();
  morph_cuts_ = r.character->morph_cuts;
  if (!mesh.morph_targets.empty()) {
    MorphEntriesByVertex by_vertex = morphEntriesByVertex(mesh);
    const std::vector<float> tails =
        orderMorphEntriesByEffect(mesh, morphWeightBounds(*r.palette->palette()), &by_vertex);
    morph_first_ = by_vertex.first;
    for (size_t i = 0; i < by_vertex.entries.size(); ++i) {
      const MorphEntriesByVertex::Entry& e = by_vertex.entries[i];
      const MorphTarget& t = mesh.morph_targets[e.target];
      morph_entries_.push_back(
          {e.target, tails[i], t.position_deltas[e.index],
           t.normal_deltas.empty() ? glm::vec3(0.0f) : t.normal_deltas[e.index],
           t.tangent_deltas.empty() ? glm::vec3(0.0f) : t.tangent_deltas[e.index]});
    }
  }
  chunk_bytes_ = kChunkBytes;
  for (const glm::uvec2& range : ranges_)
    chunk_bytes_ = std::max(chunk_bytes_, size_t(range.y) * vertex_bytes_);
  if (vao_ != kNoObject) glDeleteVertexArrays(1, &vao_);
  glCreateVertexArrays(1, &vao_);
  glVertexArrayElementBuffer(vao_, r.character->index_buffer);
  for (GLuint loc : {0u, 1u, 2u, 3u, 8u, 9u}) {
    glEnableVertexArrayAttrib(vao_, loc);
    glVertexArrayAttribBinding(vao_, loc, 0);
  }
  glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribFormat(vao_, 1, 3, GL_FLOAT, GL_FALSE, 12);
  glVertexArrayAttribFormat(vao_, 2, 2, GL_FLOAT, GL_FALSE, 24);
  // The optional words; without them the attribute reads the position (preskinned.vert's
  // u_tangents is 0 and the fragment stage ignores the others: SiMaterial.layer.w), so nothing
  // comes from the host's generic attribute state.
  glVertexArrayAttribFormat(vao_, 3, 4, GL_FLOAT, GL_FALSE, GLuint(tangent_offset_));
  glVertexArrayAttribFormat(vao_, 8, 2, GL_FLOAT, GL_FALSE, GLuint(texcoord1_offset_));
  glVertexArrayAttribFormat(vao_, 9, 4, GL_UNSIGNED_BYTE, GL_TRUE, GLuint(color_offset_));
  return Status::ok();
}

Status CpuSkinningPath::draw(const DrawResources& r, const PathFrame& f, DrawStats* st) {
  GLuint& stream = r.scratch->cpu_stream;  // Shared by every character's draws.
  if (stream == kNoObject || r.scratch->cpu_stream_bytes < chunk_bytes_) {
    r.scratch->cpu_stream_bytes = 0;
    Status s = createMutableBuffer(&stream, chunk_bytes_, GL_STREAM_DRAW,
                                   "the CPU-skinning vertex stream");
    if (!s.isOk()) return s;
    r.scratch->cpu_stream_bytes = chunk_bytes_;
  }
  glVertexArrayVertexBuffer(vao_, 0, stream, 0, GLsizei(vertex_bytes_));
  const Program& program = r.programs[ProgramId::kPreSkinned];
  glUseProgram(program.id);
  glBindVertexArray(vao_);
  bindAppearance(r, program);
  setCameraUniforms(program, f.camera, f.light);
  const bool tangents = tangent_offset_ != 0;
  glProgramUniform1ui(program.id, 6, tangents ? 1u : 0u);
  // Records of posed instances name live frames after the palette's texels.
  const BakedPalette& palette = live_palette_.of(*r.palette->palette(), *f.crowd);
  const SkinnedMesh& mesh = r.character->mesh;
  const std::vector<SubMesh>& sub_meshes = r.character->sub_meshes;
  // The crowd's sub-meshes (CrowdDesc::sub_mesh_count), as every other path draws them.
  const size_t worn_sub_meshes =
      std::min<size_t>({sub_meshes.size(), f.view->subMeshCount(), 32});
  std::vector<glm::mat4> joint(palette.skeleton_to_palette.size(), glm::mat4(1.0f));
  pending_.clear();
  vertices_.clear();
  const auto flush = [&] {
    if (vertices_.empty()) return;
    glInvalidateBufferData(stream);  // Orphan: the GPU may still read the last chunk.
    glNamedBufferSubData(stream, 0, GLsizeiptr(vertices_.size()), vertices_.data());
    for (const PendingDraw& d : pending_) {
      glProgramUniform1ui(program.id, 4, d.color);
      glProgramUniform1i(program.id, 5, d.base_vertex);
      if (program.lod >= 0) glProgramUniform1ui(program.id, program.lod, d.lod);
      if (program.instance_handle >= 0)
        glProgramUniform1ui(program.id, program.instance_handle, d.handle);
      glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(d.range.index_count), GL_UNSIGNED_INT,
                               reinterpret_cast<const void*>(uintptr_t(d.range.first_index) * 4),
                               d.base_vertex);
      ++st->draw_calls;
      st->triangles += d.range.index_count / 3;
      ++st->instances;
    }
    pending_.clear();
    vertices_.clear();
  };
  const CrowdManager& crowd = *f.crowd;
  const CrowdView& view = *f.view;
  const Span<const InstanceRecord> records = view.records();
  for (size_t v = 0; v < records.size(); ++v) {
    const InstanceRecord& rec = records[v];
    uint32_t lod = 0;
    InstanceDesc desc;
    if (!view.lodOf(view.visibleHandles()[v], &lod).isOk() ||
        !crowd.get(view.visibleHandles()[v], &desc).isOk())
      continue;
    glm::mat4 world(1.0f);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) world[col][row] = rec.world_rows[row][col];
    for (size_t j = 0; j < joint.size(); ++j) {
      const int32_t slot = palette.skeleton_to_palette[j];
      if (slot < 0) continue;
      joint[j] = world * recordJointMatrix(palette, view, v, uint32_t(slot));
    }
    const bool morphs = !morph_first_.empty();
    if (morphs) {
      morph_weights_.resize(palette.layout.morph_target_count);
      const Status s = recordMorphWeights(palette, view, v, morph_weights_);
      if (!s.isOk()) return s;
    }
    for (uint32_t sm = 0; sm < worn_sub_meshes; ++sm) {
      if (!((desc.variation_mask >> sm) & 1u)) continue;
      const size_t lod_index = std::min<size_t>(lod, sub_meshes[sm].lods.size() - 1);
      if (sub_meshes[sm].lods[lod_index].index_count == 0) continue;  // Dropped (buildPartLods).
      const glm::uvec2 vr = ranges_[range_of_[sm][lod_index]];
      if (vertices_.size() + size_t(vr.y) * vertex_bytes_ > chunk_bytes_) flush();
      const GLint first = GLint(vertices_.size() / vertex_bytes_);
      vertices_.resize(vertices_.size() + size_t(vr.y) * vertex_bytes_);
      float* out = reinterpret_cast<float*>(vertices_.data() + size_t(first) * vertex_bytes_);
      for (uint32_t k = 0; k < vr.y; ++k, out += vertex_bytes_ / 4) {
        const uint32_t vi = vr.x + k;
        glm::mat4 blended(0.0f);
        for (size_t i = 0; i < mesh.influenceCount(); ++i) {
          const Influence in = mesh.influence(vi, i);
          if (in.weight != 0.0f) blended += joint[in.joint] * in.weight;
        }
        // The bind pose, with the vertex's morph targets at the instance's weights.
        glm::vec3 position = mesh.positions[vi], normal = mesh.normals[vi];
        glm::vec3 direction = tangents ? glm::vec3(mesh.tangents[vi]) : glm::vec3(0.0f);
        if (morphs && morph_first_[vi + 1] > morph_first_[vi]) {
          glm::vec3 n = normal, t = direction;
          const float cut = morph_cuts_[std::min<size_t>(lod, morph_cuts_.size() - 1)];
          for (uint32_t e = morph_first_[vi]; e < morph_first_[vi + 1]; ++e) {
            const MorphEntry& entry = morph_entries_[e];
            if (entry.tail <= cut) break;  // The rest moves it no farther than the LOD's cut.
            const float w = morph_weights_[entry.target];
            if (w == 0.0f) continue;
            position += w * entry.position;
            n += w * entry.normal;
            t += w * entry.tangent;
          }
          if (glm::length(n) > 0.0f) normal = glm::normalize(n);
          if (glm::length(t) > 0.0f && glm::length(direction) > 0.0f) direction = glm::normalize(t);
        }
        const glm::vec3 p(blended * glm::vec4(position, 1.0f));
        // The normal as the shaders (and si::emulateSkinning) skin it: a blend of rotations is
        // no rotation, so through the blend's cofactor, not the blend itself.
        const glm::mat3 m(blended);
        const glm::vec3 n = detail::skinNormal(m, normal);
        const glm::vec2 uv = mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[vi];
        const float values[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
        std::memcpy(out, values, sizeof(values));
        uint8_t* bytes = reinterpret_cast<uint8_t*>(out);
        if (texcoord1_offset_ != 0)
          std::memcpy(bytes + texcoord1_offset_, &mesh.texcoords1[vi][0], 8);
        if (color_offset_ != 0) {
          const uint32_t rgba = packColor8(mesh.colors[vi]);
          std::memcpy(bytes + color_offset_, &rgba, 4);
        }
        if (!tangents) continue;
        // Skinned as the vertex shader skins it: the blended matrix, normalized, w kept.
        const glm::vec4& t = mesh.tangents[vi];
        const glm::vec3 turned = m * direction;
        const float length = glm::length(turned);
        const glm::vec4 skinned = length > 0.0f ? glm::vec4(turned / length, t.w) : glm::vec4(0.0f);
        std::memcpy(bytes + tangent_offset_, &skinned[0], sizeof(skinned));
      }
      pending_.push_back({sub_meshes[sm].lods[lod_index], first - GLint(vr.x), rec.blend[3], lod,
                          view.visibleHandles()[v].id});
    }
  }
  flush();
  return Status::ok();
}

void CpuSkinningPath::release() {
  if (vao_ != kNoObject) glDeleteVertexArrays(1, &vao_);
  vao_ = kNoObject;
}

}  // namespace si::detail
