// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The vertex stream and palette uniform of the shipped GLSL skinning interface.
#include "si/core/shader_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/morph_entries.h"
#include "core/str_cat.h"
#include "si/core/lod_error.h"

namespace si {
using detail::strCat;

namespace {
// kLimitExceeded past the entries a morph word can name.
Status checkMorphEntryCount(const detail::MorphEntriesByVertex& by_vertex) {
  if (by_vertex.entries.size() <= kMaxMorphEntries) return Status::ok();
  return {StatusCode::kLimitExceeded,
          strCat("the mesh's morph targets move vertices ", by_vertex.entries.size(),
                 " times; the morph word holds at most ", kMaxMorphEntries)};
}

// Each vertex's morph word (first entry << 9 | count) for the entries `by_vertex`.
Status morphWords(const detail::MorphEntriesByVertex& by_vertex, std::vector<uint32_t>* words) {
  const Status s = checkMorphEntryCount(by_vertex);
  if (!s.isOk()) return s;
  words->assign(by_vertex.first.size() - 1, 0u);
  for (size_t v = 0; v + 1 < by_vertex.first.size(); ++v) {
    const uint32_t count = by_vertex.first[v + 1] - by_vertex.first[v];
    if (count > 0) (*words)[v] = by_vertex.first[v] << 9 | count;
  }
  return Status::ok();
}
}  // namespace

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
  std::vector<uint32_t> morph_words;
  if (!mesh.morph_targets.empty()) {
    stream.morph_offset = stream.stride_bytes;
    stream.stride_bytes += 4;
    s = morphWords(detail::morphEntriesByVertex(mesh), &morph_words);
    if (!s.isOk()) return s;
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
    if (stream.morph_offset != 0) std::memcpy(dst + stream.morph_offset, &morph_words[v], 4);
  }
  *out = std::move(stream);
  return Status::ok();
}

Status buildMorphStream(const SkinnedMesh& mesh, const BakedPalette& palette,
                        uint32_t max_texture_size, MorphStream* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "buildMorphStream: out is null"};
  if (mesh.morph_targets.empty())
    return {StatusCode::kInvalidArgument, "buildMorphStream: the mesh has no morph targets"};
  Status s = mesh.validate(palette.skeleton_to_palette.size());
  if (!s.isOk()) return s;
  if (palette.layout.morph_target_count != mesh.morph_targets.size())
    return {StatusCode::kInvalidArgument,
            strCat("buildMorphStream: the palette holds the weights of ",
                   palette.layout.morph_target_count, " morph targets, the mesh has ",
                   mesh.morph_targets.size(), " (bake it with them)")};
  detail::MorphEntriesByVertex by_vertex = detail::morphEntriesByVertex(mesh);
  s = checkMorphEntryCount(by_vertex);  // The vertex stream's words name these runs.
  if (!s.isOk()) return s;
  const std::vector<float> tails =
      detail::orderMorphEntriesByEffect(mesh, detail::morphWeightBounds(palette), &by_vertex);
  MorphStream stream;
  const bool normals = std::any_of(mesh.morph_targets.begin(), mesh.morph_targets.end(),
                                   [](const MorphTarget& t) { return !t.normal_deltas.empty(); });
  const bool tangents = std::any_of(mesh.morph_targets.begin(), mesh.morph_targets.end(),
                                    [](const MorphTarget& t) { return !t.tangent_deltas.empty(); });
  stream.texels_per_entry = tangents ? 3 : normals ? 2 : 1;
  stream.entry_count = uint32_t(by_vertex.entries.size());
  const uint64_t texels = uint64_t(std::max(stream.entry_count, 1u)) * stream.texels_per_entry;
  const uint64_t max = max_texture_size == 0 ? 16384 : max_texture_size;
  stream.width_log2 = 0;
  while ((uint64_t(1) << stream.width_log2) * (uint64_t(1) << stream.width_log2) < texels)
    ++stream.width_log2;
  stream.width = 1u << stream.width_log2;
  stream.height = uint32_t((texels + stream.width - 1) / stream.width);
  if (stream.width > max || stream.height > max)
    return {StatusCode::kLimitExceeded,
            strCat("buildMorphStream: ", texels, " texels of morph entries do not fit in a ", max,
                   "x", max, " texture")};
  stream.texels.assign(size_t(stream.width) * stream.height * 4, 0u);
  uint32_t e = 0;
  const auto put = [&](uint32_t texel, uint32_t w0, const glm::vec3& v) {
    uint32_t* dst = stream.texels.data() + size_t(texel) * 4;
    dst[0] = w0;
    std::memcpy(dst + 1, &v, 12);
  };
  for (const detail::MorphEntriesByVertex::Entry& entry : by_vertex.entries) {
    const uint32_t target = entry.target, i = entry.index;
    const MorphTarget& t = mesh.morph_targets[target];
    const uint32_t at = e * stream.texels_per_entry;
    put(at, target | detail::morphTailBits(tails[e]), t.position_deltas[i]);
    if (stream.texels_per_entry > 1)
      put(at + 1, 0u, t.normal_deltas.empty() ? glm::vec3(0.0f) : t.normal_deltas[i]);
    if (stream.texels_per_entry > 2)
      put(at + 2, 0u, t.tangent_deltas.empty() ? glm::vec3(0.0f) : t.tangent_deltas[i]);
    ++e;
  }
  *out = std::move(stream);
  return Status::ok();
}

glm::uvec4 morphShaderInfo(const BakedPalette& palette, const MorphStream& stream) {
  return glm::uvec4(stream.width_log2, stream.texels_per_entry, palette.layout.morph_first_texel,
                    palette.layout.morph_target_count);
}

Status morphLodCuts(const SkinnedMesh& mesh, float share, std::array<float, kMorphLodCuts>* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "morphLodCuts: out is null"};
  if (!(share >= 0.0f && share <= 1.0f))
    return {StatusCode::kInvalidArgument,
            strCat("morphLodCuts: the share ", share, " is not within 0 and 1")};
  // Levels without measured errors cut nothing: every target kept, exactly.
  const bool measured = std::all_of(mesh.sub_meshes.begin(), mesh.sub_meshes.end(),
                                    [](const SubMesh& m) { return !m.lod_error_units.empty(); });
  std::vector<float> levels;
  if (measured) {
    const Status s = lodErrorsByLevel(mesh, &levels);
    if (!s.isOk()) return s;
  }
  std::array<float, kMorphLodCuts> cuts{};
  for (size_t k = 0; k < cuts.size(); ++k)
    cuts[k] = share * (k < levels.size() ? levels[k] : levels.empty() ? 0.0f : levels.back());
  *out = cuts;
  return Status::ok();
}

glm::uvec4 paletteShaderInfo(const BakedPalette& palette) {
  return glm::uvec4(palette.layout.width_log2, palette.layout.joint_stride_texels,
                    palette.format == PaletteFormat::kQuatTranslationF32 ? 1u : 0u, 0u);
}

}  // namespace si
