// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The per-frame loop, after B. Dudash, "Skinned Instancing" (NVIDIA, 2007): LOD lists per frame
// on the CPU, frustum culling before anything reaches the GPU.
#include "crowd/frame_builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "crowd/cull_math.h"

namespace si::detail {

namespace {

uint32_t floatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

uint32_t wornMask(uint32_t mask, uint32_t sub_meshes) {
  return mask & (sub_meshes == 32 ? 0xFFFFFFFFu : ((1u << sub_meshes) - 1u));
}

}  // namespace

void buildFrame(const FrameInputs& in, InstanceStore& st, CrowdFrame* frame) {
  const BakedPalette& palette = *in.palette;
  const std::vector<ClipTiming>& clips = *in.clips;
  const uint32_t n = st.size(), submeshes = in.sub_mesh_count;
  const cull::Params& cull_params = in.params;
  const double anim_step = cull_params.animation_step_seconds;
  const uint32_t anim_lod = cull_params.animation_lod_start;
  const double clock = in.clock;
  const uint32_t stride = palette.layout.frame_stride_texels;

  CrowdFrame& f = *frame;
  f.stats = CrowdFrameStats();
  f.stats.instances = n;
  f.visible_dense.clear();
  f.records.clear();
  f.visible_handles.clear();
  std::fill(f.bucket_offsets.begin(), f.bucket_offsets.end(), 0u);

  // Pass 1: distance, LOD, culling, records; count bucket entries. The selection uses only
  // +, -, * and comparisons in a fixed order (cull_math.h), so the GPU-driven culling pass,
  // which does the same arithmetic, selects exactly the same instances and LODs.
  for (uint32_t i = 0; i < n; ++i) {
    const glm::vec3 rel(st.positions[i] - in.camera_position);  // Camera-relative, from double.
    const Playback& pb = st.playback[i];
    // A crossfade is over once the clock passes its end (compared without a division).
    if (st.fade_duration[i] > 0.0 && !(clock - st.fade_start[i] < st.fade_duration[i]))
      st.fade_duration[i] = 0.0;
    const bool fading = st.fade_duration[i] > 0.0;
    const ClipTiming& ca = clips[pb.clip];
    const ClipTiming& cb = clips[fading ? st.fade_from[i].clip : pb.clip];
    cull::Selection sel;
    sel.lod = st.lods[i];
    if (!cull::select(rel, st.rotations[i], st.scales[i], ca.sphere_center, ca.sphere_radius,
                      cb.sphere_center, cb.sphere_radius, cull_params, &sel)) {
      ++(sel.culled_by_distance ? f.stats.culled_distance : f.stats.culled_frustum);
      continue;
    }
    const uint32_t lod = sel.lod;
    st.lods[i] = static_cast<uint8_t>(lod);
    ++f.stats.per_lod[lod];

    // The record.
    InstanceRecord rec;
    const glm::mat3 r = glm::mat3_cast(st.rotations[i]) * st.scales[i];
    for (int row = 0; row < 3; ++row) {
      rec.world_rows[row][0] = r[0][row];
      rec.world_rows[row][1] = r[1][row];
      rec.world_rows[row][2] = r[2][row];
      rec.world_rows[row][3] = rel[row];
    }
    double ta = localTime(pb, ca, clock);
    if (lod >= anim_lod) ta = std::floor(ta / anim_step) * anim_step;
    const FrameSample fa = fastSample(ca, palette.clips[pb.clip], ta);
    rec.frames[0] = ca.first_texel + fa.frame * stride;
    rec.frames[1] = ca.first_texel + fa.next_frame * stride;
    rec.blend[0] = floatBits(fa.fraction);
    rec.blend[3] = st.colors[i];
    if (fading) {
      // Clip A is the one fading out; B the new one, weighted by weight_b.
      const float weight_b =
          std::min(float((clock - st.fade_start[i]) / st.fade_duration[i]), 1.0f);
      const Playback& old = st.fade_from[i];
      double tb = localTime(old, cb, clock);
      if (lod >= anim_lod) tb = std::floor(tb / anim_step) * anim_step;
      const FrameSample fo = fastSample(cb, palette.clips[old.clip], tb);
      rec.frames[2] = rec.frames[0];
      rec.frames[3] = rec.frames[1];
      rec.blend[1] = rec.blend[0];
      rec.frames[0] = cb.first_texel + fo.frame * stride;
      rec.frames[1] = cb.first_texel + fo.next_frame * stride;
      rec.blend[0] = floatBits(fo.fraction);
      rec.blend[2] = floatBits(std::max(0.0f, weight_b));
    } else {
      rec.frames[2] = rec.frames[0];
      rec.frames[3] = rec.frames[1];
      rec.blend[1] = rec.blend[0];
      rec.blend[2] = floatBits(0.0f);
    }
    f.records.push_back(rec);
    f.visible_dense.push_back(i);
    f.visible_handles.push_back(st.dense_handles[i]);
    for (uint32_t mask = wornMask(st.masks[i], submeshes); mask; mask &= mask - 1)
      ++f.bucket_offsets[lod * submeshes + uint32_t(__builtin_ctz(mask)) + 1];
  }
  f.stats.visible = static_cast<uint32_t>(f.records.size());

  // Prefix sums, then pass 2: fill each bucket in visible order (deterministic).
  const uint32_t buckets = uint32_t(f.bucket_offsets.size()) - 1;
  for (uint32_t b = 0; b < buckets; ++b) f.bucket_offsets[b + 1] += f.bucket_offsets[b];
  f.stats.bucket_entries = f.bucket_offsets[buckets];
  f.bucket_entries.resize(f.stats.bucket_entries);
  f.bucket_cursor.assign(f.bucket_offsets.begin(), f.bucket_offsets.end() - 1);
  for (uint32_t v = 0; v < f.visible_dense.size(); ++v) {
    const uint32_t i = f.visible_dense[v];
    const uint32_t base = st.lods[i] * submeshes;
    for (uint32_t mask = wornMask(st.masks[i], submeshes); mask; mask &= mask - 1)
      f.bucket_entries[f.bucket_cursor[base + uint32_t(__builtin_ctz(mask))]++] = v;
  }
}

}  // namespace si::detail
