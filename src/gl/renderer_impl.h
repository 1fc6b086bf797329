// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Renderer's private state, shared by the translation units of si::gl (renderer.cpp: the
// instanced, compute and baseline paths; gpu_culling.cpp: GPU-driven culling and LOD).

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "si/gl/renderer.h"

namespace si {

inline constexpr GLuint kNoObject = 0;

// Milliseconds since `t0` (the draw functions' CPU time).
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

namespace detail {
// Compiles one shader; kBackend with the driver's log on failure.
Status compile(GLenum type, const std::string& source, const char* name, GLuint* out);
// Checks a linked program: kBackend with the driver's log (and the program deleted) on failure.
Status finishLink(GLuint program, const char* name, GLuint* out);
// Compiles and links a vertex + fragment program; `varying` non-null captures it with transform
// feedback.
Status link(const std::string& vs, const std::string& fs, const char* name, const char* varying,
            GLuint* out);
// Compiles and links a compute program.
Status linkCompute(const std::string& cs, const char* name, GLuint* out);
}  // namespace detail

// A program and which of the shared uniforms it declares (-1: absent; setting an absent location
// is GL_INVALID_OPERATION).
struct Program {
  GLuint id = kNoObject;
  GLint palette_info = -1, view_projection = -1, base_factor = -1, light_direction = -1;
};

inline Program describe(GLuint id) {
  Program p;
  p.id = id;
  if (id == kNoObject) return p;
  p.palette_info = glGetUniformLocation(id, "si_palette_info");
  p.view_projection = glGetUniformLocation(id, "u_view_projection");
  p.base_factor = glGetUniformLocation(id, "u_base_factor");
  p.light_direction = glGetUniformLocation(id, "u_light_direction");
  return p;
}

struct Renderer::Impl {
  GlInfo info;
  RendererDesc desc;
  bool debug = false;
  uint32_t block_size = 0, capacity = 0, alignment = 256;
  Program skinned, depth, rigid, traditional, capture, preskinned, compute_skin, pulled;
  // Compute pre-skinning: the compacted vertex list and index buffer of each (sub-mesh, LOD),
  // the ring the compute pass writes, the path in use and why.
  struct PreLod {
    uint32_t first_index = 0, index_count = 0;  // Into pre_index_buffer (local indices).
    uint32_t vertex_offset = 0, vertex_count = 0;  // Into the LOD vertex list.
  };
  std::vector<std::vector<PreLod>> pre_lods;  // [sub_mesh][lod]
  GLuint pre_vao = kNoObject, pre_index_buffer = kNoObject, lod_vertex_list = kNoObject;
  GLuint skinned_ring = kNoObject;
  uint64_t skinned_ring_vertices = 0;
  uint32_t source_words = 8, max_lod_vertices = 0;
  SkinningPath path = SkinningPath::kVertexShader;
  std::string path_reason = "explicit setting";
  // CPU-skinning baseline: a streaming vertex buffer and the vertex range of each LOD range.
  GLuint cpu_vao = kNoObject, cpu_stream = kNoObject;
  size_t cpu_stream_size = 0;
  std::vector<uint8_t> cpu_vertices;
  std::vector<glm::uvec2> lod_vertex_ranges;  // Per (sub-mesh, lod): first vertex, count.
  std::vector<std::vector<uint32_t>> lod_range_index;  // [sub_mesh][lod] -> lod_vertex_ranges.
  SkinnedMesh mesh_copy;
  // Palette.
  GLuint palette_texture = kNoObject;
  glm::uvec4 palette_info{0};
  const BakedPalette* palette = nullptr;
  uint32_t palette_slots = 0;
  // Character.
  GLuint vao = kNoObject, vertex_buffer = kNoObject, index_buffer = kNoObject;
  GLuint base_texture = kNoObject;
  glm::vec4 base_factor{1.0f};
  std::vector<SubMesh> sub_meshes;
  uint32_t vertex_count = 0;
  // Record ring.
  GLuint ring = kNoObject;
  uint8_t* ring_mapped = nullptr;
  size_t region_size = 0, ring_size = 0;
  uint32_t ring_frames = 3, ring_index = 0;
  std::vector<GLsync> fences;
  std::vector<DrawBatch> draws;
  // Traditional path.
  GLuint character_ubo = kNoObject;
  std::vector<uint8_t> character_block;
  GLuint timer = kNoObject;

  Status check(const char* what) const { return debug ? checkGlErrors(what) : Status::ok(); }

