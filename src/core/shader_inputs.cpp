// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The vertex stream and palette uniform of the shipped GLSL skinning interface.
#include "si/core/shader_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/str_cat.h"

namespace si {
using detail::strCat;

uint32_t packNormal10(const glm::vec3& n) {
  const auto c = [](float v) {
    return uint32_t(int32_t(std::lround(std::clamp(v, -1.0f, 1.0f) * 511.0f)) & 0x3FF);
  };
  return c(n.x) | (c(n.y) << 10) | (c(n.z) << 20);
}

uint32_t packTangent10(const glm::vec4& t) {
  return packNormal10(glm::vec3(t)) | ((t.w < 0.0f ? 3u : 1u) << 30);
}

uint32_t packColor8(const glm::vec4& color) {
  uint32_t word = 0;
  for (int c = 0; c < 4; ++c)
    word |= uint32_t(std::lround(std::clamp(color[c], 0.0f, 1.0f) * 255.0f)) << (8 * c);
  return word;
}

Status buildVertexStream(const SkinnedMesh& mesh, const BakedPalette& palette, VertexStream* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "buildVertexStream: out is null"};
  Status s = mesh.validate(palette.skeleton_to_palette.size());
  if (!s.isOk()) return s;
  VertexStream stream;
  stream.wide_joints = palette.palette_joints.size() > 256;
  stream.stride_bytes = stream.wide_joints ? 36 : 32;
  if (!mesh.joints1.empty()) {  // Right after the fixed words: the pre-skinning reads them so.
    stream.joints1_offset = stream.stride_bytes;
    stream.weights1_offset = stream.joints1_offset + (stream.wide_joints ? 8 : 4);
    stream.stride_bytes = stream.weights1_offset + 8;
  }
  const bool tangents = !mesh.tangents.empty();
  if (tangents) stream.tangent_offset = stream.stride_bytes;
  if (tangents) stream.stride_bytes += 4;
  if (!mesh.texcoords1.empty()) {
    stream.texcoord1_offset = stream.stride_bytes;
    stream.stride_bytes += 4;
  }
  if (!mesh.colors.empty()) {
    stream.color_offset = stream.stride_bytes;
    stream.stride_bytes += 4;
  }
  stream.weights_offset = stream.wide_joints ? 28 : 24;
  stream.vertex_count = uint32_t(mesh.vertexCount());
  stream.bytes.resize(mesh.vertexCount() * stream.stride_bytes);
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    uint8_t* dst = stream.bytes.data() + v * stream.stride_bytes;
    std::memcpy(dst + VertexStream::kPositionOffset, &mesh.positions[v], 12);
    const uint32_t n = packNormal10(mesh.normals[v]);
    std::memcpy(dst + VertexStream::kNormalOffset, &n, 4);
    const glm::vec2 uv = mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[v];
    const uint16_t h[2] = {floatToHalf(uv.x), floatToHalf(uv.y)};
    std::memcpy(dst + VertexStream::kTexcoordOffset, h, 4);
    uint16_t slots[8] = {};
    for (size_t k = 0; k < mesh.influenceCount(); ++k) {
      const Influence in = mesh.influence(v, k);
      if (in.weight == 0.0f) continue;
      const int32_t slot = palette.skeleton_to_palette[in.joint];
      if (slot < 0)
        return {StatusCode::kInvalidArgument,
                strCat("buildVertexStream: vertex ", v, " is weighted to joint ", in.joint,
                       ", which the palette does not store")};
      slots[k] = uint16_t(slot);
    }
    const auto putJoints = [&](uint32_t offset, const uint16_t* four) {
      if (stream.wide_joints) {
        std::memcpy(dst + offset, four, 8);
        return;
      }
      const uint8_t narrow[4] = {uint8_t(four[0]), uint8_t(four[1]), uint8_t(four[2]),
                                 uint8_t(four[3])};
      std::memcpy(dst + offset, narrow, 4);
    };
    putJoints(VertexStream::kJointsOffset, slots);
    glm::u16vec4 w, w1;
    if (stream.joints1_offset == 0) {
      w = quantizeWeights(mesh.weights[v]);
    } else {
      quantizeWeights(mesh.weights[v], mesh.weights1[v], &w, &w1);
      putJoints(stream.joints1_offset, slots + 4);
      std::memcpy(dst + stream.weights1_offset, &w1, 8);
    }
    std::memcpy(dst + stream.weights_offset, &w, 8);
    if (tangents) {
      const uint32_t t = packTangent10(mesh.tangents[v]);
      std::memcpy(dst + stream.tangent_offset, &t, 4);
    }
    if (stream.texcoord1_offset != 0) {
      const uint16_t h1[2] = {floatToHalf(mesh.texcoords1[v].x), floatToHalf(mesh.texcoords1[v].y)};
      std::memcpy(dst + stream.texcoord1_offset, h1, 4);
    }
    if (stream.color_offset != 0) {
      const uint32_t rgba = packColor8(mesh.colors[v]);
      std::memcpy(dst + stream.color_offset, &rgba, 4);
    }
  }
  *out = std::move(stream);
  return Status::ok();
}

glm::uvec4 paletteShaderInfo(const BakedPalette& palette) {
  return glm::uvec4(palette.layout.width_log2, palette.layout.joint_stride_texels,
                    palette.format == PaletteFormat::kQuatTranslationF32 ? 1u : 0u, 0u);
}

}  // namespace si
