// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The AnimationBaker: clips to palette texels, with an error report measured by emulating the
// shader against the double-precision reference. Technique: B. Dudash, "Skinned Instancing",
// NVIDIA whitepaper (2007), and GPU Gems 3 ch. 2; the shell error metric follows N. Frechette's
// Animation Compression Library (docs/error_metrics.md).
#include "si/bake/animation_baker.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/str_cat.h"
#include "si/core/reference_evaluator.h"

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

// Times at which the shader's result is compared with the reference: every frame interval at
// fractions 0, 1/4, 1/2, 3/4 (or only 1/2 for the rate search), and the clip's end.
std::vector<double> measurementTimes(const BakedClip& clip, bool midpoints_only) {
  if (clip.frame_count <= 1) return {0.0};
  std::vector<double> frame_times = clip.frame_times_seconds;
  if (frame_times.empty()) {
    for (uint32_t f = 0; f < clip.frame_count; ++f)
      frame_times.push_back(f + 1 == clip.frame_count ? double(clip.duration_seconds)
                                                      : f * clip.frame_interval_seconds);
  }
  std::vector<double> times;
  for (size_t i = 0; i + 1 < frame_times.size(); ++i) {
    const double a = frame_times[i], b = frame_times[i + 1];
    if (!(b > a)) continue;  // The zero-length span between a STEP key's two frames.
    if (midpoints_only) {
      times.push_back(a + 0.5 * (b - a));
    } else {
      for (double u : {0.0, 0.25, 0.5, 0.75}) times.push_back(a + u * (b - a));
    }
  }
  if (!midpoints_only) times.push_back(clip.duration_seconds);
  return times;
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
  for (size_t c = 0; c < plan.clip_indices.size(); ++c) {
    const Clip& clip = character.clips[plan.clip_indices[c]];
    BakedClip bc;
    bc.name = clip.name;
    bc.loop_mode = resolveLoopMode(clip.loop_mode);
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
      if (!s.isOk()) return s;
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
  }
  *out = std::move(p);
  return Status::ok();
}