  // The character's vertex format (see renderer.h) on `vao`, binding 0, with the index buffer.
  bool wide_joints = false;
  void describeVertexFormat(GLuint v) const {
    glVertexArrayVertexBuffer(v, 0, vertex_buffer, 0, GLsizei(wide_joints ? 36 : 32));
    glVertexArrayElementBuffer(v, index_buffer);
    for (GLuint loc = 0; loc < 5; ++loc) {
      glEnableVertexArrayAttrib(v, loc);
      glVertexArrayAttribBinding(v, loc, 0);
    }
    glVertexArrayAttribFormat(v, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(v, 1, 4, GL_INT_2_10_10_10_REV, GL_TRUE, 12);
    glVertexArrayAttribFormat(v, 2, 2, GL_HALF_FLOAT, GL_FALSE, 16);
    glVertexArrayAttribIFormat(v, 3, 4, wide_joints ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE, 20);
    glVertexArrayAttribFormat(v, 4, 4, GL_UNSIGNED_SHORT, GL_TRUE, wide_joints ? 28 : 24);
  }

  // GPU-driven culling (gpu_culling.cpp): programs, per-instance buffers sized for `capacity`
  // instances, the state version last uploaded.
  struct GpuCull {
    GLuint cull = kNoObject, build = kNoObject, scatter = kNoObject;
    Program draw;
    GLuint vao = kNoObject;
    GLuint state = kNoObject, clips = kNoObject, times = kNoObject, counters = kNoObject;
    GLuint records = kNoObject, visible = kNoObject, entries = kNoObject, identity = kNoObject;
    GLuint commands = kNoObject, ranges = kNoObject;
    uint32_t capacity = 0, instances = 0, buckets = 0, sub_meshes = 0;
    uint64_t version = 0;
    const CrowdManager* crowd = nullptr;
    GLuint vertex_source = 0;  // The vertex buffer the VAO was made for.
  } gpu;
  void releaseGpuCull();

  Status ensureRing(size_t bytes_per_frame) {
    // Each region ends with one block of slack so a bound range of the full block size stays
    // inside the buffer.
    const size_t need = (bytes_per_frame + alignment - 1) / alignment * alignment + block_size;
    if (ring != kNoObject && need <= region_size) return Status::ok();
    for (GLsync& f : fences)
      if (f) {
        glClientWaitSync(f, GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e10));
        glDeleteSync(f);
        f = nullptr;
      }
    if (ring != kNoObject) {
      glUnmapNamedBuffer(ring);
      glDeleteBuffers(1, &ring);
    }
    region_size = std::max<size_t>(need * 2, size_t(1) << 20);  // Grow geometrically.
    region_size = (region_size + alignment - 1) / alignment * alignment;
    ring_size = region_size * ring_frames;
    glCreateBuffers(1, &ring);
    const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(ring, GLsizeiptr(ring_size), nullptr, flags);
    ring_mapped = static_cast<uint8_t*>(glMapNamedBufferRange(ring, 0, GLsizeiptr(ring_size), flags));
    if (ring_mapped == nullptr)
      return {StatusCode::kBackend, "mapping the instance record ring failed"};
    fences.assign(ring_frames, nullptr);
    return check("creating the instance record ring");
  }

  // Waits until the GPU is done with region `r` (it was used ring_frames frames ago).
  void acquireRegion(uint32_t r) {
    if (fences[r]) {
      glClientWaitSync(fences[r], GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e10));
      glDeleteSync(fences[r]);
      fences[r] = nullptr;
    }
  }

  void bindCommon(const Program& program, const Camera& camera, const glm::vec3& light) {
    glUseProgram(program.id);
    glBindVertexArray(vao);
    glBindTextureUnit(0, palette_texture);
    glBindTextureUnit(1, base_texture);
    const glm::mat4 vp = camera.viewProjection();
    if (program.palette_info >= 0)
      glProgramUniform4uiv(program.id, program.palette_info, 1, &palette_info[0]);
    if (program.view_projection >= 0)
      glProgramUniformMatrix4fv(program.id, program.view_projection, 1, GL_FALSE, &vp[0][0]);
    if (program.base_factor >= 0)
      glProgramUniform4fv(program.id, program.base_factor, 1, &base_factor[0]);
    if (program.light_direction >= 0)
      glProgramUniform3fv(program.id, program.light_direction, 1, &light[0]);
  }

  void beginTimer(DrawStats* stats) {
    if (desc.measure_gpu_time && stats != nullptr) glBeginQuery(GL_TIME_ELAPSED, timer);
  }
  // Ends the query beginTimer() started and returns the GPU milliseconds (blocking), or -1 when
  // none was started.
  double endTimer(const DrawStats* stats) {
    if (!desc.measure_gpu_time || stats == nullptr) return -1.0;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer, GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-6;
  }

  IndexRange lodRange(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<IndexRange>& lods = sub_meshes[sub_mesh].lods;
    return lods[std::min<size_t>(lod, lods.size() - 1)];
  }

  const PreLod& preLod(uint32_t sub_mesh, uint32_t lod) const {
    const std::vector<PreLod>& lods = pre_lods[sub_mesh];
    return lods[std::min<size_t>(lod, lods.size() - 1)];
  }

