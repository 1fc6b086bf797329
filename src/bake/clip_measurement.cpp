// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The baker's measurements: the error report (the shell metric follows N. Frechette's Animation
// Compression Library, docs/error_metrics.md) and the culling boxes.
#include "bake/clip_measurement.h"

#include <algorithm>
#include <cmath>

#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si::detail {

namespace {

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

}  // namespace

// Per stored joint, the 8 drawn vertices weighted to it that lie farthest from its bind
// position. Interpolation error grows with the lever arm, so these bound the search's error
// cheaply; the final report still measures every drawn vertex.
std::vector<uint32_t> searchVertices(const Character& character, const SkinnedMesh& mesh,
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
  return out;
}

SkinnedMesh subsetMesh(const SkinnedMesh& mesh, const std::vector<uint32_t>& vertices) {
  SkinnedMesh subset;
  for (uint32_t v : vertices) {
    subset.positions.push_back(mesh.positions[v]);
    subset.normals.push_back(mesh.normals[v]);
    subset.joints.push_back(mesh.joints[v]);
    subset.weights.push_back(mesh.weights[v]);
  }
  return subset;
}

// `mesh` is the character's mesh or a subset of its vertices, `gpu_mesh` the same with the
// weights the vertex format stores; `vertices` index into both. The reference skins `mesh`,
// the emulation `gpu_mesh`, so the error includes the vertex format's quantization.
Status measureClip(const Character& character, const SkinnedMesh& mesh,
                   const SkinnedMesh& gpu_mesh, const BakedPalette& p,
                   uint32_t clip_index, const std::vector<uint32_t>& vertices,
                   double shell_distance, bool midpoints_only, ClipErrorReport* out) {
  const BakedClip& bc = p.clips[clip_index];
  const Clip& clip = character.clips[size_t(character.findClip(bc.name))];
  const size_t nv = mesh.vertexCount(), nj = character.skeleton.jointCount();
  std::vector<glm::mat4> emulated(nj);
  std::vector<glm::vec3> positions(nv);
  std::vector<glm::dvec3> reference(nv);
  std::vector<float> errors;
  ReferencePose pose;
  ClipErrorReport& r = *out;
  r.name = bc.name;
  r.sample_rate_hz = bc.sampleRateHz();
  r.frame_count = bc.frame_count;
  r.shell_distance_units = shell_distance;
  const double height = p.character_height > 0.0f ? p.character_height : 1.0;
  if (clip.root_motion.extract) {
    uint32_t root_joint = 0;
    Status s = rootMotionJoint(character.skeleton, clip, &root_joint);
    if (!s.isOk()) return s;
    r.root_motion_joint = character.skeleton.joint_names[root_joint];
  }
  double sum = 0.0;
  // Bind-pose position of each stored joint, for the shell metric.
  std::vector<glm::dvec3> joint_bind(nj);
  for (size_t j = 0; j < nj; ++j)
    joint_bind[j] = glm::dvec3(glm::inverse(glm::dmat4(character.skeleton.inverse_bind_matrices[j]))[3]);
  const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

  const std::vector<double> times = measurementTimes(bc, midpoints_only);
  for (double t : times) {
    const FrameSample sample = sampleFrames(bc, t);
    Status s = emulateSkinningMatrices(p, clip_index, sample, emulated);
    if (s.isOk()) s = emulateSkinning(gpu_mesh, emulated, positions, {});
    if (!s.isOk()) return s;
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
    if (clip.root_motion.extract) {  // The baked motion, lerped, against the reference's.
      GroundMotion exact;
      s = evaluateRootMotion(character.skeleton, clip, t, &exact);
      if (!s.isOk()) return s;
      const GroundMotion baked = sampleRootMotion(bc, sample);
      const double e = glm::length(baked.translation - exact.translation) +
                       std::fabs(wrapAngle(baked.yaw - exact.yaw)) * height;
      r.root_motion_max_error_units = std::max(r.root_motion_max_error_units, e);
    }
    for (uint32_t j : p.palette_joints)
      for (const glm::dvec3& axis : axes) {
        const glm::dvec4 vp(joint_bind[j] + axis * shell_distance, 1.0);
        const glm::dvec3 ref(pose.skinning[j] * vp);
        const glm::dvec3 emu(glm::dmat4(emulated[j]) * vp);
        r.shell_max_error_units = std::max(r.shell_max_error_units, glm::length(ref - emu));
      }
  }
  if (!errors.empty()) {
    r.samples = errors.size();
    r.mean_error_units = sum / double(errors.size());
    const size_t k = std::min(errors.size() - 1, size_t(std::ceil(0.99 * errors.size())) - 1);
    std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(k), errors.end());
    r.p99_error_units = errors[k];
    r.max_error_ratio = r.max_error_units / height;
    r.p99_error_ratio = r.p99_error_units / height;
    r.mean_error_ratio = r.mean_error_units / height;
  }
  r.root_motion_max_error_ratio = r.root_motion_max_error_units / height;
  return Status::ok();
}

Status clipBounds(const BakedPalette& p, uint32_t clip_index, const SkinnedMesh& gpu_mesh,
                  const std::vector<uint32_t>& vertices, Aabb* out) {
  const BakedClip& bc = p.clips[clip_index];
  const PaletteLayout& l = p.layout;
  const int64_t n = bc.frame_count, border = l.border_frames;
  const bool cubic = bc.interpolation == FrameInterpolation::kCubic;
  const size_t nj = p.skeleton_to_palette.size();
  // Positions of the last four frames (border frames included): frame f in ring[(f + 4) % 4].
  std::vector<glm::vec3> ring[4];
  const auto at = [&](int64_t f) -> const std::vector<glm::vec3>& { return ring[(f + 4) % 4]; };
  std::vector<glm::mat4> matrices(nj);
  Aabb box;
  for (int64_t f = -border; f < n + border; ++f) {
    const uint32_t texel = l.frameTexel(clip_index, f);
    for (size_t j = 0; j < nj; ++j) {
      const int32_t slot = p.skeleton_to_palette[j];
      matrices[j] = slot < 0 ? glm::mat4(1.0f)
                             : emulateFrameMatrix(p, texel, texel, 0.0f, uint32_t(slot));
    }
    std::vector<glm::vec3>& positions = ring[(f + 4) % 4];
    positions.resize(gpu_mesh.vertexCount());
    Status s = emulateSkinning(gpu_mesh, matrices, positions, {});
    if (!s.isOk()) return s;
    if (f >= 0 && f < n)
      for (uint32_t v : vertices) box.extend(positions[v]);
    // Interval i = f - 2 reads at most frames i - 1 to i + 2 = f, all in the ring now.
    const int64_t i = f - 2;
    if (!cubic || i < 0 || i + 1 >= n) continue;
    const auto mode = static_cast<IntervalMode>(bc.interval_modes[size_t(i)]);
    const int64_t first = mode == IntervalMode::kCubic || mode == IntervalMode::kCubicEndsNext
                              ? i - 1 : i;
    const int64_t last = mode == IntervalMode::kCubic || mode == IntervalMode::kCubicStartsHere
                             ? i + 2 : i + 1;
    for (uint32_t v : vertices) {
      Aabb local;
      for (int64_t k = first; k <= last; ++k) local.extend(at(k)[v]);
      const glm::vec3 widen = 0.125f * (local.max - local.min);
      box.extend(local.min - widen);
      box.extend(local.max + widen);
    }
  }
  *out = box;
  return Status::ok();
}

}  // namespace si::detail
