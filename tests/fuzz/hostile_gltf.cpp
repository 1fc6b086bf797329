// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Hostile glTF seeds (hostile_gltf.h): one small skinned, animated file written out, then
// variants of it that each break one rule the importer and the bake must refuse or survive.
#include "hostile_gltf.h"

#include "gltf/morph_asset.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace si::fuzz {

namespace {

// The base file's buffer: positions (4 x vec3), joints (4 x u8vec4), weights (4 x vec4),
// indices (6 x u16, padded), 2 inverse bind matrices, 2 key times, 2 rotation keys.
struct Layout {
  static constexpr size_t kPositions = 0, kJoints = 48, kWeights = 64, kIndices = 128, kBinds = 144,
                          kTimes = 272, kRotations = 280, kBytes = 312;
};

void putFloats(std::vector<uint8_t>* b, size_t at, std::initializer_list<float> values) {
  for (float v : values) {
    std::memcpy(b->data() + at, &v, 4);
    at += 4;
  }
}

std::vector<uint8_t> baseBuffer() {
  std::vector<uint8_t> b(Layout::kBytes, 0);
  putFloats(&b, Layout::kPositions, {-0.5f, 0, 0, 0.5f, 0, 0, 0.5f, 1, 0, -0.5f, 1, 0});
  const uint8_t joints[16] = {0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  std::memcpy(b.data() + Layout::kJoints, joints, 16);
  putFloats(&b, Layout::kWeights, {1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::memcpy(b.data() + Layout::kIndices, indices, 12);
  // Joint 0 at the origin, joint 1 half a unit up: their inverse bind matrices.
  putFloats(&b, Layout::kBinds, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  putFloats(&b, Layout::kBinds + 64, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -0.5f, 0, 1});
  putFloats(&b, Layout::kTimes, {0.0f, 1.0f});
  putFloats(&b, Layout::kRotations, {0, 0, 0, 1, 0, 0, 0.3826834f, 0.9238795f});
  return b;
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t(bytes[i]) << 16) |
                       (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0u) |
                       (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0u);
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

// The base file's JSON with the buffer embedded.
std::string baseJson(const std::vector<uint8_t>& buffer) {
  return std::string(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,2]}],)") +
         R"("nodes":[{"name":"hip","children":[1]},{"name":"spine","translation":[0,0.5,0]},)" +
         R"({"name":"body","mesh":0,"skin":0}],)" +
         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2},)" +
         R"("indices":3}]}],"skins":[{"joints":[0,1],"inverseBindMatrices":4}],)" +
         R"("animations":[{"name":"bend","channels":[{"sampler":0,"target":{"node":1,)" +
         R"("path":"rotation"}}],"samplers":[{"input":5,"output":6,"interpolation":"LINEAR"}]}],)" +
         R"("accessors":[)" +
         R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-0.5,0,0],)" +
         R"("max":[0.5,1,0]},)" +
         R"({"bufferView":1,"componentType":5121,"count":4,"type":"VEC4"},)" +
         R"({"bufferView":2,"componentType":5126,"count":4,"type":"VEC4"},)" +
         R"({"bufferView":3,"componentType":5123,"count":6,"type":"SCALAR"},)" +
         R"({"bufferView":4,"componentType":5126,"count":2,"type":"MAT4"},)" +
         R"({"bufferView":5,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]},)" +
         R"({"bufferView":6,"componentType":5126,"count":2,"type":"VEC4"}],)" +
         R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},)" +
         R"({"buffer":0,"byteOffset":48,"byteLength":16},)" +
         R"({"buffer":0,"byteOffset":64,"byteLength":64},)" +
         R"({"buffer":0,"byteOffset":128,"byteLength":12},)" +
         R"({"buffer":0,"byteOffset":144,"byteLength":128},)" +
         R"({"buffer":0,"byteOffset":272,"byteLength":8},)" +
         R"({"buffer":0,"byteOffset":280,"byteLength":32}],)" +
         R"("buffers":[{"byteLength":312,"uri":"data:application/octet-stream;base64,)" +
         base64(buffer) + R"("}]})";
}

// `json` with the first `from` replaced by `to` (the caller's variant names a text the base
// holds: an absent one is a generator bug, reported).
bool replaced(std::string* json, const std::string& from, const std::string& to) {
  const size_t at = json->find(from);
  if (at == std::string::npos) {
    std::fprintf(stderr, "si_write_fuzz_seeds: the base glTF holds no \"%s\"\n", from.c_str());
    return false;
  }
  json->replace(at, from.size(), to);
  return true;
}

