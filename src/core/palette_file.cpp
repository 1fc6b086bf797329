// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The palette file's bounds-checked reader (docs/palette-format.md): runtime code, no file IO
// (the host reads the bytes from its own file system; si::bake's loadPaletteFile does it for
// tools).
#include "si/core/palette_file.h"

#include <cstring>

#include "core/palette_file_format.h"
#include "core/str_cat.h"

namespace si {
using detail::strCat;

namespace {

// ---- Reading: every read checks the bytes left first ---------------------------------------
class Reader {
 public:
  explicit Reader(Span<const uint8_t> b) : data_(b.data()), size_(b.size()) {}
  bool u32(uint32_t* v) { return raw(v, 4); }
  bool u64(uint64_t* v) { return raw(v, 8); }
  bool f32(float* v) { return raw(v, 4); }
  bool f64(double* v) { return raw(v, 8); }
  bool raw(void* out, size_t n) {
    if (n > size_ - pos_) return false;
    if (n > 0) std::memcpy(out, data_ + pos_, n);
    pos_ += n;
    return true;
  }
  size_t left() const { return size_ - pos_; }
  size_t position() const { return pos_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

Status corrupt(const std::string& what) {
  return {StatusCode::kCorrupt, "palette file: " + what};
}

}  // namespace

uint32_t crc32(Span<const uint8_t> bytes) {
  static const auto table = [] {
    std::vector<uint32_t> t(256);
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (uint8_t b : bytes) c = table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

Status loadPalette(Span<const uint8_t> bytes, BakedPalette* palette) {
  if (palette == nullptr) return {StatusCode::kInvalidArgument, "loadPalette: palette is null"};
  if (!detail::isLittleEndian())
    return {StatusCode::kUnsupported, "loadPalette: big-endian hosts are not supported"};
  if (bytes.size() > kMaxPaletteFileSize)
    return {StatusCode::kLimitExceeded,
            strCat("palette file: ", bytes.size(), " bytes exceed the limit of ",
                   kMaxPaletteFileSize)};
  Reader r(bytes);
  char magic[8];
  if (!r.raw(magic, 8) || std::memcmp(magic, detail::kPaletteMagic, 8) != 0)
    return corrupt("not a palette file (bad magic)");
  uint32_t version, format, width, height, joint_count, texels_per_joint, stride,
      border_frames = 0, morph_targets = 0, skeleton_joints, clip_count;
  float height_units;
  if (!r.u32(&version)) return corrupt("truncated header");
  if (version < 1 || version > kPaletteFileVersion)
    return {StatusCode::kUnsupported, strCat("palette file: version ", version,
                                             " (this library reads versions 1 to ",
                                             kPaletteFileVersion, ")")};
  if (!r.u32(&format) || !r.u32(&width) || !r.u32(&height) || !r.u32(&joint_count) ||
      !r.u32(&texels_per_joint) || !r.u32(&stride) || (version >= 2 && !r.u32(&border_frames)) ||
      (version >= 5 && !r.u32(&morph_targets)) || !r.u32(&skeleton_joints) || !r.u32(&clip_count) ||
      !r.f32(&height_units))
    return corrupt("truncated header");
  if (border_frames > 1) return corrupt(strCat("border frames ", border_frames, " (0 or 1)"));
  if (morph_targets > kMaxMorphTargets)
    return corrupt(strCat("morph targets ", morph_targets, " (at most ", kMaxMorphTargets, ")"));
  // Compare the whole 32-bit value before narrowing it to the 8-bit enum.
  if (format != uint32_t(PaletteFormat::kMatrix3x4F32) &&
      format != uint32_t(PaletteFormat::kMatrix3x4F16) &&
      format != uint32_t(PaletteFormat::kQuatTranslationF32))
    return corrupt(strCat("unknown format ", format));
  const PaletteFormat f = static_cast<PaletteFormat>(format);
  if (width == 0 || width > detail::kMaxPaletteTextureSize || (width & (width - 1)) != 0 || height == 0 ||
      height > detail::kMaxPaletteTextureSize)
    return corrupt(strCat("texture size ", width, "x", height, " out of range"));
  if (texels_per_joint != texelsPerJoint(f) || stride < texels_per_joint || stride > 64)
    return corrupt("joint texel counts do not match the format");
  if (joint_count == 0 || skeleton_joints > 65535 || joint_count > skeleton_joints)
    return corrupt(strCat("joint counts ", joint_count, " of ", skeleton_joints, " out of range"));
  if (clip_count == 0 || clip_count > kMaxPaletteClips)
    return corrupt(strCat("clip count ", clip_count, " out of range"));

  BakedPalette p;
  p.format = f;
  p.character_height = height_units;
  if (uint64_t(joint_count) * 4 > r.left()) return corrupt("truncated joint table");
  p.palette_joints.resize(joint_count);
  p.skeleton_to_palette.assign(skeleton_joints, -1);
  for (uint32_t s = 0; s < joint_count; ++s) {
    uint32_t j = 0;
    r.u32(&j);  // Size checked above.
    if (j >= skeleton_joints || (s > 0 && j <= p.palette_joints[s - 1]))
      return corrupt(strCat("joint table entry ", s, " (", j, ") is out of order or range"));
    p.palette_joints[s] = j;
    p.skeleton_to_palette[j] = static_cast<int32_t>(s);
  }
  if (version >= 6) {  // The joints' bounds: none, or one box (6 floats) per palette joint.
    uint32_t bounds = 0;
    if (!r.u32(&bounds) || (bounds != 0 && bounds != joint_count) ||
        uint64_t(bounds) * 24 > r.left())
      return corrupt(
          strCat("joint bounds: ", bounds, " for ", joint_count, " joints, or truncated"));
    p.joint_bounds.resize(bounds);
    for (Aabb& b : p.joint_bounds)
      for (glm::vec3* corner : {&b.min, &b.max})
        for (int i = 0; i < 3; ++i) r.f32(&(*corner)[i]);  // Size checked above.
  }
  std::vector<uint32_t> frame_counts;
  for (uint32_t c = 0; c < clip_count; ++c) {
    BakedClip clip;
    uint32_t name_length, loop, times_count;
    if (!r.u32(&name_length)) return corrupt(strCat("clip ", c, ": truncated"));
    if (name_length > detail::kMaxPaletteNameLength || name_length > r.left())
      return corrupt(strCat("clip ", c, ": name length ", name_length, " out of range"));
    clip.name.resize(name_length);
    r.raw(clip.name.data(), name_length);
    if (!r.u32(&loop) || !r.f32(&clip.duration_seconds) || !r.f64(&clip.frame_interval_seconds) ||
        !r.u32(&clip.frame_count) || !r.u32(&times_count))
      return corrupt(strCat("clip ", c, ": truncated"));
    const auto where = [&] { return strCat("clip ", c, " '", clip.name, "': "); };
    // Only what reading needs here (the enum narrowing, sizes that bound allocations); every
    // consistency rule is BakedPalette::validate()'s, applied to the whole palette below.
    if (loop != uint32_t(LoopMode::kOnce) && loop != uint32_t(LoopMode::kLoop))
      return corrupt(where() + "unknown loop mode");
    clip.loop_mode = static_cast<LoopMode>(loop);
    if (clip.frame_count == 0 || clip.frame_count > kMaxClipFrames)
      return corrupt(where() + strCat("frame count ", clip.frame_count, " out of range"));
    if (uint64_t(times_count) * 8 > r.left()) return corrupt(where() + "truncated frame times");
    clip.frame_times_seconds.resize(times_count);
    for (double& t : clip.frame_times_seconds) r.f64(&t);  // Size checked above.
    if (version >= 2) {
      uint32_t interpolation, modes_count;
      if (!r.u32(&interpolation) || !r.u32(&modes_count))
        return corrupt(where() + "truncated interpolation");
      if (interpolation != uint32_t(FrameInterpolation::kLinear) &&
          interpolation != uint32_t(FrameInterpolation::kCubic))
        return corrupt(where() + strCat("unknown interpolation ", interpolation));
      clip.interpolation = static_cast<FrameInterpolation>(interpolation);
      if (modes_count > r.left()) return corrupt(where() + "truncated interval modes");
      clip.interval_modes.resize(modes_count);
      r.raw(clip.interval_modes.data(), modes_count);
    }
    if (version >= 3) {
      uint32_t markers = 0;
      // Each marker takes at least 13 bytes (time, name length, a name byte).
      if (!r.u32(&markers) || uint64_t(markers) * 13 > r.left())
        return corrupt(where() + "truncated markers");
      clip.markers.resize(markers);
      for (AnimationMarker& m : clip.markers) {
        uint32_t length = 0;
        if (!r.f64(&m.time_seconds) || !r.u32(&length) || length > detail::kMaxPaletteNameLength ||
            length > r.left())
          return corrupt(where() + "truncated marker or marker name too long");
        m.name.resize(length);
        r.raw(m.name.data(), length);
      }
    }
    if (version >= 4) {
      uint32_t samples = 0;
      if (!r.u32(&samples) || uint64_t(samples) * 12 > r.left())
        return corrupt(where() + "truncated root motion");
      clip.root_motion.resize(samples);
      for (glm::vec3& m : clip.root_motion)
        for (int i = 0; i < 3; ++i) r.f32(&m[i]);  // Size checked above.
    }
    float v[10];
    for (float& x : v)
      if (!r.f32(&x)) return corrupt(where() + "truncated bounds");
    clip.bounds.min = glm::vec3(v[0], v[1], v[2]);
    clip.bounds.max = glm::vec3(v[3], v[4], v[5]);
    clip.bounding_sphere.center = glm::vec3(v[6], v[7], v[8]);
    clip.bounding_sphere.radius = v[9];
    frame_counts.push_back(clip.frame_count);
    p.clips.push_back(std::move(clip));
  }
  // The layout follows from the header and clip table; the stored size must agree.
  PaletteLayoutDesc ld;
  ld.joint_count = joint_count;
  ld.clip_frame_counts = frame_counts;
  ld.texels_per_joint = texels_per_joint;
  ld.joint_stride_texels = stride;
  ld.max_texture_size = detail::kMaxPaletteTextureSize;
  ld.border_frames = border_frames;
  ld.morph_target_count = morph_targets;
  if (!computePaletteLayout(ld, &p.layout).isOk() || p.layout.width != width ||
      p.layout.height != height)
    return corrupt(strCat("texture size ", width, "x", height,
                          " does not match the clip table's layout"));
  for (size_t c = 0; c < p.clips.size(); ++c) p.clips[c].first_texel = p.layout.clip_first_texel[c];
  uint64_t data_size = 0;
  if (!r.u64(&data_size)) return corrupt("truncated texel data size");
  const uint64_t expected = p.layout.textureTexelCount() * bytesPerTexel(f);
  if (data_size != expected)
    return corrupt(strCat("texel data of ", data_size, " bytes, the layout needs ", expected));
  if (data_size + 4 > r.left()) return corrupt("truncated texel data");
  p.texel_bytes.resize(size_t(data_size));
  r.raw(p.texel_bytes.data(), size_t(data_size));
  const size_t checked = r.position();
  uint32_t stored_crc = 0;
  r.u32(&stored_crc);
  if (r.left() != 0) return corrupt(strCat(r.left(), " trailing bytes after the checksum"));
  if (crc32(Span<const uint8_t>(bytes.data(), checked)) != stored_crc)
    return corrupt("checksum mismatch");
  // A file with a valid checksum can still be inconsistent (written by another tool, or made
  // by an attacker): the palette must pass what every bake passes.
  Status s = p.validate();
  if (!s.isOk()) return corrupt(s.message());
  *palette = std::move(p);
  return Status::ok();
}

}  // namespace si