  // Binds batch d's records (in ring region `base`) to uniform block binding 0.
  void bindRecords(size_t base, const DrawBatch& d) const {
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, ring, GLintptr(base + d.byte_offset),
                      GLsizeiptr(block_size));
  }

  // The vertex-shader path (and depth-only, rigid): one instanced draw per batch.
  void drawVertexPath(size_t base, DrawStats* st) const {
    for (const DrawBatch& d : draws) {
      if (d.sub_mesh >= sub_meshes.size()) continue;
      const IndexRange range = lodRange(d.sub_mesh, d.lod);
      bindRecords(base, d);
      glDrawElementsInstanced(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                              reinterpret_cast<const void*>(uintptr_t(range.first_index) * 4),
                              GLsizei(d.instance_count));
      ++st->draw_calls;
      st->triangles += uint64_t(range.index_count / 3) * d.instance_count;
      st->instances += d.instance_count;
    }
  }

  Status ensureSkinnedRing() {
    if (skinned_ring != kNoObject) return Status::ok();
    const uint64_t bytes = desc.compute_ring_bytes == 0 ? uint64_t(32) << 20 : desc.compute_ring_bytes;
    skinned_ring_vertices = std::max<uint64_t>(bytes / 16, max_lod_vertices);
    glCreateBuffers(1, &skinned_ring);
    glNamedBufferStorage(skinned_ring, GLsizeiptr(skinned_ring_vertices * 16), nullptr, 0);
    return check("creating the pre-skinned vertex ring");
  }

  // The compute path: for each batch, a compute dispatch skins its instances' vertices into the
  // ring; when the ring is full (or at the end) the pending draws read them by vertex id. Barriers
  // order the writes before the draws and the draws before the ring is overwritten.
  Status drawComputePath(const Camera& camera, const glm::vec3& light, size_t base,
                         DrawStats* st) {
    Status s = ensureSkinnedRing();
    if (!s.isOk()) return s;
    const glm::mat4 vp = camera.viewProjection();
    glBindTextureUnit(0, palette_texture);
    glBindTextureUnit(1, base_texture);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, skinned_ring);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, vertex_buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, lod_vertex_list);
    glProgramUniform4uiv(compute_skin.id, compute_skin.palette_info, 1, &palette_info[0]);
    glProgramUniformMatrix4fv(pulled.id, pulled.view_projection, 1, GL_FALSE, &vp[0][0]);
    glProgramUniform4fv(pulled.id, pulled.base_factor, 1, &base_factor[0]);
    glProgramUniform3fv(pulled.id, pulled.light_direction, 1, &light[0]);
    glBindVertexArray(pre_vao);
    // One dispatch covers at most 65535 groups of 64 (GL's guaranteed minimum).
    const uint64_t dispatch_limit = uint64_t(65535) * 64;
    uint64_t cursor = 0;
    pending.clear();
    const auto flush = [&] {
      if (pending.empty()) return;
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // Skinned vertices before the draws.
      glUseProgram(pulled.id);
      for (const PendingDraw& p : pending) {
        bindRecords(base, p.batch);
        glProgramUniform4ui(pulled.id, 5, p.ring_first, p.lod.vertex_count, p.lod.vertex_offset,
                            p.first_instance);
        glProgramUniform2ui(pulled.id, 6, p.instances, source_words);
        glDrawElementsInstanced(GL_TRIANGLES, GLsizei(p.lod.index_count), GL_UNSIGNED_INT,
                                reinterpret_cast<const void*>(uintptr_t(p.lod.first_index) * 4),
                                GLsizei(p.instances));
        ++st->draw_calls;
        st->triangles += uint64_t(p.lod.index_count / 3) * p.instances;
        st->instances += p.instances;
      }
      st->ring_bytes_used = std::max<uint64_t>(st->ring_bytes_used, cursor * 16);
      ++st->compute_chunks;
      pending.clear();
      cursor = 0;
    };
    for (const DrawBatch& d : draws) {
      if (d.sub_mesh >= pre_lods.size()) continue;
      const PreLod& lod = preLod(d.sub_mesh, d.lod);
      if (lod.vertex_count == 0 || lod.index_count == 0) continue;
      for (uint32_t first = 0; first < d.instance_count;) {
        const uint64_t fit = std::min(skinned_ring_vertices - cursor, dispatch_limit) /
                             lod.vertex_count;
        if (fit == 0) {
          flush();
          continue;
        }
        const uint32_t count = uint32_t(std::min<uint64_t>(d.instance_count - first, fit));
        if (pending.empty()) {
          // The last chunk's draws (or last frame's) are done reading the ring.
          glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
          glUseProgram(compute_skin.id);
        }
        bindRecords(base, d);
        glProgramUniform4ui(compute_skin.id, 5, uint32_t(cursor), lod.vertex_count,
                            lod.vertex_offset, first);
        glProgramUniform2ui(compute_skin.id, 6, count, source_words);
        const uint64_t threads = uint64_t(count) * lod.vertex_count;
        glDispatchCompute(GLuint((threads + 63) / 64), 1, 1);
        pending.push_back({d, lod, first, count, uint32_t(cursor)});
        ++st->compute_dispatches;
        st->skinned_vertices += threads;
        cursor += threads;
        first += count;
      }
    }
    flush();
    return Status::ok();
  }

  struct PendingDraw {
    DrawBatch batch;
    PreLod lod;
    uint32_t first_instance, instances, ring_first;
  };
  std::vector<PendingDraw> pending;

  Status measurePaths(const glm::vec3& light);
  // Compiles the GPU-driven culling's compute programs into gpu (gpu_culling.cpp).
  Status createGpuCullPrograms(const std::string& header);
};

}  // namespace si