struct JsonEdit {
  const char* name;
  const char* from;
  const char* to;
};

// One rule broken per file, in the JSON.
const JsonEdit kJsonEdits[] = {
    {"node_cycle", R"("translation":[0,0.5,0]})", R"("translation":[0,0.5,0],"children":[0]})"},
    {"node_own_child", R"({"name":"hip","children":[1]})", R"({"name":"hip","children":[0,1]})"},
    {"node_two_parents", R"("mesh":0,"skin":0})", R"("mesh":0,"skin":0,"children":[1]})"},
    {"skin_joint_past_nodes", R"("joints":[0,1])", R"("joints":[0,9])"},
    {"skin_joint_twice", R"("joints":[0,1])", R"("joints":[1,1])"},
    {"skin_joint_is_the_mesh", R"("joints":[0,1])", R"("joints":[0,2])"},
    {"skin_no_joints", R"("joints":[0,1])", R"("joints":[])"},
    {"skin_past_skins", R"("mesh":0,"skin":0)", R"("mesh":0,"skin":3)"},
    {"binds_count_short", R"("count":2,"type":"MAT4")", R"("count":1,"type":"MAT4")"},
    {"binds_wrong_type", R"("count":2,"type":"MAT4")", R"("count":2,"type":"VEC4")"},
    {"accessor_past_view", R"("count":4,"type":"VEC3")", R"("count":400,"type":"VEC3")"},
    {"accessor_count_huge", R"("count":6,"type":"SCALAR")",
     R"("count":4294967295,"type":"SCALAR")"},
    {"accessor_negative_count", R"("count":4,"type":"VEC3")", R"("count":-4,"type":"VEC3")"},
    {"view_past_buffer", R"("byteOffset":280,"byteLength":32)",
     R"("byteOffset":280,"byteLength":3200)"},
    {"view_odd_stride", R"("byteOffset":64,"byteLength":64})",
     R"("byteOffset":64,"byteLength":64,"byteStride":6})"},
    {"view_offset_huge", R"("byteOffset":128,"byteLength":12)",
     R"("byteOffset":18446744073709551615,"byteLength":12)"},
    {"buffer_length_lies", R"("byteLength":312,"uri")", R"("byteLength":31200,"uri")"},
    {"indices_as_floats", R"("componentType":5123,"count":6)", R"("componentType":5126,"count":6)"},
    {"joints_as_floats", R"("componentType":5121,"count":4,"type":"VEC4")",
     R"("componentType":5126,"count":4,"type":"VEC4")"},
    {"times_decreasing", R"("min":[0],"max":[1])", R"("min":[1],"max":[0])"},
    {"keys_short", R"("componentType":5126,"count":2,"type":"VEC4"}])",
     R"("componentType":5126,"count":1,"type":"VEC4"}])"},
    {"cubic_without_tangents", R"("interpolation":"LINEAR")", R"("interpolation":"CUBICSPLINE")"},
    {"unknown_interpolation", R"("interpolation":"LINEAR")", R"("interpolation":"SMOOTH")"},
    {"channel_past_nodes", R"("target":{"node":1,)", R"("target":{"node":99,)"},
    {"channel_unknown_path", R"("path":"rotation")", R"("path":"twist")"},
    {"channel_weights_without_targets", R"("path":"rotation")", R"("path":"weights")"},
    {"scale_past_float", R"("translation":[0,0.5,0])",
     R"("translation":[0,0.5,0],"scale":[1e39,1e39,1e39])"},
    {"translation_huge", R"("translation":[0,0.5,0])", R"("translation":[3e38,3e38,3e38])"},
    {"matrix_singular", R"("translation":[0,0.5,0])",
     R"("matrix":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0])"},
    {"rotation_zero", R"("translation":[0,0.5,0])", R"("rotation":[0,0,0,0])"},
    {"points_not_triangles", R"("indices":3})", R"("indices":3,"mode":0})"},
    {"no_positions", R"({"POSITION":0,)", R"({)"},
    {"eight_influences_half", R"("WEIGHTS_0":2})", R"("WEIGHTS_0":2,"JOINTS_1":1})"},
    {"morph_target_past_accessors", R"("indices":3})",
     R"("indices":3,"targets":[{"POSITION":42}]})"},
    {"sparse_past_count", R"("count":4,"type":"VEC3",)",
     R"("count":4,"type":"VEC3","sparse":{"count":1,"indices":{"bufferView":3,"componentType":5123},"values":{"bufferView":0}},)"},
    {"no_scene_nodes", R"("scenes":[{"nodes":[0,2]}])", R"("scenes":[{"nodes":[]}])"},
    {"scene_past_scenes", R"("scene":0)", R"("scene":5)"},
};

