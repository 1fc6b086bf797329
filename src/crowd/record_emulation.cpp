// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The shader's arithmetic on a record, on the CPU.
#include "si/crowd/record_emulation.h"

#include <cstring>
#include <vector>

namespace si {

glm::mat4 emulateRecordMatrix(const BakedPalette& palette, const InstanceRecord& rec,
                              uint32_t slot) {
  IntervalMode ma, mb;
  const float fa = unpackFraction(rec.blend[0], &ma), fb = unpackFraction(rec.blend[1], &mb);
  float wb;
  std::memcpy(&wb, &rec.blend[2], 4);
  glm::mat4 mat = emulateFrameMatrix(palette, rec.frames[0], rec.frames[1], fa, ma, slot);
  if (wb > 0.0f)
    mat = mat * (1.0f - wb) +
          emulateFrameMatrix(palette, rec.frames[2], rec.frames[3], fb, mb, slot) * wb;
  return mat;
}

Status emulateRecordMorphWeights(const BakedPalette& palette, const InstanceRecord& rec,
                                 Span<float> out) {
  IntervalMode ma, mb;
  const float fa = unpackFraction(rec.blend[0], &ma), fb = unpackFraction(rec.blend[1], &mb);
  float wb;
  std::memcpy(&wb, &rec.blend[2], 4);
  Status s = emulateMorphWeights(palette, rec.frames[0], rec.frames[1], fa, ma, out);
  if (!s.isOk() || !(wb > 0.0f)) return s;
  std::vector<float> b(out.size());
  s = emulateMorphWeights(palette, rec.frames[2], rec.frames[3], fb, mb, b);
  for (size_t k = 0; k < out.size() && s.isOk(); ++k) out[k] = out[k] * (1.0f - wb) + b[k] * wb;
  return s;
}

Status emulateLayeredMorphWeights(const BakedPalette& palette, const InstanceRecord& rec,
                                  const LayerRecord& layer, Span<const LayerMask> masks,
                                  Span<float> out) {
  return emulateLayeredMorphWeights(palette, rec, layer, Span<const LayerRecord>(), masks, out);
}

Status emulateLayeredMorphWeights(const BakedPalette& palette, const InstanceRecord& rec,
                                  const LayerRecord& layer, Span<const LayerRecord> extras,
                                  Span<const LayerMask> masks, Span<float> out) {
  Status s = emulateRecordMorphWeights(palette, rec, out);
  const uint32_t m = layerMask(layer);
  if (!s.isOk() || m >= masks.size() || masks[m].morph_targets.empty()) return s;
  const bool chained = layerHasExtras(layer) && extras.size() >= kExtraLayerRecords;
  const LayerRecord chain[1 + kExtraLayerRecords] = {layer, chained ? extras[0] : LayerRecord{},
                                                     chained ? extras[1] : LayerRecord{}};
  std::vector<float> overlay(out.size());
  for (const LayerRecord& l : chain) {
    const float w = layerWeight(l);
    if (!(w > 0.0f)) continue;
    IntervalMode mode;
    const float fraction = unpackFraction(l.fraction, &mode);
    s = emulateMorphWeights(palette, l.frames[0], l.frames[1], fraction, mode, overlay);
    for (uint32_t t : masks[m].morph_targets)
      if (s.isOk() && t < out.size()) out[t] = out[t] * (1.0f - w) + overlay[t] * w;
    if (!s.isOk()) return s;
  }
  return s;
}

glm::mat4 emulateLayeredRecordMatrix(const BakedPalette& palette, const InstanceRecord& rec,
                                     const LayerRecord& layer, Span<const LayerMask> masks,
                                     uint32_t slot) {
  return emulateLayeredRecordMatrix(palette, rec, layer, Span<const LayerRecord>(), masks, slot);
}

glm::mat4 emulateLayeredRecordMatrix(const BakedPalette& palette, const InstanceRecord& rec,
                                     const LayerRecord& layer, Span<const LayerRecord> extras,
                                     Span<const LayerMask> masks, uint32_t slot) {
  const uint32_t m = layerMask(layer);
  const auto base = [&](uint32_t s) { return emulateRecordMatrix(palette, rec, s); };
  const bool chained = layerHasExtras(layer) && extras.size() >= kExtraLayerRecords;
  if (m >= masks.size() || (!chained && !(layerWeight(layer) > 0.0f))) return base(slot);
  if (!chained) {
    IntervalMode mode;
    const float fraction = unpackFraction(layer.fraction, &mode);
    const auto overlay = [&](uint32_t s) {
      return emulateFrameMatrix(palette, layer.frames[0], layer.frames[1], fraction, mode, s);
    };
    return emulateLayeredMatrix(masks[m], slot, layerWeight(layer), base, overlay);
  }
  const auto poseOf = [&](const LayerRecord& r) {
    IntervalMode mode;
    const float fraction = unpackFraction(r.fraction, &mode);
    return LayerPose{[&palette, r, fraction, mode](uint32_t s) {
                       return emulateFrameMatrix(palette, r.frames[0], r.frames[1], fraction, mode,
                                                 s);
                     },
                     layerWeight(r)};
  };
  const LayerPose layers[1 + kExtraLayerRecords] = {poseOf(layer), poseOf(extras[0]),
                                                    poseOf(extras[1])};
  return emulateLayeredChain(masks[m], slot, base,
                             Span<const LayerPose>(layers, 1 + kExtraLayerRecords));
}

}  // namespace si
