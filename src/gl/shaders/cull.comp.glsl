// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// GPU-driven culling, pass 1 of 3: one thread per instance. CrowdManager::update()'s selection
// (src/crowd/cull_math.h, written out again with `precise` so no step is fused or reordered)
// and its record at the crowd's clock; the visible instance's row and its bucket counts.
#include "cull_common.glsl"
#include "cull_occlusion.glsl"
#include "dispatch_index.glsl"
layout(local_size_x = 64) in;
layout(location = 0) uniform vec4 u_planes[6];
layout(location = 6) uniform dvec3 u_camera;
layout(location = 7) uniform double u_clock;
layout(location = 8) uniform vec4 u_params;  // radius, far line (radii), hysteresis
layout(location = 9) uniform float u_lines[7];
layout(location = 17) uniform uint u_anim_lod;
layout(location = 18) uniform double u_anim_step;
layout(location = 28) uniform uint u_lod_bias;  // The view's: drawn LOD = min(lod + bias, last).
// Per LOD, the sub-meshes with triangles there (bit s): a part dropped at a LOD (an empty range,
// si::buildPartLods) joins no bucket.
layout(location = 29) uniform uint u_drawn_parts[8];
// CrowdDesc::impostor_lod (0: none): an instance there joins one bucket, sub-mesh 0's.
layout(location = 37) uniform uint u_impostor_lod;
// The view's own state per instance (src/gl/paths/gpu_view_slots.h): x the handle of the
// instance it was kept for (0: a seed, whichever instance sits there), y its LOD before the bias
// (hysteresis, bits 0-15) and whether it was visible at the end of its last frame (occlusion
// culling, bit 16). Where another instance sits now (removed, added, moved by a removal) the
// view starts over: LOD 0, not visible; so churn needs no seed for views at LOD 0.
layout(std430, binding = 16) buffer SiViewInstances { uvec2 si_view[]; };
// Occlusion culling: 0 off; 1 the first phase (instances visible last frame); 2 the second
// (every instance in the frustum tested against the pyramid of what the first phase drew:
// those not occluded are visible next frame, and drawn now unless the first phase drew them).
layout(location = 20) uniform uint u_occlusion_phase;
// Layered animation: 1 when the crowd plays overlays; each visible instance's layer record
// (si::LayerRecord, CrowdManager's layerRecordOf) then goes beside its record.
layout(location = 23) uniform uint u_layers;
layout(std430, binding = 17) readonly buffer SiOverlays { SiGpuOverlay si_overlays[]; };
layout(std430, binding = 18) writeonly buffer SiLayersOut { uvec4 si_layers_out[]; };
// 2D blends: the first index of the extra layers (2 per instance) in si_overlays, and of their
// records (2 per visible instance) in si_layers_out; 0 while the crowd writes none
// (CrowdManager::writesExtraLayers). With motion vectors, the previous ones' first index in
// si_previous_layers_out.
layout(location = 38) uniform uint u_extras;
layout(location = 39) uniform uint u_previous_extras;
// Motion vectors: 1 when the renderer draws them. Each visible instance's previous record (and
// previous layer record) then goes beside its record: what this path drew of the same instance
// (keyed by its handle's slot, checked by the whole handle and its placement: a teleport since
// draws none) at the previous frame (crowd step), or, when it drew none, the current one moved
// to the previous camera's origin (InstanceBatcher::buildPrevious's fallback). Two parities of
// drawn records: the frame's own, the previous one's.
layout(location = 24) uniform uint u_motion;
layout(location = 25) uniform uvec2 u_frame;  // this frame's number, drawn records per parity
layout(location = 26) uniform vec3 u_camera_shift;  // camera position minus the previous frame's
struct SiDrawn {
  SiInstance record;
  uvec4 layer;
  uvec4 extra[2];  // A 2D blend's extra layer records (zero without).
  uvec4 tag;  // handle, frame, placement
};
layout(std430, binding = 19) buffer SiDrawnRecords { SiDrawn si_drawn[]; };
layout(std430, binding = 20) writeonly buffer SiPreviousOut { SiInstance si_previous_out[]; };
layout(std430, binding = 21) writeonly buffer SiPreviousLayersOut {
  uvec4 si_previous_layers_out[];
};

