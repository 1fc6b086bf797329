// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The shader's arithmetic on a record, on the CPU.
#include "si/crowd/record_emulation.h"

#include <cstring>

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

glm::mat4 emulateLayeredRecordMatrix(const BakedPalette& palette, const InstanceRecord& rec,
                                     const LayerRecord& layer, Span<const LayerMask> masks,
                                     uint32_t slot) {
  const glm::mat4 base = emulateRecordMatrix(palette, rec, slot);
  const float weight = layerWeight(layer);
  const uint32_t m = layerMask(layer);
  if (!(weight > 0.0f) || m >= masks.size() || !masks[m].contains(slot)) return base;
  const int32_t anchor = masks[m].slot_anchor[slot];
  IntervalMode mode;
  const float fraction = unpackFraction(layer.fraction, &mode);
  const auto overlay = [&](uint32_t s) {
    return emulateFrameMatrix(palette, layer.frames[0], layer.frames[1], fraction, mode, s);
  };
  const glm::mat4 base_anchor =
      anchor >= 0 ? emulateRecordMatrix(palette, rec, uint32_t(anchor)) : glm::mat4(1.0f);
  const glm::mat4 overlay_anchor = anchor >= 0 ? overlay(uint32_t(anchor)) : glm::mat4(1.0f);
  std::vector<glm::mat4> base_chain, overlay_chain;
  for (uint32_t up : layerChain(masks[m], slot)) {
    base_chain.push_back(emulateRecordMatrix(palette, rec, up));
    overlay_chain.push_back(overlay(up));
  }
  return emulateLayeredMatrix(base, overlay(slot), base_anchor, overlay_anchor, anchor, weight,
                              base_chain, overlay_chain);
}

}  // namespace si
