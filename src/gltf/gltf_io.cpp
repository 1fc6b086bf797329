// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// tinygltf's callbacks: files only from the asset's folder, no path expansion, no writing;
// images decoded when asked for, a failed decode a warning; parsing bytes and reading files.
#include <cstring>
#include <fstream>

#include "gltf/gltf_convert.h"
#include "si/gltf/asset_path.h"

namespace si::detail {

namespace {

bool fileExists(const std::string& path, void* user) {
  const FsContext* fs = static_cast<const FsContext*>(user);
  if (fs->base_dir.empty()) return false;
  std::ifstream f(path, std::ios::binary);
  return bool(f);
}
std::string noExpansion(const std::string& path, void*) { return path; }
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
  const FsContext* fs = static_cast<const FsContext*>(user);
  // tinygltf joins the base folder and the (decoded) URI: the remainder must resolve inside it.
  const std::string prefix = fs->base_dir.empty() ? "" : fs->base_dir + "/";
  std::string resolved;
  if (fs->base_dir.empty() || path.compare(0, prefix.size(), prefix) != 0 ||
      !resolveAssetUri(fs->base_dir, path.substr(prefix.size()), &resolved).isOk()) {
    if (err) *err += "refused to read '" + path + "': outside the asset's folder\n";
    return false;
  }
  std::ifstream f(resolved, std::ios::binary | std::ios::ate);
  if (!f) {
    if (err) *err += "cannot read '" + resolved + "'\n";
    return false;
  }
  const std::streamoff size = f.tellg();
  if (size < 0 || uint64_t(size) > (uint64_t(1) << 31)) {
    if (err) *err += "'" + resolved + "' is too large\n";
    return false;
  }
  out->resize(size_t(size));
  f.seekg(0);
  f.read(reinterpret_cast<char*>(out->data()), size);
  return bool(f);
}
bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
               int req_w, int req_h, const unsigned char* bytes, int size, void* user) {
  const ImageContext* ctx = static_cast<const ImageContext*>(user);
  if (!ctx->load) return true;  // Images are optional.
  std::string e, w;
  if (!tinygltf::LoadImageData(image, index, &e, &w, req_w, req_h, bytes, size, nullptr)) {
    ctx->warnings->push_back(strCat("image ", index, " could not be decoded (", e,
                                    "): its materials keep their factor only"));
    image->image.clear();
  }
  (void)err;
  (void)warn;
  return true;
}

}  // namespace

void installCallbacks(tinygltf::TinyGLTF* loader, FsContext* fs, ImageContext* images) {
  loader->SetFsCallbacks({&fileExists, &noExpansion, &readWholeFile, &refuseWrite, fs});
  loader->SetImageLoader(&loadImage, images);
}

Status parseGltf(Span<const uint8_t> bytes, const std::string& base_dir, bool load_images,
                 std::vector<std::string>* warnings, tinygltf::Model* model) {
  if (bytes.size() > (size_t(1) << 31))
    return {StatusCode::kLimitExceeded, "glTF: the file is larger than 2 GiB"};
  tinygltf::TinyGLTF loader;
  FsContext fs{base_dir};
  ImageContext images{load_images, warnings};
  installCallbacks(&loader, &fs, &images);
  std::string err, warn;
  bool ok;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    ok = loader.LoadBinaryFromMemory(model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                     base_dir);
  } else {
    ok = loader.LoadASCIIFromString(model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                    unsigned(bytes.size()), base_dir);
  }
  if (!warn.empty()) warnings->push_back("tinygltf: " + warn);
  if (!ok) return corrupt("cannot parse: " + (err.empty() ? std::string("unknown error") : err));
  return Status::ok();
}

Status readGltfFile(const std::string& path, GltfFile* out) {
  std::vector<uint8_t>* bytes = &out->bytes;
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) return {StatusCode::kIo, strCat("glTF: cannot open '", path, "'")};
  const std::streamoff size = f.tellg();
  if (size < 0 || uint64_t(size) > (uint64_t(1) << 31))
    return {StatusCode::kIo, strCat("glTF: cannot read '", path, "'")};
  bytes->resize(static_cast<size_t>(size));
  f.seekg(0);
  f.read(reinterpret_cast<char*>(bytes->data()), size);
  if (!f) return {StatusCode::kIo, strCat("glTF: cannot read '", path, "'")};
  const size_t slash = path.find_last_of('/');
  out->dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return Status::ok();
}

}  // namespace si::detail
