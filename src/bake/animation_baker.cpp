// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The AnimationBaker: clips to palette texels, with an error report measured by emulating the
// shader against the double-precision reference. Technique: B. Dudash, "Skinned Instancing",
// NVIDIA whitepaper (2007), and GPU Gems 3 ch. 2; the shell error metric follows N. Frechette's
// Animation Compression Library (docs/error_metrics.md).
#include "si/bake/animation_baker.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "bake/border_frames.h"
#include "bake/clip_measurement.h"
#include "core/str_cat.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si {
using detail::strCat;

namespace {

// A skinning matrix as rotation, translation and uniform scale, when it is one.
struct Rigid {
  glm::dquat rotation;
  glm::dvec3 translation;
  double scale = 1.0;
};

// Relative tolerance for "uniform and orthogonal" when checking a joint for the rigid format.
constexpr double kRigidTolerance = 1e-4;

bool decomposeRigid(const glm::dmat4& m, Rigid* out) {
  const glm::dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
  const double s0 = glm::length(c0), s1 = glm::length(c1), s2 = glm::length(c2);
  const double s = (s0 + s1 + s2) / 3.0;
  out->translation = glm::dvec3(m[3]);
  if (s < 1e-12) {  // Zero scale: representable, rotation irrelevant.
    out->rotation = glm::dquat(1, 0, 0, 0);
    out->scale = 0.0;
    return true;
  }
  const double tol = kRigidTolerance * s;
  if (std::fabs(s0 - s) > tol || std::fabs(s1 - s) > tol || std::fabs(s2 - s) > tol) return false;
  if (std::fabs(glm::dot(c0, c1)) > tol * s || std::fabs(glm::dot(c1, c2)) > tol * s ||
      std::fabs(glm::dot(c0, c2)) > tol * s)
    return false;
  if (glm::dot(glm::cross(c0, c1), c2) <= 0.0) return false;  // Mirrored.
  glm::dquat q = glm::quat_cast(glm::dmat3(c0 / s, c1 / s, c2 / s));
  q = safeNormalize(q);
  if (q.w < 0.0) q = -q;
  out->rotation = q;
  out->scale = s;
  return true;
}

void storeTexel(BakedPalette* p, uint32_t index, const glm::dvec4& v) {
  if (p->format == PaletteFormat::kMatrix3x4F16) {
    uint16_t h[4];
    for (int c = 0; c < 4; ++c) h[c] = floatToHalf(static_cast<float>(v[c]));
    std::memcpy(p->texel_bytes.data() + size_t(index) * 8, h, 8);
  } else {
    const float f[4] = {float(v.x), float(v.y), float(v.z), float(v.w)};
    std::memcpy(p->texel_bytes.data() + size_t(index) * 16, f, 16);
  }
}

// Bakes the planned clips into `out` (texels, clip table, joint maps; no bounds yet).
Status bakeTexels(const Character& character, const BakeDesc& d, const PalettePlan& plan,
                  BakedPalette* out) {
  BakedPalette p;
  p.format = d.format;
  p.layout = plan.layout;
  p.palette_joints = plan.palette_joints;
  p.skeleton_to_palette.assign(character.skeleton.jointCount(), -1);
  for (size_t s = 0; s < p.palette_joints.size(); ++s)
    p.skeleton_to_palette[p.palette_joints[s]] = static_cast<int32_t>(s);
  p.texel_bytes.assign(size_t(p.layout.textureTexelCount()) * bytesPerTexel(d.format), 0);
  p.character_height = character.height();

  ReferencePose pose;
  GroundMotion motion;
  for (size_t c = 0; c < plan.clip_indices.size(); ++c) {
    const Clip& clip = character.clips[plan.clip_indices[c]];
    BakedClip bc;
    bc.name = clip.name;
    bc.loop_mode = resolveLoopMode(clip.loop_mode);
    bc.markers = clip.markers;
    bc.duration_seconds = clip.duration_seconds;
    bc.frame_count = plan.frames[c].frame_count;
    bc.frame_interval_seconds = plan.frames[c].frame_interval_seconds;
    bc.first_texel = p.layout.clip_first_texel[c];
    bc.frame_times_seconds = plan.frames[c].frame_times_seconds;
    const std::vector<uint8_t>& before_step = plan.frames[c].before_step;
    for (uint32_t f = 0; f < bc.frame_count; ++f) {
      // The last frame lies exactly on the clip's end; a frame before a STEP key holds the
      // pose an instant before it (the largest double below the key time).
      double t = f + 1 == bc.frame_count && f > 0 ? double(clip.duration_seconds)
                                                  : f * bc.frame_interval_seconds;
      if (!bc.frame_times_seconds.empty()) {
        t = bc.frame_times_seconds[f];
        if (before_step[f]) t = std::nextafter(t, 0.0);
      }
      Status s = evaluateLocalPose(character.skeleton, clip, t, &pose);
      if (s.isOk() && clip.root_motion.extract)
        s = evaluateRootMotion(character.skeleton, clip, t, &motion);
      if (!s.isOk()) return s;
      if (clip.root_motion.extract) {  // Yaw unwrapped from the previous frame's.
        const double previous = f == 0 ? 0.0 : double(bc.root_motion.back().z);
        const double yaw = f == 0 ? 0.0 : previous + wrapAngle(motion.yaw - previous);
        bc.root_motion.push_back(f == 0 ? glm::vec3(0.0f)
                                        : glm::vec3(glm::dvec3(motion.translation, yaw)));
      }
      for (uint32_t slot = 0; slot < p.palette_joints.size(); ++slot) {
        const uint32_t joint = p.palette_joints[slot];
        const glm::dmat4& m = pose.skinning[joint];
        if (d.format == PaletteFormat::kQuatTranslationF32) {
          Rigid r;
          if (!decomposeRigid(m, &r))
            return {StatusCode::kUnsupported,
                    strCat("bake: clip '", clip.name, "': joint ", joint, " '",
                           character.skeleton.joint_names[joint], "' has non-uniform or negative "
                           "scale at t=", t, " s; quat_translation_f32 cannot represent it (use "
                           "a matrix format)")};
          storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, 0),
                     glm::dvec4(r.rotation.x, r.rotation.y, r.rotation.z, r.rotation.w));
          storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, 1),
                     glm::dvec4(r.translation, r.scale));
        } else {
          for (uint32_t row = 0; row < 3; ++row)
            storeTexel(&p, p.layout.texelIndex(uint32_t(c), f, slot, row),
                       glm::dvec4(m[0][row], m[1][row], m[2][row], m[3][row]));
        }
      }
    }
    p.clips.push_back(std::move(bc));
    detail::finishClipFrames(&p, uint32_t(c), plan.interpolations[c], plan.frames[c].breaks);
  }
  *out = std::move(p);
  return Status::ok();
}

