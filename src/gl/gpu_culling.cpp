// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling and LOD: CrowdManager::update()'s selection and records computed by a
// compute pass over the crowd's state in shader storage, bucketed per (LOD, sub-mesh) and drawn
// with one glMultiDrawElementsIndirect. The selection arithmetic is src/crowd/cull_math.h's,
// written out again with `precise` so no step is fused or reordered: both select exactly the
// same instances and LODs (tests/render: GpuCullingSelectsWhatTheCpuSelects).
#include <glad/gl.h>

#include <chrono>
#include <cstring>

#include "core/str_cat.h"
#include "gl/renderer_impl.h"
#include "si/crowd/gpu_crowd_state.h"

namespace si {
using detail::strCat;

namespace {

// Bindings shared by the three passes.
const char* kCullDecl = R"(
layout(std430, binding = 0) buffer SiState { SiGpuInstance si_state[]; };
layout(std430, binding = 1) readonly buffer SiClips { SiGpuClip si_clips[]; };
layout(std430, binding = 2) readonly buffer SiTimes { double si_times[]; };
layout(std430, binding = 3) coherent buffer SiCounters {
  uint si_visible_count; uint si_pad0, si_pad1, si_pad2;
  uint si_bucket_count[256];
  uint si_cursor[256];
  uint si_dispatch[4];
};
layout(std430, binding = 4) writeonly buffer SiRecordsOut { SiInstance si_records[]; };
layout(std430, binding = 5) buffer SiEntriesOut { uint si_entries[]; };
layout(std430, binding = 6) buffer SiVisible { uvec4 si_visible[]; };  // index, lod, mask
layout(location = 16) uniform uvec4 u_counts;  // instances, lod count, sub-meshes, frame stride
)";

// The cull pass: one thread per instance.
const char* kCullMain = R"(
layout(local_size_x = 64) in;
layout(location = 0) uniform vec4 u_planes[6];
layout(location = 6) uniform dvec3 u_camera;
layout(location = 7) uniform double u_clock;
layout(location = 8) uniform vec4 u_params;  // radius, far line (radii), hysteresis
layout(location = 9) uniform float u_lines[7];
layout(location = 17) uniform uint u_anim_lod;
layout(location = 18) uniform double u_anim_step;

// cull_math.h's dot3, cross3 and rotate, in the same order and unfused.
float siDot3(vec3 a, vec3 b) {
  precise float r = (a.x * b.x + a.y * b.y) + a.z * b.z;
  return r;
}
vec3 siCross3(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return r;
}
vec3 siRotate(vec4 q, vec3 v) {
  precise vec3 uv = siCross3(q.xyz, v);
  precise vec3 uuv = siCross3(q.xyz, uv);
  precise vec3 r = v + ((uv * q.w) + uuv) * 2.0;
  return r;
}

// CrowdManager::localTime and fastSample / si::sampleFrames.
double siLocalTime(double start_time, double start_clock, float speed, uint loop_mode,
                   SiGpuClip c) {
  double t = start_time + (u_clock - start_clock) * double(speed);
  if (!(c.duration > 0.0lf)) return 0.0lf;
  if (loop_mode == 2u) {  // LoopMode::kLoop
    double w = t - floor(t * c.inv_duration) * c.duration;
    if (w < 0.0lf) w += c.duration;
    return w >= c.duration ? 0.0lf : w;
  }
  return clamp(t, 0.0lf, c.duration);
}
uvec3 siSample(SiGpuClip c, double t) {  // frame, next frame, fraction bits
  if (c.uniform_grid != 0u) {
    double position = t * c.inv_interval;
    uint i = min(uint(position), c.last_interval);
    return uvec3(i, i + 1u, floatBitsToUint(float(clamp(position - double(i), 0.0lf, 1.0lf))));
  }
  if (c.frame_count <= 1u || !(c.interval > 0.0lf)) return uvec3(0u);
  double tt = clamp(t, 0.0lf, c.duration);
  uint last = c.frame_count - 2u;
  uint lo = min(min(uint(tt / c.interval), last), c.frame_count), hi = c.frame_count;
  while (lo < hi) {  // upper_bound
    uint mid = (lo + hi) / 2u;
    if (si_times[c.times_offset + mid] <= tt) lo = mid + 1u; else hi = mid;
  }
  uint i = min(lo == 0u ? 0u : lo - 1u, last);
  double t0 = si_times[c.times_offset + i], span = si_times[c.times_offset + i + 1u] - t0;
  float f = span > 0.0lf ? float(clamp((tt - t0) / span, 0.0lf, 1.0lf)) : 1.0;
  return uvec3(i, i + 1u, floatBitsToUint(f));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_counts.x) return;
  SiGpuInstance st = si_state[i];
  precise vec3 rel = vec3(dvec3(st.px, st.py, st.pz) - u_camera);
  bool fading = st.fading != 0u && st.fade_duration > 0.0lf &&
                u_clock - st.fade_start < st.fade_duration;
  SiGpuClip ca = si_clips[st.clip];
  SiGpuClip cb = si_clips[fading ? st.from_clip : st.clip];
  float s = st.scale;
  precise float radius = u_params.x * s;
  precise float d2 = siDot3(rel, rel);
  if (u_params.y >= 0.0) {
    precise float far_line = u_params.y * radius;
    if (d2 > far_line * far_line) return;
  }
  precise vec3 center_a = rel + siRotate(st.rotation, ca.sphere.xyz * s);
  precise vec3 center_b = rel + siRotate(st.rotation, cb.sphere.xyz * s);
  precise float ra = ca.sphere.w * s;
  precise float rb = cb.sphere.w * s;
  for (int k = 0; k < 6; ++k) {
    vec4 p = u_planes[k];
    precise float da = siDot3(p.xyz, center_a) + p.w;
    precise float db = siDot3(p.xyz, center_b) + p.w;
    if (!(da >= -ra) && !(db >= -rb)) return;
  }
  uint lods = u_counts.y;
  uint lod = min(st.lod, lods - 1u);
  while (lod + 1u < lods) {
    precise float line = u_lines[lod] * (1.0 + u_params.z) * radius;
    if (!(d2 > line * line)) break;
    ++lod;
  }
  while (lod > 0u) {
    precise float line = u_lines[lod - 1u] * (1.0 - u_params.z) * radius;
    if (!(d2 < line * line)) break;
    --lod;
  }
  si_state[i].lod = lod;