// Live poses (CrowdManager::setLivePose): every slot's current frame and hand-over
// (si::GpuLivePose), named by SiGpuInstance::live_pose (0xFFFFFFFF: none).
layout(std430, binding = 25) readonly buffer SiLivePoses { SiGpuLivePose si_live_poses[]; };

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
  if (!(c.duration > 0.0lf) || isinf(t) || isnan(t)) return 0.0lf;
  if (loop_mode == 2u) {  // LoopMode::kLoop
    double w = t - floor(t * c.inv_duration) * c.duration;
    if (w < 0.0lf) w += c.duration;
    if (w >= 0.0lf && w < c.duration) return w;
    w = t - floor(t / c.duration) * c.duration;  // The CPU's exact remainder, nearly.
    return w >= 0.0lf && w < c.duration ? w : 0.0lf;
  }
  return clamp(t, 0.0lf, c.duration);
}
// The fraction word with the interval mode in bits 30-31 (si::packFraction).
uint siPackFraction(SiGpuClip c, uint i, float f) {
  uint mode = c.modes_offset == 0xFFFFFFFFu ? 0u : uint(si_times[c.modes_offset + i]);
  return (floatBitsToUint(f) & 0x3FFFFFFFu) | (mode << 30);
}
uvec3 siSample(SiGpuClip c, double t) {  // frame, next frame, fraction word
  if (c.uniform_grid != 0u) {
    double position = t * c.inv_interval;
    uint i = min(uint(position), c.last_interval);
    return uvec3(i, i + 1u, siPackFraction(c, i, float(clamp(position - double(i), 0.0lf, 1.0lf))));
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
  return uvec3(i, i + 1u, siPackFraction(c, i, f));
}

// A posed instance's record (frame_builder.cpp's setLiveFrame, LivePoses::clipWeight, in the
// same order and unfused): the live frame alone, or as clip A with the clip's playback as
// clip B at the clip's weight, or the clip's record as it is once the clip is wholly back.
void siLiveRecord(SiGpuLivePose l, uint color, inout SiInstance rec) {
  float live = l.weight_to;
  if (u_clock - l.fade_start < l.fade_duration) {
    precise double u = max(0.0lf, (u_clock - l.fade_start) / l.fade_duration);
    precise double w = double(l.weight_from) + (double(l.weight_to) - double(l.weight_from)) * u;
    live = float(w);
  }
  precise float clip_weight = 1.0 - live;
  if (clip_weight >= 1.0) return;
  if (clip_weight <= 0.0) {
    rec.frames = uvec4(l.first_texel);
    rec.blend = uvec4(0u, 0u, floatBitsToUint(0.0), color);
    return;
  }
  rec.frames.xy = uvec2(l.first_texel);
  rec.blend.x = 0u;  // si::packFraction(0, kLinear)
  rec.blend.z = floatBitsToUint(clip_weight);
}

// The overlay's layer record at the crowd's clock (overlayWeight, packLayerWeight).
uvec4 siLayerRecord(SiGpuOverlay o, uint stride) {
  if (o.playing == 0u) return uvec4(0u);
  SiGpuClip c = si_clips[o.clip];
  uvec3 f = siSample(c, siLocalTime(o.start_time, o.start_clock, o.speed, o.loop, c));
  float w = o.weight_to;
  if (o.fade_duration > 0.0lf && u_clock < o.fade_start + o.fade_duration) {
    double u = clamp((u_clock - o.fade_start) / o.fade_duration, 0.0lf, 1.0lf);
    w = float(double(o.weight_from) + (double(o.weight_to) - double(o.weight_from)) * u);
  }
  precise float q = clamp(w, 0.0, 1.0) * 65535.0 + 0.5;
  return uvec4(c.first_texel + f.x * stride, c.first_texel + f.y * stride, f.z,
               uint(q) | (o.mask << 16));
}

void main() {
  uint i = siFlatInvocation();
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
  // A squared distance past a float (or a position past one) is culled, far line or not, as
  // on the CPU (cull_math.h, kMaxSquaredDistance).
  if (!(d2 <= uintBitsToFloat(0x7F7FFFFFu)) || isinf(d2) || isnan(d2)) return;
  if (u_params.y >= 0.0) {
    precise float far_line = u_params.y * radius;
    if (d2 > far_line * far_line) return;
  }
  // Bounds B: the clip faded from, or a live pose's own (it draws over its clip, and with it
  // while they hand over), as CrowdManager::update() culls them.
  vec4 sphere_b = cb.sphere;
  vec3 box_b_min = cb.box_min.xyz, box_b_max = cb.box_max.xyz;
  bool two_bounds = fading;
  if (st.live_pose != 0xFFFFFFFFu && si_live_poses[st.live_pose].bounded != 0u) {
    SiGpuLivePose lp = si_live_poses[st.live_pose];
    sphere_b = lp.sphere;
    box_b_min = lp.box_min.xyz;
    box_b_max = lp.box_max.xyz;
    two_bounds = true;
  }
  precise vec3 center_a = rel + siRotate(st.rotation, ca.sphere.xyz * s);
  precise vec3 center_b = rel + siRotate(st.rotation, sphere_b.xyz * s);
  precise float ra = ca.sphere.w * s;
  precise float rb = sphere_b.w * s;
  for (int k = 0; k < 6; ++k) {
    vec4 p = u_planes[k];
    precise float da = siDot3(p.xyz, center_a) + p.w;
    precise float db = siDot3(p.xyz, center_b) + p.w;
    if (!(da >= -ra) && !(db >= -rb)) return;
  }
  uint lods = u_counts.y;
  uvec2 kept = si_view[i];
  if (kept.x != 0u && kept.x != st.handle) kept.y = 0u;  // Another instance: start over.
  uint lod = min(kept.y & 0xFFFFu, lods - 1u);
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
  // Applying the hysteresis again in the second phase changes nothing.
  uint drawn = kept.y >> 16;
  si_view[i] = uvec2(st.handle, lod | (drawn << 16));
  if (u_occlusion_phase == 1u && drawn == 0u) return;
  if (u_occlusion_phase == 2u) {
    bool occluded = siOccluded(rel, st.rotation, s, ca.box_min.xyz, ca.box_max.xyz) &&
                    (!two_bounds || siOccluded(rel, st.rotation, s, box_b_min, box_b_max));
    si_view[i].y = lod | ((occluded ? 0u : 1u) << 16);
    if (occluded || drawn != 0u) return;
  }
  lod = min(lod + u_lod_bias, lods - 1u);  // The drawn LOD (CrowdViewDesc::lod_bias).
  // An impostor shows its clip's frames: a live pose stays a mesh, at the last mesh level.
  if (st.live_pose != 0xFFFFFFFFu && u_impostor_lod != 0u) lod = min(lod, u_impostor_lod - 1u);

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
  if (st.live_pose != 0xFFFFFFFFu) siLiveRecord(si_live_poses[st.live_pose], st.color, rec);
  uint v = atomicAdd(si_visible_count, 1u);
  si_records[v] = rec;
  uvec4 layer = u_layers != 0u ? siLayerRecord(si_overlays[i], stride) : uvec4(0u);
  uvec4 extra[2] = uvec4[2](uvec4(0u), uvec4(0u));
  if (u_extras != 0u) {  // Flagged on the layer record when either is drawn (layerRecordsOf).
    extra[0] = siLayerRecord(si_overlays[u_extras + 2u * i], stride);
    extra[1] = siLayerRecord(si_overlays[u_extras + 2u * i + 1u], stride);
    if (((extra[0].w | extra[1].w) & 0xFFFFu) != 0u) layer.w |= 0x80000000u;
    si_layers_out[u_extras + 2u * v] = extra[0];
    si_layers_out[u_extras + 2u * v + 1u] = extra[1];
  }
  if (u_layers != 0u) si_layers_out[v] = layer;
  if (u_motion != 0u) {
    uint slot = st.handle & 0xFFFFFu;  // HandlePool::kSlotBits
    uint here = (u_frame.x & 1u) * u_frame.y + slot, there = (~u_frame.x & 1u) * u_frame.y + slot;
    SiDrawn last = si_drawn[there];
    SiInstance prev = rec;
    uvec4 prev_layer = layer;
    uvec4 prev_extra[2] = extra;
    if (last.tag.x == st.handle && last.tag.y == u_frame.x - 1u && last.tag.z == st.placement) {
      prev = last.record;
      prev_layer = last.layer;
      prev_extra = last.extra;
    } else {
      for (int row = 0; row < 3; ++row) prev.world_rows[row].w += u_camera_shift[row];
    }
    si_previous_out[v] = prev;
    if (u_layers != 0u) si_previous_layers_out[v] = prev_layer;
    if (u_previous_extras != 0u) {
      si_previous_layers_out[u_previous_extras + 2u * v] = prev_extra[0];
      si_previous_layers_out[u_previous_extras + 2u * v + 1u] = prev_extra[1];
    }
    si_drawn[here] = SiDrawn(rec, layer, extra, uvec4(st.handle, u_frame.x, st.placement, 0u));
  }
  uint subs = u_counts.z;
  uint mask = st.mask & (subs >= 32u ? 0xFFFFFFFFu : ((1u << subs) - 1u)) & u_drawn_parts[lod];
  if (u_impostor_lod != 0u && lod >= u_impostor_lod) mask = 1u;
  si_visible[v] = uvec4(i, lod, mask, st.handle);
  for (uint m = mask; m != 0u; m &= m - 1u)
    atomicAdd(si_bucket_count[lod * subs + uint(findLSB(m))], 1u);
}