// One rule broken per file, in the buffer: a byte offset and the floats written there.
struct BufferEdit {
  const char* name;
  size_t at;
  std::vector<float> values;
};

std::vector<BufferEdit> bufferEdits() {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  return {
      {"weights_nan", Layout::kWeights, {nan, nan, nan, nan}},
      {"weights_zero", Layout::kWeights, {0, 0, 0, 0}},
      {"weights_negative", Layout::kWeights + 16, {-1, 2, 0, 0}},
      {"weights_infinite", Layout::kWeights + 32, {inf, 0, 0, 0}},
      {"positions_nan", Layout::kPositions, {nan, 0, 0}},
      {"positions_huge", Layout::kPositions + 12, {3e38f, 3e38f, 3e38f}},
      {"binds_nan", Layout::kBinds, {nan, 0, 0, 0}},
      {"binds_zero", Layout::kBinds + 64, std::vector<float>(16, 0.0f)},
      {"binds_huge", Layout::kBinds + 64, {1e38f, 0, 0, 0, 0, 1e38f, 0, 0, 0, 0, 1e38f}},
      {"times_nan", Layout::kTimes, {nan, 1}},
      {"times_equal", Layout::kTimes, {0.5f, 0.5f}},
      {"times_decreasing_keys", Layout::kTimes, {1, 0}},
      {"times_huge", Layout::kTimes + 4, {3e38f}},
      {"rotation_nan", Layout::kRotations, {nan, nan, nan, nan}},
      {"rotation_zero_length", Layout::kRotations + 16, {0, 0, 0, 0}},
      {"rotation_huge", Layout::kRotations + 16, {3e38f, 3e38f, 0, 0}},
  };
}

bool write(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), std::streamsize(text.size()));
  if (!out) std::fprintf(stderr, "si_write_fuzz_seeds: cannot write %s\n", path.c_str());
  return bool(out);
}

}  // namespace

int writeHostileGltfs(const std::string& dir) {
  const std::vector<uint8_t> buffer = baseBuffer();
  const std::string base = baseJson(buffer);
  int written = 0;
  if (!write(dir + "/hostile_base.gltf", base)) return 1;
  ++written;
  for (const JsonEdit& e : kJsonEdits) {
    std::string json = base;
    if (!replaced(&json, e.from, e.to) || !write(dir + "/hostile_" + e.name + ".gltf", json))
      return 1;
    ++written;
  }
  for (const BufferEdit& e : bufferEdits()) {
    std::vector<uint8_t> b = buffer;
    for (size_t k = 0; k < e.values.size(); ++k)
      std::memcpy(b.data() + e.at + 4 * k, &e.values[k], 4);
    if (!write(dir + "/hostile_" + e.name + ".gltf", baseJson(b))) return 1;
    ++written;
  }
  // Joint indices past the skin's joints, at every vertex.
  std::vector<uint8_t> b = buffer;
  for (size_t v = 0; v < 4; ++v) b[Layout::kJoints + 4 * v] = uint8_t(200 + v);
  if (!write(dir + "/hostile_joints_past_skin.gltf", baseJson(b))) return 1;
  ++written;
  // The skeleton under a chain of 4000 nodes (a walk of the hierarchy, recursive or quadratic,
  // at depth).
  std::string deep = base;
  std::string chain;
  const int kDepth = 4000;  // Nodes 4 to 4003, node 3 the chain's root, the last hip's parent.
  for (int k = 0; k < kDepth; ++k)
    chain += ",{\"children\":[" + std::to_string(k < kDepth - 1 ? 5 + k : 0) + "]}";
  if (!replaced(&deep, R"({"name":"body","mesh":0,"skin":0}])",
                R"({"name":"body","mesh":0,"skin":0},{"children":[4]})" + chain + "]") ||
      !replaced(&deep, R"("nodes":[0,2]})", R"("nodes":[3,2]})") ||
      !write(dir + "/hostile_deep_chain.gltf", deep))
    return 1;
  ++written;
  // Well-formed morph targets and weights channels (tests/gltf/morph_asset.h), one file per
  // interpolation: the fuzzer's way into the morph import.
  for (const char* interp : {"LINEAR", "STEP", "CUBICSPLINE"}) {
    if (!write(dir + "/morph_" + interp + ".gltf", si::test::morphFile(interp))) return 1;
    ++written;
  }
  std::printf("si_write_fuzz_seeds: %d glTF files in %s\n", written, dir.c_str());
  return 0;
}

}  // namespace si::fuzz
