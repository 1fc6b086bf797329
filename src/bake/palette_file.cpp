// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The palette file's writer and the file helpers of the offline tools (docs/palette-format.md);
// the reader is runtime code in si::core (src/core/palette_file.cpp).
#include "si/bake/palette_file.h"

#include <fstream>

#include "core/palette_file_format.h"
#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {

// ---- Writing ------------------------------------------------------------------------------
class Writer {
 public:
  explicit Writer(std::vector<uint8_t>* out) : out_(out) {}
  void u32(uint32_t v) { bytes(&v, 4); }
  void u64(uint64_t v) { bytes(&v, 8); }
  void f32(float v) { bytes(&v, 4); }
  void f64(double v) { bytes(&v, 8); }
  void bytes(const void* p, size_t n) {
    // The format is little-endian; so are the hosts this library supports (checked below).
    const uint8_t* b = static_cast<const uint8_t*>(p);
    out_->insert(out_->end(), b, b + n);
  }

 private:
  std::vector<uint8_t>* out_;
};

}  // namespace

Status savePalette(const BakedPalette& p, std::vector<uint8_t>* bytes) {
  if (bytes == nullptr) return {StatusCode::kInvalidArgument, "savePalette: bytes is null"};
  if (!detail::isLittleEndian())
    return {StatusCode::kUnsupported, "savePalette: big-endian hosts are not supported"};
  Status valid = p.validate();
  if (!valid.isOk()) return {StatusCode::kInvalidArgument, "savePalette: " + valid.message()};
  // What loadPalette() would refuse is not written.
  for (const BakedClip& c : p.clips) {
    bool long_name = c.name.size() > detail::kMaxPaletteNameLength;
    for (const AnimationMarker& m : c.markers) long_name |= m.name.size() > detail::kMaxPaletteNameLength;
    if (long_name)
      return {StatusCode::kInvalidArgument,
              strCat("savePalette: clip '", c.name.substr(0, 64), "' has a clip or marker name ",
                     "longer than ", detail::kMaxPaletteNameLength, " bytes")};
  }
  const PaletteLayout& l = p.layout;
  std::vector<uint8_t> out;
  Writer w(&out);
  w.bytes(detail::kPaletteMagic, 8);
  w.u32(kPaletteFileVersion);
  w.u32(static_cast<uint32_t>(p.format));
  w.u32(l.width);
  w.u32(l.height);
  w.u32(l.joint_count);
  w.u32(l.texels_per_joint);
  w.u32(l.joint_stride_texels);
  w.u32(l.border_frames);
  w.u32(l.morph_target_count);
  w.u32(static_cast<uint32_t>(p.skeleton_to_palette.size()));
  w.u32(static_cast<uint32_t>(p.clips.size()));
  w.f32(p.character_height);
  for (uint32_t j : p.palette_joints) w.u32(j);
  w.u32(static_cast<uint32_t>(p.joint_bounds.size()));  // Version 6: 0 or one per joint.
  for (const Aabb& b : p.joint_bounds)
    for (const glm::vec3& corner : {b.min, b.max})
      for (int i = 0; i < 3; ++i) w.f32(corner[i]);
  for (const BakedClip& c : p.clips) {
    w.u32(static_cast<uint32_t>(c.name.size()));
    w.bytes(c.name.data(), c.name.size());
    w.u32(static_cast<uint32_t>(c.loop_mode));
    w.f32(c.duration_seconds);
    w.f64(c.frame_interval_seconds);
    w.u32(c.frame_count);
    w.u32(static_cast<uint32_t>(c.frame_times_seconds.size()));
    for (double t : c.frame_times_seconds) w.f64(t);
    w.u32(static_cast<uint32_t>(c.interpolation));
    w.u32(static_cast<uint32_t>(c.interval_modes.size()));
    w.bytes(c.interval_modes.data(), c.interval_modes.size());
    w.u32(static_cast<uint32_t>(c.markers.size()));
    for (const AnimationMarker& m : c.markers) {
      w.f64(m.time_seconds);
      w.u32(static_cast<uint32_t>(m.name.size()));
      w.bytes(m.name.data(), m.name.size());
    }
    w.u32(static_cast<uint32_t>(c.root_motion.size()));
    for (const glm::vec3& m : c.root_motion)
      for (int i = 0; i < 3; ++i) w.f32(m[i]);
    for (int i = 0; i < 3; ++i) w.f32(c.bounds.min[i]);
    for (int i = 0; i < 3; ++i) w.f32(c.bounds.max[i]);
    for (int i = 0; i < 3; ++i) w.f32(c.bounding_sphere.center[i]);
    w.f32(c.bounding_sphere.radius);
  }
  w.u64(p.texel_bytes.size());
  w.bytes(p.texel_bytes.data(), p.texel_bytes.size());
  w.u32(crc32(out));
  *bytes = std::move(out);
  return Status::ok();
}

Status savePaletteFile(const BakedPalette& palette, const std::string& path) {
  std::vector<uint8_t> bytes;
  Status s = savePalette(palette, &bytes);
  if (!s.isOk()) return s;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return {StatusCode::kIo, strCat("cannot open '", path, "' for writing")};
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) return {StatusCode::kIo, strCat("cannot write '", path, "'")};
  return Status::ok();
}

Status loadPaletteFile(const std::string& path, BakedPalette* palette) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {StatusCode::kIo, strCat("cannot open '", path, "'")};
  const std::streamoff size = in.tellg();
  if (size < 0) return {StatusCode::kIo, strCat("cannot read '", path, "'")};
  if (uint64_t(size) > kMaxPaletteFileSize)
    return {StatusCode::kLimitExceeded, strCat("'", path, "' is larger than the palette limit")};
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), size);
  if (!in) return {StatusCode::kIo, strCat("cannot read '", path, "'")};
  return loadPalette(bytes, palette);
}

}  // namespace si