// For the automatic rate search: per stored joint, the 8 drawn vertices weighted to it that lie
// farthest from its bind position, as a mesh of their own. Interpolation error grows with the
// lever arm, so these bound the search's error cheaply; the final report still measures every
// drawn vertex.
SkinnedMesh searchMesh(const Character& character, const SkinnedMesh& mesh,
                       const std::vector<uint32_t>& drawn) {
  const size_t nj = character.skeleton.jointCount();
  std::vector<std::vector<std::pair<float, uint32_t>>> per_joint(nj);
  for (uint32_t v : drawn)
    for (int k = 0; k < 4; ++k) {
      if (mesh.weights[v][k] <= 0.0f) continue;
      const uint16_t j = mesh.joints[v][k];
      const glm::vec3 joint_pos(glm::inverse(character.skeleton.inverse_bind_matrices[j])[3]);
      per_joint[j].push_back({glm::length(mesh.positions[v] - joint_pos), v});
    }
  std::vector<uint32_t> out;
  for (auto& list : per_joint) {
    const size_t keep = std::min<size_t>(8, list.size());
    std::partial_sort(list.begin(), list.begin() + std::ptrdiff_t(keep), list.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    for (size_t i = 0; i < keep; ++i) out.push_back(list[i].second);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  SkinnedMesh subset;
  for (uint32_t v : out) {
    subset.positions.push_back(mesh.positions[v]);
    subset.normals.push_back(mesh.normals[v]);
    subset.joints.push_back(mesh.joints[v]);
    subset.weights.push_back(mesh.weights[v]);
  }
  return subset;
}

struct Measurement {
  ClipErrorReport report;
  Aabb bounds;
};

// Emulates the shader at the clip's measurement times; compares with the reference when
// `with_error`; always accumulates bounds of the emulated positions.
// `mesh` is the character's mesh or a subset of its vertices, `gpu_mesh` the same with the
// weights the vertex format stores; `vertices` index into both. The reference skins `mesh`,
// the emulation `gpu_mesh`, so the error includes the vertex format's quantization.
Status measureClip(const Character& character, const SkinnedMesh& mesh,
                   const SkinnedMesh& gpu_mesh, const BakedPalette& p,
                   uint32_t clip_index, const std::vector<uint32_t>& vertices,
                   double shell_distance, bool with_error, bool midpoints_only,
                   Measurement* out) {
  const BakedClip& bc = p.clips[clip_index];
  const Clip& clip = character.clips[size_t(character.findClip(bc.name))];
  const size_t nv = mesh.vertexCount(), nj = character.skeleton.jointCount();
  std::vector<glm::mat4> emulated(nj);
  std::vector<glm::vec3> positions(nv);
  std::vector<glm::dvec3> reference(nv);
  std::vector<float> errors;
  ReferencePose pose;
  ClipErrorReport& r = out->report;
  r.name = bc.name;
  r.sample_rate_hz = bc.sampleRateHz();
  r.frame_count = bc.frame_count;
  r.shell_distance_units = shell_distance;
  double sum = 0.0;
  // Bind-pose position of each stored joint, for the shell metric.
  std::vector<glm::dvec3> joint_bind(nj);
  for (size_t j = 0; j < nj; ++j)
    joint_bind[j] = glm::dvec3(glm::inverse(glm::dmat4(character.skeleton.inverse_bind_matrices[j]))[3]);
  const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

  std::vector<double> times = measurementTimes(bc, midpoints_only && with_error);
  if (!with_error) {  // Bounds only: the frames themselves (the matrix lerp stays on chords).
    times = bc.frame_times_seconds;
    if (times.empty())
      for (uint32_t f = 0; f < bc.frame_count; ++f)
        times.push_back(std::min(double(bc.duration_seconds), f * bc.frame_interval_seconds));
  }
  for (double t : times) {
    const FrameSample sample = sampleFrames(bc, t);
    Status s = emulateSkinningMatrices(p, clip_index, sample, emulated);
    if (s.isOk()) s = emulateSkinning(gpu_mesh, emulated, positions, {});
    if (!s.isOk()) return s;
    for (uint32_t v : vertices) out->bounds.extend(positions[v]);
    if (!with_error) continue;
    s = evaluateLocalPose(character.skeleton, clip, t, &pose);
    if (s.isOk()) s = skinVertices(mesh, pose.skinning, reference, {}, {});
    if (!s.isOk()) return s;
    for (uint32_t v : vertices) {
      const double e = glm::length(glm::dvec3(positions[v]) - reference[v]);
      errors.push_back(static_cast<float>(e));
      sum += e;
      if (e > r.max_error_units || errors.size() == 1) {
        r.max_error_units = e;
        r.max_error_time_seconds = t;
        r.max_error_vertex = v;
        int best = 0;
        for (int k = 1; k < 4; ++k)
          if (mesh.weights[v][k] > mesh.weights[v][best]) best = k;
        r.max_error_joint = mesh.joints[v][best];
      }
    }
    for (uint32_t j : p.palette_joints)
      for (const glm::dvec3& axis : axes) {
        const glm::dvec4 vp(joint_bind[j] + axis * shell_distance, 1.0);
        const glm::dvec3 ref(pose.skinning[j] * vp);
        const glm::dvec3 emu(glm::dmat4(emulated[j]) * vp);
        r.shell_max_error_units = std::max(r.shell_max_error_units, glm::length(ref - emu));
      }
  }
  if (with_error && !errors.empty()) {
    r.samples = errors.size();
    r.mean_error_units = sum / double(errors.size());
    const size_t k = std::min(errors.size() - 1, size_t(std::ceil(0.99 * errors.size())) - 1);
    std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(k), errors.end());
    r.p99_error_units = errors[k];
    const double h = p.character_height > 0.0f ? p.character_height : 1.0;
    r.max_error_ratio = r.max_error_units / h;
    r.p99_error_ratio = r.p99_error_units / h;
    r.mean_error_ratio = r.mean_error_units / h;
  }
  return Status::ok();
}

// Candidate rates for the automatic mode, lowest first.
const double kCandidateRates[] = {5, 10, 15, 20, 24, 30, 40, 48, 60, 80, 96, 120, 160, 240};

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
  if (d.rate_mode == RateMode::kAutomatic) {
    const double tolerance = d.error_tolerance_ratio * height;
    const SkinnedMesh search_mesh = searchMesh(character, character.mesh, vertices);
    const SkinnedMesh search_gpu_mesh = searchMesh(character, gpu_mesh, vertices);
    std::vector<uint32_t> search_vertices(search_mesh.vertexCount());
    for (size_t i = 0; i < search_vertices.size(); ++i) search_vertices[i] = uint32_t(i);
    std::vector<double> candidates;
    for (double r : kCandidateRates)
      if (r <= d.max_sample_rate_hz) candidates.push_back(r);
    if (candidates.empty() || candidates.back() < d.max_sample_rate_hz)
      candidates.push_back(d.max_sample_rate_hz);
    for (size_t c = 0; c < rates.size(); ++c) {
      progress("choosing rates", uint32_t(c), search_share * double(c) / clip_count);
      // Max error of this clip alone baked at `rate`: on the search subset at interval
      // midpoints (cheap), or on every drawn vertex at every measurement time (exact).
      const auto clip_error = [&](double rate, bool full, double* error) {
        BakeDesc one = d;
        one.clip_names = {character.clips[plan.clip_indices[c]].name};
        one.rate_mode = RateMode::kFixed;
        one.sample_rate_hz = static_cast<float>(rate);
        PalettePlan one_plan;
        BakedPalette trial;
        Measurement m;
        Status st = planPalette(character, one, &one_plan);
        if (st.isOk()) st = bakeTexels(character, one, one_plan, &trial);
        if (st.isOk())
          st = full ? measureClip(character, character.mesh, gpu_mesh, trial, 0, vertices,
                                  shell, true, false, &m)
                    : measureClip(character, search_mesh, search_gpu_mesh, trial, 0,
                                  search_vertices, shell, true, true, &m);
        *error = m.report.max_error_units;
        return st;
      };
      // A format whose precision floor is above the tolerance (half floats) cannot meet it at
      // any rate: then aim for 1.1 x the error at the highest rate instead of climbing to it.
      double floor_error = 0.0, full_floor_error = 0.0;
      s = clip_error(candidates.back(), false, &floor_error);
      if (s.isOk() && floor_error > tolerance)
        s = clip_error(candidates.back(), true, &full_floor_error);
      if (!s.isOk()) return s;
      const double target = std::max(tolerance, 1.1 * floor_error);
      const double full_target = std::max(tolerance, 1.1 * full_floor_error);
      // Binary search on the subset for the lowest candidate meeting the target (error falls as
      // the rate rises), then confirm on the whole mesh, stepping up until it holds.
      size_t lo = 0, hi = candidates.size() - 1;
      while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        double error = 0.0;
        s = clip_error(candidates[mid], false, &error);
        if (!s.isOk()) return s;
        if (error <= target) {
          hi = mid;
        } else {
          lo = mid + 1;
        }
      }
      for (; lo + 1 < candidates.size(); ++lo) {
        double error = 0.0;
        s = clip_error(candidates[lo], true, &error);
        if (!s.isOk()) return s;
        if (error <= full_target) break;
      }
      rates[c] = candidates[lo];
    }
    s = planPalette(character, d, &plan, rates);
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
    Measurement m;
    s = measureClip(character, character.mesh, gpu_mesh, baked, c, vertices, shell, measure,
                    false, &m);
    if (!s.isOk()) return s;
    // Matrix formats interpolate on chords between frames, so the frames' box is conservative
    // up to float rounding; the rotation format's nlerp can bulge, so pad by 1 % of the height.
    const float pad = static_cast<float>(
        height * (d.format == PaletteFormat::kQuatTranslationF32 ? 1e-2 : 1e-5));
    m.bounds.min -= glm::vec3(pad);
    m.bounds.max += glm::vec3(pad);
    BakedClip& bc = baked.clips[c];
    // The box's circumsphere contains the mesh; in double, so a mesh spanning most of the float
    // range is refused by name instead of leaving an infinite sphere in the palette.
    const glm::dvec3 lo(m.bounds.min), hi(m.bounds.max);
    const glm::dvec3 center = 0.5 * lo + 0.5 * hi;
    const double radius = 0.5 * glm::length(hi - lo) * (1.0 + 1e-6);
    const double float_max = 3.0e38;
    if (!(std::isfinite(radius) && radius < float_max && glm::all(glm::lessThan(glm::abs(lo),
          glm::dvec3(float_max))) && glm::all(glm::lessThan(glm::abs(hi), glm::dvec3(float_max)))))
      return {StatusCode::kOutOfRange,
              strCat("bake: clip ", c, " '", baked.clips[c].name,
                     "': the skinned mesh spans past what float bounds hold (box from ",
                     lo.x, ", ", lo.y, ", ", lo.z, " to ", hi.x, ", ", hi.y, ", ", hi.z, ")")};
    bc.bounds = m.bounds;
    bc.bounding_sphere.center = glm::clamp(glm::vec3(center), m.bounds.min, m.bounds.max);
    bc.bounding_sphere.radius = float(radius);
    if (measure) {
      m.report.palette_bytes = uint64_t(bc.frame_count) * baked.layout.frame_stride_texels *
                               bytesPerTexel(d.format);
      m.report.tolerance_met = m.report.max_error_units <= d.error_tolerance_ratio * height;
      rep.max_error_units = std::max(rep.max_error_units, m.report.max_error_units);
      rep.max_error_ratio = std::max(rep.max_error_ratio, m.report.max_error_ratio);
      rep.p99_error_units = std::max(rep.p99_error_units, m.report.p99_error_units);
      rep.clips.push_back(std::move(m.report));
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