// Candidate rates for the automatic mode, lowest first.
const double kCandidateRates[] = {5, 10, 15, 20, 24, 30, 40, 48, 60, 80, 96, 120, 160, 240};

// What the automatic rate search of every clip shares.
struct RateSearch {
  const Character& character;
  const BakeDesc& desc;  // Resolved.
  const SkinnedMesh& gpu_mesh;
  const std::vector<uint32_t>& vertices;
  double shell;
  // The same searchVertices() of the mesh and of gpu_mesh (chosen once, on the mesh).
  SkinnedMesh search_mesh, search_gpu_mesh;
  std::vector<uint32_t> search_vertices;     // Every vertex of search_mesh.
  std::vector<double> candidates;            // Rates tried, lowest first.
};

// Max error of `clip` alone baked at `rate` with `interpolation`: on the search subset at
// interval midpoints (cheap), or on every drawn vertex at every measurement time (exact).
Status trialError(const RateSearch& rs, const Clip& clip, FrameInterpolation interpolation,
                  double rate, bool full, double* error) {
  BakeDesc one = rs.desc;
  one.clip_names = {clip.name};
  one.rate_mode = RateMode::kFixed;
  one.sample_rate_hz = static_cast<float>(rate);
  const FrameInterpolation interpolations[] = {interpolation};
  PalettePlan plan;
  BakedPalette trial;
  ClipErrorReport m;
  Status st = planPalette(rs.character, one, &plan, {}, interpolations);
  if (st.isOk()) st = bakeTexels(rs.character, one, plan, &trial);
  if (st.isOk())
    st = full ? detail::measureClip(rs.character, rs.character.mesh, rs.gpu_mesh, trial, 0,
                                    rs.vertices, rs.shell, false, &m)
              : detail::measureClip(rs.character, rs.search_mesh, rs.search_gpu_mesh, trial, 0,
                                    rs.search_vertices, rs.shell, true, &m);
  *error = m.max_error_units;
  return st;
}