  // The record (CrowdManager::update()'s).
  SiInstance rec;
  vec4 q = st.rotation;
  float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  rec.world_rows[0] = vec4(vec3(1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)) * s, rel.x);
  rec.world_rows[1] = vec4(vec3(2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)) * s, rel.y);
  rec.world_rows[2] = vec4(vec3(2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)) * s, rel.z);
  uint stride = u_counts.w;
  double ta = siLocalTime(st.start_time, st.start_clock, st.speed, st.loop, ca);
  if (lod >= u_anim_lod) ta = floor(ta / u_anim_step) * u_anim_step;
  uvec3 fa = siSample(ca, ta);
  uvec4 frames_a = uvec4(ca.first_texel + fa.x * stride, ca.first_texel + fa.y * stride, 0u, 0u);
  if (fading) {
    double tb = siLocalTime(st.from_start_time, st.from_start_clock, st.from_speed, st.from_loop,
                            cb);
    if (lod >= u_anim_lod) tb = floor(tb / u_anim_step) * u_anim_step;
    uvec3 fb = siSample(cb, tb);
    float w = min(float((u_clock - st.fade_start) / st.fade_duration), 1.0);
    rec.frames = uvec4(cb.first_texel + fb.x * stride, cb.first_texel + fb.y * stride,
                       frames_a.x, frames_a.y);
    rec.blend = uvec4(fb.z, fa.z, floatBitsToUint(max(0.0, w)), st.color);
  } else {
    rec.frames = uvec4(frames_a.xy, frames_a.xy);
    rec.blend = uvec4(fa.z, fa.z, floatBitsToUint(0.0), st.color);
  }
  uint v = atomicAdd(si_visible_count, 1u);
  si_records[v] = rec;
  uint subs = u_counts.z;
  uint mask = st.mask & (subs >= 32u ? 0xFFFFFFFFu : ((1u << subs) - 1u));
  si_visible[v] = uvec4(i, lod, mask, 0u);
  for (uint m = mask; m != 0u; m &= m - 1u)
    atomicAdd(si_bucket_count[lod * subs + uint(findLSB(m))], 1u);
}
)";

