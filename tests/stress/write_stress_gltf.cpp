// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// write_stress_gltf: writes the generated stress character (stress/stress_character.h) as a
// glTF 2.0 file (OUT.gltf + OUT.bin), so that the tools that take assets (si-bake --cast,
// bake_report --model) measure it beside the shared ones. One node per joint, one skinned
// mesh with one primitive per sub-mesh, one animation with a LINEAR sampler per channel.
// Usage: write_stress_gltf OUT.gltf [--duration S]
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "stress/stress_character.h"

namespace {

struct Writer {
  std::vector<unsigned char> bin;
  std::string views, accessors;
  int view_count = 0, accessor_count = 0;

  // Appends `bytes` as a buffer view and an accessor over it; returns the accessor index.
  int add(const void* bytes, size_t size, const char* type, int component, size_t count,
          const std::string& bounds = "", int target = 0) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    bin.insert(bin.end(), static_cast<const unsigned char*>(bytes),
               static_cast<const unsigned char*>(bytes) + size);
    views += std::string(view_count ? "," : "") + "{\"buffer\":0,\"byteOffset\":" +
             std::to_string(offset) + ",\"byteLength\":" + std::to_string(size) +
             (target ? ",\"target\":" + std::to_string(target) : "") + "}";
    accessors += std::string(accessor_count ? "," : "") + "{\"bufferView\":" +
                 std::to_string(view_count) + ",\"componentType\":" + std::to_string(component) +
                 ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + bounds + "}";
    ++view_count;
    return accessor_count++;
  }
};

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: write_stress_gltf OUT.gltf [--duration S]\n");
    return 2;
  }
  const std::string out = argv[1];
  si::test::StressDesc desc;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--duration") == 0) {
      desc.duration_seconds = std::strtof(argv[i + 1], nullptr);
    } else {
      std::fprintf(stderr, "write_stress_gltf: unknown option '%s'\n", argv[i]);
      return 2;
    }
  }
  const si::Character c = si::test::makeStressCharacter(desc);
  const si::Skeleton& sk = c.skeleton;
  const si::SkinnedMesh& m = c.mesh;
  Writer w;
  const size_t nv = m.vertexCount(), nj = sk.jointCount();

  // One primitive per sub-mesh, each with its own vertices (as exporters write parts).
  std::string primitives;
  for (size_t s = 0; s < m.sub_meshes.size(); ++s) {
    const si::IndexRange& r = m.sub_meshes[s].lods[0];
    std::vector<uint32_t> remap(nv, UINT32_MAX), indices;
    std::vector<glm::vec3> pos, nrm;
    std::vector<glm::u16vec4> jnt;
    std::vector<glm::vec4> wgt;
    for (uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i) {
      const uint32_t v = m.indices[i];
      if (remap[v] == UINT32_MAX) {
        remap[v] = uint32_t(pos.size());
        pos.push_back(m.positions[v]);
        nrm.push_back(m.normals[v]);
        jnt.push_back(m.joints[v]);
        wgt.push_back(m.weights[v]);
      }
      indices.push_back(remap[v]);
    }
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : pos) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const std::string bounds = ",\"min\":[" + num(lo.x) + "," + num(lo.y) + "," + num(lo.z) +
                               "],\"max\":[" + num(hi.x) + "," + num(hi.y) + "," + num(hi.z) + "]";
    const size_t n = pos.size();
    const int position = w.add(pos.data(), n * 12, "VEC3", 5126, n, bounds, 34962);
    const int normal = w.add(nrm.data(), n * 12, "VEC3", 5126, n, "", 34962);
    const int joints = w.add(jnt.data(), n * 8, "VEC4", 5123, n, "", 34962);
    const int weights = w.add(wgt.data(), n * 16, "VEC4", 5126, n, "", 34962);
    const int index = w.add(indices.data(), indices.size() * 4, "SCALAR", 5125, indices.size(), "", 34963);
    primitives += std::string(s ? "," : "") + "{\"attributes\":{\"POSITION\":" +
                  std::to_string(position) + ",\"NORMAL\":" + std::to_string(normal) +
                  ",\"JOINTS_0\":" + std::to_string(joints) + ",\"WEIGHTS_0\":" +
                  std::to_string(weights) + "},\"indices\":" + std::to_string(index) + "}";
  }
  const int ibm = w.add(sk.inverse_bind_matrices.data(), nj * 64, "MAT4", 5126, nj);

  // Nodes: joints 0..nj-1 (the skeleton's order), then the mesh node.
  std::string nodes;
  for (size_t j = 0; j < nj; ++j) {
    std::string children;
    for (size_t k = 0; k < nj; ++k)
      if (sk.parents[k] == int32_t(j)) children += std::string(children.empty() ? "" : ",") + std::to_string(k);
    const glm::vec3 t = sk.rest_pose[j].translation;
    nodes += std::string(j ? "," : "") + "{\"name\":\"" + sk.joint_names[j] + "\",\"translation\":[" +
             num(t.x) + "," + num(t.y) + "," + num(t.z) + "]" +
             (children.empty() ? "" : ",\"children\":[" + children + "]") + "}";
  }
  nodes += ",{\"name\":\"stress_mesh\",\"mesh\":0,\"skin\":0}";
  std::string skin_joints;
  for (size_t j = 0; j < nj; ++j) skin_joints += std::string(j ? "," : "") + std::to_string(j);

  // Animation: one sampler per channel; every track of the clip has the same key times.
  const si::Clip& clip = c.clips[0];
  const std::vector<float>& times = clip.joint_tracks[0].rotation.times_seconds;
  const int input = w.add(times.data(), times.size() * 4, "SCALAR", 5126, times.size(),
                          ",\"min\":[" + num(times.front()) + "],\"max\":[" + num(times.back()) + "]");
  std::string samplers, channels;
  int sampler = 0;
  for (size_t j = 0; j < nj; ++j) {
    const si::JointTracks& tr = clip.joint_tracks[j];
    struct Out { const char* path; const void* data; size_t size; const char* type; size_t count; };
    const Out outs[] = {
        {"translation", tr.translation.values.data(), tr.translation.values.size() * 12, "VEC3", tr.translation.values.size()},
        {"rotation", tr.rotation.values.data(), 0, "VEC4", tr.rotation.values.size()},
        {"scale", tr.scale.values.data(), tr.scale.values.size() * 12, "VEC3", tr.scale.values.size()}};
    for (const Out& o : outs) {
      int output;
      if (std::strcmp(o.path, "rotation") == 0) {  // glm stores w first; glTF wants x, y, z, w.
        std::vector<float> xyzw;
        for (const glm::quat& q : tr.rotation.values) xyzw.insert(xyzw.end(), {q.x, q.y, q.z, q.w});
        output = w.add(xyzw.data(), xyzw.size() * 4, o.type, 5126, o.count);
      } else {
        output = w.add(o.data, o.size, o.type, 5126, o.count);
      }
      samplers += std::string(sampler ? "," : "") + "{\"input\":" + std::to_string(input) +
                  ",\"output\":" + std::to_string(output) + ",\"interpolation\":\"LINEAR\"}";
      channels += std::string(sampler ? "," : "") + "{\"sampler\":" + std::to_string(sampler) +
                  ",\"target\":{\"node\":" + std::to_string(j) + ",\"path\":\"" + o.path + "\"}}";
      ++sampler;
    }
  }

  std::string bin_name = out.substr(out.find_last_of('/') + 1);
  bin_name = bin_name.substr(0, bin_name.rfind('.')) + ".bin";
  const std::string bin_path = out.substr(0, out.find_last_of('/') + 1) + bin_name;
  const std::string json =
      "{\"asset\":{\"version\":\"2.0\",\"generator\":\"SkinnedInstancing write_stress_gltf\"},"
      "\"scene\":0,\"scenes\":[{\"nodes\":[0," + std::to_string(nj) + "]}],"
      "\"nodes\":[" + nodes + "],\"meshes\":[{\"name\":\"stress\",\"primitives\":[" + primitives +
      "]}],\"skins\":[{\"inverseBindMatrices\":" + std::to_string(ibm) + ",\"skeleton\":0,"
      "\"joints\":[" + skin_joints + "]}],\"animations\":[{\"name\":\"" + clip.name +
      "\",\"samplers\":[" + samplers + "],\"channels\":[" + channels + "]}],"
      "\"buffers\":[{\"uri\":\"" + bin_name + "\",\"byteLength\":" + std::to_string(w.bin.size()) +
      "}],\"bufferViews\":[" + w.views + "],\"accessors\":[" + w.accessors + "]}";
  std::FILE* f = std::fopen(out.c_str(), "wb");
  std::FILE* b = std::fopen(bin_path.c_str(), "wb");
  if (f == nullptr || b == nullptr) {
    std::fprintf(stderr, "write_stress_gltf: cannot write '%s'\n", out.c_str());
    return 1;
  }
  const bool ok = std::fwrite(json.data(), 1, json.size(), f) == json.size() &&
                  std::fwrite(w.bin.data(), 1, w.bin.size(), b) == w.bin.size();
  const bool closed = std::fclose(f) == 0 && std::fclose(b) == 0;
  if (!ok || !closed) {
    std::fprintf(stderr, "write_stress_gltf: writing '%s' failed\n", out.c_str());
    return 1;
  }
  std::printf("%s: %zu vertices, %zu joints, %zu primitives, clip '%s' %.1f s\n", out.c_str(), nv,
              nj, m.sub_meshes.size(), clip.name.c_str(), double(clip.duration_seconds));
  return 0;
}