// The lowest candidate rate whose max error meets the tolerance (or the highest), and the max
// error on every drawn vertex at that rate (`full_error`, may be null).
Status searchRate(const RateSearch& rs, const Clip& clip, FrameInterpolation interpolation,
                  double* rate, double* full_error = nullptr) {
  std::vector<double> candidates = rs.candidates;
  // A cubic clip whose corner keys lie on a grid: the multiples of its rate, so that frames
  // land on the corners (between them the curve is smooth and the spline converges fast).
  const double key_rate = interpolation == FrameInterpolation::kCubic ? cornerKeyRate(clip) : 0.0;
  if (key_rate > 0.0 && key_rate <= rs.desc.max_sample_rate_hz) {
    candidates.clear();
    for (double m = 1.0; m * key_rate <= rs.desc.max_sample_rate_hz * (1.0 + 1e-9); m += 1.0)
      candidates.push_back(m * key_rate);
  }
  const double height = rs.character.height() > 0.0f ? rs.character.height() : 1.0;
  const double tolerance = rs.desc.error_tolerance_ratio * height;
  // A format whose precision floor is above the tolerance (half floats) cannot meet it at any
  // rate: then aim for 1.1 x the error at the highest rate instead of climbing to it.
  double floor_error = 0.0, full_floor_error = 0.0;
  Status s = trialError(rs, clip, interpolation, candidates.back(), false, &floor_error);
  if (s.isOk() && floor_error > tolerance)
    s = trialError(rs, clip, interpolation, candidates.back(), true, &full_floor_error);
  if (!s.isOk()) return s;
  const double target = std::max(tolerance, 1.1 * floor_error);
  const double full_target = std::max(tolerance, 1.1 * full_floor_error);
  // Binary search on the subset for the lowest candidate meeting the target (error falls as
  // the rate rises), then confirm on the whole mesh, stepping up until it holds.
  size_t lo = 0, hi = candidates.size() - 1;
  while (lo < hi) {
    const size_t mid = (lo + hi) / 2;
    double error = 0.0;
    s = trialError(rs, clip, interpolation, candidates[mid], false, &error);
    if (!s.isOk()) return s;
    if (error <= target) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  bool confirmed = false;  // The last full measurement is of candidates[lo] and met the target.
  double error = 0.0;
  for (; lo + 1 < candidates.size(); ++lo) {
    s = trialError(rs, clip, interpolation, candidates[lo], true, &error);
    if (!s.isOk()) return s;
    confirmed = error <= full_target;
    if (confirmed) break;
  }
  if (full_error != nullptr && !confirmed) {  // The highest candidate, not measured in full yet.
    error = full_floor_error;
    if (!(floor_error > tolerance))
      s = trialError(rs, clip, interpolation, candidates[lo], true, &error);
    if (!s.isOk()) return s;
  }
  if (full_error != nullptr) *full_error = error;
  *rate = candidates[lo];
  return Status::ok();
}

}  // namespace

