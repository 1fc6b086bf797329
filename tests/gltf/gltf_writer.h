// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// A tiny glTF writer for tests: builds a .gltf JSON with one base64 data-URI buffer, for the
// cases the sample assets lack (STEP and CUBICSPLINE, JOINTS_1, u8/u16 components, sparse
// accessors, negative scale, several skins).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace si::test {

class GltfWriter {
 public:
  // Appends raw bytes (4-byte aligned) as a buffer view; returns its index.
  int view(const void* data, size_t size, int stride = 0) {
    while (blob_.size() % 4) blob_.push_back(0);
    const size_t offset = blob_.size();
    const uint8_t* p = static_cast<const uint8_t*>(data);
    blob_.insert(blob_.end(), p, p + size);
    std::ostringstream v;
    v << "{\"buffer\":0,\"byteOffset\":" << offset << ",\"byteLength\":" << size;
    if (stride) v << ",\"byteStride\":" << stride;
    v << "}";
    views_.push_back(v.str());
    return int(views_.size() - 1);
  }
  // An accessor over a new view; `extra` is appended JSON (e.g. ,"normalized":true).
  template <typename T>
  int accessor(const std::vector<T>& data, int component_type, const char* type, size_t count,
               const std::string& extra = "") {
    const int v = view(data.data(), data.size() * sizeof(T));
    return rawAccessor(v, component_type, type, count, extra);
  }
  int rawAccessor(int view_index, int component_type, const char* type, size_t count,
                  const std::string& extra = "") {
    std::ostringstream a;
    a << "{";
    if (view_index >= 0) a << "\"bufferView\":" << view_index << ",";
    a << "\"componentType\":" << component_type << ",\"type\":\"" << type << "\",\"count\":"
      << count << extra << "}";
    accessors_.push_back(a.str());
    return int(accessors_.size() - 1);
  }
  // Raw JSON arrays for the rest of the document.
  std::string nodes, meshes, skins, animations, materials, textures, images;

  // An image entry's JSON for `rgba` (width x height, 4 bytes a texel): an uncompressed PNG
  // (stored deflate blocks) as a data URI.
  static std::string pngImage(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba) {
    std::vector<uint8_t> raw;  // Filter byte 0 before each row.
    for (uint32_t y = 0; y < height; ++y) {
      raw.push_back(0);
      raw.insert(raw.end(), rgba.begin() + ptrdiff_t(y) * width * 4,
                 rgba.begin() + ptrdiff_t(y + 1) * width * 4);
    }
    std::vector<uint8_t> z = {0x78, 0x01};
    for (size_t at = 0; at < raw.size(); at += 65535) {  // Stored blocks; the last says so.
      const size_t n = std::min<size_t>(65535, raw.size() - at);
      z.push_back(at + n >= raw.size() ? 1 : 0);
      z.insert(z.end(), {uint8_t(n), uint8_t(n >> 8), uint8_t(~n), uint8_t(~n >> 8)});
      z.insert(z.end(), raw.begin() + ptrdiff_t(at), raw.begin() + ptrdiff_t(at + n));
    }
    uint32_t a = 1, b = 0;
    for (uint8_t c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    be32(&z, (b << 16) | a);
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<uint8_t> ihdr;
    be32(&ihdr, width);
    be32(&ihdr, height);
    ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8 bits, RGBA, deflate, no filter, no interlace.
    chunk(&png, "IHDR", ihdr);
    chunk(&png, "IDAT", z);
    chunk(&png, "IEND", {});
    return "{\"uri\":\"data:image/png;base64," + base64(png) + "\"}";
  }

  std::string json() const {
    std::ostringstream j;
    j << "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],";
    j << "\"nodes\":[" << nodes << "],\"meshes\":[" << meshes << "],\"skins\":[" << skins << "],";
    if (!animations.empty()) j << "\"animations\":[" << animations << "],";
    if (!materials.empty()) j << "\"materials\":[" << materials << "],";
    if (!textures.empty()) j << "\"textures\":[" << textures << "],";
    if (!images.empty()) j << "\"images\":[" << images << "],";
    j << "\"accessors\":[" << join(accessors_) << "],\"bufferViews\":[" << join(views_) << "],";
    j << "\"buffers\":[{\"byteLength\":" << blob_.size()
      << ",\"uri\":\"data:application/octet-stream;base64," << base64(blob_) << "\"}]}";
    return j.str();
  }

 private:
  static void be32(std::vector<uint8_t>* out, uint32_t v) {
    out->insert(out->end(), {uint8_t(v >> 24), uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)});
  }
  static void chunk(std::vector<uint8_t>* png, const char* type, const std::vector<uint8_t>& data) {
    be32(png, uint32_t(data.size()));
    std::vector<uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    uint32_t crc = 0xFFFFFFFFu;
    for (uint8_t c : body) {
      crc ^= c;
      for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    png->insert(png->end(), body.begin(), body.end());
    be32(png, ~crc);
  }
  static std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
    return s;
  }
  static std::string base64(const std::vector<uint8_t>& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
      const uint32_t b = (uint32_t(in[i]) << 16) | (i + 1 < in.size() ? uint32_t(in[i + 1]) << 8 : 0) |
                         (i + 2 < in.size() ? in[i + 2] : 0);
      out += t[(b >> 18) & 63];
      out += t[(b >> 12) & 63];
      out += i + 1 < in.size() ? t[(b >> 6) & 63] : '=';
      out += i + 2 < in.size() ? t[b & 63] : '=';
    }
    return out;
  }
  std::vector<uint8_t> blob_;
  std::vector<std::string> views_, accessors_;
};

}  // namespace si::test