// One thread: prefix sums of the bucket counts into the indirect draw commands and the scatter
// pass's dispatch size.
const char* kBuildMain = R"(
layout(local_size_x = 1) in;
layout(std430, binding = 7) writeonly buffer SiCommands { uint si_commands[]; };
layout(std430, binding = 8) readonly buffer SiRanges { uvec2 si_ranges[]; };  // first, count
void main() {
  uint buckets = u_counts.y * u_counts.z, offset = 0u;
  for (uint b = 0u; b < buckets; ++b) {
    uint n = si_bucket_count[b];
    si_commands[b * 5u + 0u] = si_ranges[b].y;
    si_commands[b * 5u + 1u] = n;
    si_commands[b * 5u + 2u] = si_ranges[b].x;
    si_commands[b * 5u + 3u] = 0u;
    si_commands[b * 5u + 4u] = offset;
    si_cursor[b] = offset;
    offset += n;
  }
  si_dispatch[0] = (si_visible_count + 63u) / 64u;
  si_dispatch[1] = 1u;
  si_dispatch[2] = 1u;
}
)";

// One thread per visible instance: its entry in each worn sub-mesh's bucket.
const char* kScatterMain = R"(
layout(local_size_x = 64) in;
void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= si_visible_count) return;
  uvec4 e = si_visible[v];
  for (uint m = e.z; m != 0u; m &= m - 1u) {
    uint slot = atomicAdd(si_cursor[e.y * u_counts.z + uint(findLSB(m))], 1u);
    si_entries[slot] = v;
  }
}
)";

constexpr GLintptr kBucketCountOffset = 16, kDispatchOffset = 16 + 1024 + 1024;
constexpr GLsizeiptr kCountersSize = kDispatchOffset + 16;
constexpr uint32_t kMaxBuckets = 256;


}  // namespace

Status Renderer::Impl::createGpuCullPrograms(const std::string& header) {
  const std::string common = header + kInstanceRecordGlsl + kGpuCrowdStateGlsl + kCullDecl;
  Status s = detail::linkCompute(common + kCullMain, "GPU culling", &gpu.cull);
  if (s.isOk()) s = detail::linkCompute(common + kBuildMain, "GPU culling commands", &gpu.build);
  if (s.isOk()) s = detail::linkCompute(common + kScatterMain, "GPU culling scatter", &gpu.scatter);
  return s;
}

void Renderer::Impl::releaseGpuCull() {
  for (GLuint p : {gpu.cull, gpu.build, gpu.scatter, gpu.draw.id})
    if (p != kNoObject) glDeleteProgram(p);
  const GLuint buffers[] = {gpu.state,   gpu.clips,    gpu.times,   gpu.counters,
                            gpu.records, gpu.visible,  gpu.entries, gpu.identity,
                            gpu.commands, gpu.ranges};
  glDeleteBuffers(GLsizei(sizeof(buffers) / sizeof(buffers[0])), buffers);
  if (gpu.vao != kNoObject) glDeleteVertexArrays(1, &gpu.vao);
  gpu = GpuCull();
}

namespace {

// (Re)creates `buffer` with `bytes` of storage (and `data` when given), dynamic.
void recreate(GLuint* buffer, size_t bytes, const void* data) {
  if (*buffer != kNoObject) glDeleteBuffers(1, buffer);
  glCreateBuffers(1, buffer);
  glNamedBufferStorage(*buffer, GLsizeiptr(std::max<size_t>(bytes, 16)), data,
                       GL_DYNAMIC_STORAGE_BIT);
}

}  // namespace