Status bakePalette(const Character& character, const BakeDesc& in_desc, BakedPalette* palette,
                   BakeReport* report) {
  if (palette == nullptr) return {StatusCode::kInvalidArgument, "bakePalette: palette is null"};
  Status s = character.validate();
  if (!s.isOk()) return s;
  const BakeDesc d = resolveDefaults(in_desc);
  PalettePlan plan;
  s = planPalette(character, d, &plan);
  if (!s.isOk()) return s;
  const double height = character.height() > 0.0f ? character.height() : 1.0;
  const double shell = d.shell_distance_ratio * height;
  const std::vector<uint32_t> vertices = drawnVertices(character.mesh);
  // Measure what the GPU draws: the vertex format stores weights as unorm16 (si::gl).
  SkinnedMesh gpu_mesh = character.mesh;
  for (glm::vec4& w : gpu_mesh.weights) w = dequantizeWeights(quantizeWeights(w));

  const uint32_t clip_count = static_cast<uint32_t>(plan.clip_indices.size());
  // Automatic rates: the search takes about 60 % of the time, the final measurement the rest.
  const double search_share = d.rate_mode == RateMode::kAutomatic ? 0.6 : 0.0;
  const auto progress = [&](const char* stage, uint32_t clip, double fraction) {
    if (d.progress) d.progress(BakeProgress{fraction, stage, clip, clip_count});
  };
  std::vector<double> rates(plan.clip_indices.size(), double(d.sample_rate_hz));
  std::vector<FrameInterpolation> interpolations = plan.interpolations;
  if (d.rate_mode == RateMode::kAutomatic) {
    const std::vector<uint32_t> picked =
        detail::searchVertices(character, character.mesh, vertices);
    RateSearch search{character, d, gpu_mesh, vertices, shell,
                      detail::subsetMesh(character.mesh, picked),
                      detail::subsetMesh(gpu_mesh, picked), {}, {}};
    search.search_vertices.resize(search.search_mesh.vertexCount());
    for (size_t i = 0; i < search.search_vertices.size(); ++i) search.search_vertices[i] = uint32_t(i);
    for (double r : kCandidateRates)
      if (r <= d.max_sample_rate_hz) search.candidates.push_back(r);
    if (search.candidates.empty() || search.candidates.back() < d.max_sample_rate_hz)
      search.candidates.push_back(d.max_sample_rate_hz);
    for (size_t c = 0; c < rates.size(); ++c) {
      progress("choosing rates", uint32_t(c), search_share * double(c) / clip_count);
      const Clip& clip = character.clips[plan.clip_indices[c]];
      if (d.interpolation == InterpolationChoice::kSmaller) {
        // Both, then the one with fewer frames (linear on a tie: half the reads).
        // One that meets the tolerance beats one that does not; then fewer frames, then the
        // smaller error.
        double linear = 0.0, cubic = 0.0, linear_error = 0.0, cubic_error = 0.0;
        s = searchRate(search, clip, FrameInterpolation::kLinear, &linear, &linear_error);
        if (s.isOk())
          s = searchRate(search, clip, FrameInterpolation::kCubic, &cubic, &cubic_error);
        if (!s.isOk()) return s;
        const double tolerance = d.error_tolerance_ratio * height;
        const uint32_t linear_frames = planClipFrames(clip, linear).frame_count;
        const uint32_t cubic_frames = planClipFrames(clip, cubic, true).frame_count;
        const bool linear_met = linear_error <= tolerance, cubic_met = cubic_error <= tolerance;
        const bool pick_cubic =
            linear_met != cubic_met ? cubic_met
            : cubic_frames != linear_frames ? cubic_frames < linear_frames
                                            : cubic_error < linear_error;
        interpolations[c] = pick_cubic ? FrameInterpolation::kCubic : FrameInterpolation::kLinear;
        rates[c] = pick_cubic ? cubic : linear;
      } else {
        s = searchRate(search, clip, interpolations[c], &rates[c]);
        if (!s.isOk()) return s;
      }
    }
    s = planPalette(character, d, &plan, rates, interpolations);
    if (!s.isOk()) return s;
  }

  progress("baking", 0, search_share);
  BakedPalette baked;
  s = bakeTexels(character, d, plan, &baked);
  if (!s.isOk()) return s;

  BakeReport rep;
  const bool measure = report != nullptr || d.rate_mode == RateMode::kAutomatic;
  for (uint32_t c = 0; c < baked.clips.size(); ++c) {
    progress("measuring", c, search_share + (1.0 - search_share) * double(c) / clip_count);
    ClipErrorReport m;
    if (measure) s = detail::measureClip(character, character.mesh, gpu_mesh, baked, c, vertices,
                                         shell, false, &m);
    Aabb bounds;
    if (s.isOk()) s = detail::clipBounds(baked, c, gpu_mesh, vertices, &bounds);
    if (!s.isOk()) return s;
    // Matrix formats stay within clipBounds() up to float rounding; the rotation format's
    // normalization can bulge, so pad by 1 % of the height.
    const float pad = static_cast<float>(
        height * (d.format == PaletteFormat::kQuatTranslationF32 ? 1e-2 : 1e-5));
    bounds.min -= glm::vec3(pad);
    bounds.max += glm::vec3(pad);
    BakedClip& bc = baked.clips[c];
    // The box's circumsphere contains the mesh; in double, so a mesh spanning most of the float
    // range is refused by name instead of leaving an infinite sphere in the palette.
    const glm::dvec3 lo(bounds.min), hi(bounds.max);
    const glm::dvec3 center = 0.5 * lo + 0.5 * hi;
    const double radius = 0.5 * glm::length(hi - lo) * (1.0 + 1e-6);
    const double float_max = 3.0e38;
    if (!(std::isfinite(radius) && radius < float_max && glm::all(glm::lessThan(glm::abs(lo),
          glm::dvec3(float_max))) && glm::all(glm::lessThan(glm::abs(hi), glm::dvec3(float_max)))))
      return {StatusCode::kOutOfRange,
              strCat("bake: clip ", c, " '", baked.clips[c].name,
                     "': the skinned mesh spans past what float bounds hold (box from ",
                     lo.x, ", ", lo.y, ", ", lo.z, " to ", hi.x, ", ", hi.y, ", ", hi.z, ")")};
    bc.bounds = bounds;
    bc.bounding_sphere.center = glm::clamp(glm::vec3(center), bounds.min, bounds.max);
    bc.bounding_sphere.radius = float(radius);
    if (measure) {
      m.interpolation = bc.interpolation;
      m.palette_bytes = (uint64_t(bc.frame_count) + 2 * baked.layout.border_frames) *
                        baked.layout.frame_stride_texels * bytesPerTexel(d.format);
      m.tolerance_met = m.max_error_units <= d.error_tolerance_ratio * height;
      rep.max_error_units = std::max(rep.max_error_units, m.max_error_units);
      rep.max_error_ratio = std::max(rep.max_error_ratio, m.max_error_ratio);
      rep.p99_error_units = std::max(rep.p99_error_units, m.p99_error_units);
      rep.clips.push_back(std::move(m));
    }
  }
  if (report != nullptr) {
    rep.palette_bytes = baked.layout.textureTexelCount() * bytesPerTexel(d.format);
    for (size_t j = 0; j < character.skeleton.jointCount(); ++j)
      if (baked.skeleton_to_palette[j] < 0)
        rep.joints_left_out.push_back(character.skeleton.joint_names[j]);
    std::vector<uint32_t> all_frames;
    for (size_t c = 0; c < character.clips.size(); ++c) {
      const auto it = std::find(plan.clip_indices.begin(), plan.clip_indices.end(), uint32_t(c));
      if (it == plan.clip_indices.end()) {
        rep.clips_left_out.push_back(character.clips[c].name);
        all_frames.push_back(
            planFrames(character.clips[c].duration_seconds, d.sample_rate_hz).frame_count);
      } else {
        all_frames.push_back(plan.frames[size_t(it - plan.clip_indices.begin())].frame_count);
      }
    }
    PaletteLayoutDesc full;
    full.joint_count = static_cast<uint32_t>(character.skeleton.jointCount());
    full.clip_frame_counts = all_frames;
    full.texels_per_joint = baked.layout.texels_per_joint;
    full.joint_stride_texels = baked.layout.joint_stride_texels;
    full.max_texture_size = 1u << 30;  // Hypothetical: only its size matters.
    PaletteLayout full_layout;
    if (computePaletteLayout(full, &full_layout).isOk()) {
      const uint64_t full_bytes = full_layout.used_texel_count * bytesPerTexel(d.format);
      const uint64_t used_bytes = baked.layout.used_texel_count * bytesPerTexel(d.format);
      rep.bytes_saved = full_bytes > used_bytes ? full_bytes - used_bytes : 0;
    }
    *report = std::move(rep);
  }
  *palette = std::move(baked);
  progress("measuring", clip_count ? clip_count - 1 : 0, 1.0);
  return Status::ok();
}

}  // namespace si