Status Renderer::drawCrowdGpuCulled(const CrowdManager& crowd, const Camera& camera,
                                    DrawStats* stats) {
  if (!impl_ || impl_->vao == kNoObject || impl_->palette_texture == kNoObject)
    return {StatusCode::kInvalidArgument,
            "drawCrowdGpuCulled: init, uploadPalette and uploadCharacter first"};
  Impl& m = *impl_;
  const CrowdDesc& cd = crowd.desc();
  if (cd.palette != m.palette)
    return {StatusCode::kInvalidArgument,
            "drawCrowdGpuCulled: the crowd plays another palette than the one uploaded"};
  const uint32_t buckets = cd.lod_count * cd.sub_mesh_count;
  if (buckets > kMaxBuckets || cd.sub_mesh_count > m.sub_meshes.size())
    return {StatusCode::kInvalidArgument,
            strCat("drawCrowdGpuCulled: ", cd.sub_mesh_count, " sub-meshes x ", cd.lod_count,
                   " LODs do not fit the uploaded character (", m.sub_meshes.size(),
                   " sub-meshes) or 256 buckets")};
  const auto t0 = std::chrono::steady_clock::now();
  Impl::GpuCull& g = m.gpu;
  const uint32_t n = crowd.size();
  // Upload the state when it changed (or the crowd, or its shape).
  if (g.crowd != &crowd || g.version != crowd.stateVersion() || g.instances != n ||
      g.buckets != buckets || g.vertex_source != m.vertex_buffer || g.vao == kNoObject) {
    std::vector<GpuInstanceState> state;
    crowd.exportGpuState(&state, nullptr);
    std::vector<GpuClipInfo> clips;
    std::vector<double> times;
    crowd.exportGpuClips(&clips, &times);
    const uint32_t entries = std::max(1u, n) * cd.sub_mesh_count;
    if (n > g.capacity || g.sub_meshes != cd.sub_mesh_count || g.records == kNoObject) {
      g.capacity = std::max(n, 1u);
      g.sub_meshes = cd.sub_mesh_count;
      recreate(&g.state, size_t(g.capacity) * sizeof(GpuInstanceState), nullptr);
      recreate(&g.records, size_t(g.capacity) * kInstanceRecordSize, nullptr);
      recreate(&g.visible, size_t(g.capacity) * 16, nullptr);
      recreate(&g.entries, size_t(entries) * 4, nullptr);
      std::vector<uint32_t> identity(entries);
      for (uint32_t k = 0; k < entries; ++k) identity[k] = k;
      recreate(&g.identity, identity.size() * 4, identity.data());
    }
    if (n > 0) glNamedBufferSubData(g.state, 0, GLsizeiptr(state.size() * sizeof(state[0])), state.data());
    recreate(&g.clips, clips.size() * sizeof(GpuClipInfo), clips.data());
    recreate(&g.times, times.size() * sizeof(double), times.empty() ? nullptr : times.data());
    if (g.counters == kNoObject) recreate(&g.counters, size_t(kCountersSize), nullptr);
    if (g.commands == kNoObject) recreate(&g.commands, size_t(kMaxBuckets) * 20, nullptr);
    std::vector<glm::uvec2> ranges(buckets);
    for (uint32_t b = 0; b < buckets; ++b) {
      const IndexRange r = m.lodRange(b % cd.sub_mesh_count, b / cd.sub_mesh_count);
      ranges[b] = glm::uvec2(r.first_index, r.index_count);
    }
    recreate(&g.ranges, ranges.size() * 8, ranges.data());
    if (g.vao != kNoObject) glDeleteVertexArrays(1, &g.vao);
    glCreateVertexArrays(1, &g.vao);
    m.describeVertexFormat(g.vao);
    glVertexArrayVertexBuffer(g.vao, 1, g.identity, 0, 4);
    glVertexArrayBindingDivisor(g.vao, 1, 1);
    glEnableVertexArrayAttrib(g.vao, 5);
    glVertexArrayAttribBinding(g.vao, 5, 1);
    glVertexArrayAttribIFormat(g.vao, 5, 1, GL_UNSIGNED_INT, 0);
    g.crowd = &crowd;
    g.version = crowd.stateVersion();
    g.instances = n;
    g.buckets = buckets;
    g.vertex_source = m.vertex_buffer;
  }

  // Per-frame parameters: the same CullParams CrowdManager::update() uses.
  const CullParams p = crowd.cullParams(camera);
  const GLuint cull = g.cull;
  glProgramUniform4fv(cull, 0, 6, &p.planes[0][0]);
  glProgramUniform3d(cull, 6, camera.position.x, camera.position.y, camera.position.z);
  glProgramUniform1d(cull, 7, crowd.clockSeconds());
  glProgramUniform4f(cull, 8, p.radius, p.max_distance_radii, p.hysteresis, 0.0f);
  glProgramUniform1fv(cull, 9, 7, p.lod_lines);
  const GLuint counts[4] = {n, cd.lod_count, cd.sub_mesh_count,
                            m.palette->layout.frame_stride_texels};
  for (GLuint program : {g.cull, g.build, g.scatter}) glProgramUniform4uiv(program, 16, 1, counts);
  glProgramUniform1ui(cull, 17, p.animation_lod_start);
  glProgramUniform1d(cull, 18, p.animation_step_seconds);

  m.beginTimer(stats);
  // Zero the visible count and the bucket counts.
  glClearNamedBufferSubData(g.counters, GL_R32UI, 0, kBucketCountOffset + 4 * kMaxBuckets,
                            GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  const GLuint ssbo[] = {g.state, g.clips, g.times, g.counters, g.records, g.entries, g.visible,
                         g.commands, g.ranges};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 9, ssbo);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(g.cull);
  glDispatchCompute((n + 63) / 64, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(g.build);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glUseProgram(g.scatter);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, g.counters);
  glDispatchComputeIndirect(kDispatchOffset);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

  // The draw: records and entries at bindings 4 and 5 as the vertex shader reads them.
  m.bindCommon(g.draw, camera, light_direction_);
  glBindVertexArray(g.vao);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.commands);
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr, GLsizei(buckets), 0);
  DrawStats st;
  st.draw_calls = 1;
  st.cpu_submit_ms = msSince(t0);
  st.gpu_ms = m.endTimer(stats);
  if (st.gpu_ms >= 0.0) {
    // Visible instances and triangles: the counters, read back after the timer anyway blocked.
    std::vector<uint32_t> counters(1 + 3 + kMaxBuckets);
    glGetNamedBufferSubData(g.counters, 0, GLsizeiptr(counters.size() * 4), counters.data());
    st.gpu_visible = counters[0];
    for (uint32_t b = 0; b < buckets; ++b) {
      const uint32_t instances = counters[4 + b];
      const IndexRange r = m.lodRange(b % cd.sub_mesh_count, b / cd.sub_mesh_count);
      st.triangles += uint64_t(r.index_count / 3) * instances;
      st.instances += instances;
    }
  }
  Status s = m.check("drawCrowdGpuCulled");
  if (stats != nullptr) *stats = st;
  return s;
}

Status Renderer::readGpuSelection(std::vector<glm::uvec2>* selection) {
  if (!impl_ || selection == nullptr)
    return {StatusCode::kInvalidArgument, "readGpuSelection: init() first, non-null output"};
  Impl::GpuCull& g = impl_->gpu;
  selection->clear();
  if (g.counters == kNoObject) return Status::ok();
  uint32_t visible = 0;
  glGetNamedBufferSubData(g.counters, 0, 4, &visible);
  std::vector<glm::uvec4> rows(visible);
  if (visible > 0)
    glGetNamedBufferSubData(g.visible, 0, GLsizeiptr(size_t(visible) * 16), rows.data());
  selection->reserve(visible);
  for (const glm::uvec4& r : rows) selection->push_back(glm::uvec2(r.x, r.y));
  return checkGlErrors("readGpuSelection");
}

}  // namespace si
