// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The baker's measurements: the error report (the shell metric follows N. Frechette's Animation
// Compression Library, docs/error_metrics.md) and the culling boxes.
#include "bake/clip_measurement.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/validated_evaluation.h"
#include "si/core/reference_evaluator.h"
#include "si/core/root_motion.h"

namespace si::detail {

namespace {

// A time at which the shader's result is compared with the reference, and whether every
// vertex is measured there (else the short list).
struct MeasureTime {
  double t;
  bool all_vertices;
};

// Every frame interval's midpoint and the clip's end (on every vertex); unless `midpoints_only`,
// also fractions 0, 1/4 and 3/4 of each interval (on the short list, or every vertex without
// one).
std::vector<MeasureTime> measurementTimes(const BakedClip& clip, bool midpoints_only,
                                          bool short_list) {
  if (clip.frame_count <= 1) return {{0.0, true}};
  std::vector<double> frame_times = clip.frame_times_seconds;
  if (frame_times.empty()) {
    for (uint32_t f = 0; f < clip.frame_count; ++f)
      frame_times.push_back(f + 1 == clip.frame_count ? double(clip.duration_seconds)
                                                      : f * clip.frame_interval_seconds);
  }
  std::vector<MeasureTime> times;
  for (size_t i = 0; i + 1 < frame_times.size(); ++i) {
    const double a = frame_times[i], b = frame_times[i + 1];
    if (!(b > a)) continue;  // The zero-length span between a STEP key's two frames.
    if (midpoints_only) {
      times.push_back({a + 0.5 * (b - a), true});
    } else {
      for (double u : {0.0, 0.25, 0.5, 0.75}) times.push_back({a + u * (b - a), u == 0.5 || !short_list});
    }
  }
  if (!midpoints_only) times.push_back({double(clip.duration_seconds), true});
  return times;
}

// Per joint, as float rows of 3x4 matrices: the difference the shader leaves (emulated minus
// reference) and the reference. Small differences keep their precision in float.
struct JointRows {
  float diff[12];
  float ref[12];
};

JointRows jointRows(const glm::mat4& emulated, const glm::dmat4& reference) {
  JointRows r;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) {
      r.diff[row * 4 + col] = float(double(emulated[col][row]) - reference[col][row]);
      r.ref[row * 4 + col] = float(reference[col][row]);
    }
  return r;
}

// One measured vertex, gathered once: position, influences, the vertex format's weights and
// their difference from the source's (zero where both are zero: skipped, as both sides do).
struct MeasuredVertex {
  glm::vec3 p;
  uint16_t joint[4];
  float wq[4];
  float dw[4];
};

MeasuredVertex gatherVertex(const SkinnedMesh& mesh, const SkinnedMesh& gpu_mesh, uint32_t v) {
  MeasuredVertex m;
  m.p = mesh.positions[v];
  for (int k = 0; k < 4; ++k) {
    const float w = mesh.weights[v][k], wq = gpu_mesh.weights[v][k];
    const bool used = w != 0.0f || wq != 0.0f;
    m.joint[k] = used ? mesh.joints[v][k] : 0;
    m.wq[k] = used ? wq : 0.0f;
    m.dw[k] = used ? wq - w : 0.0f;
  }
  return m;
}

// The shader's position minus the reference's: sum over influences of (wq D + (wq - w) R)
// (p, 1), where wq is the vertex format's weight and w the source's.
float vertexError(const MeasuredVertex& m, const std::vector<JointRows>& rows) {
  float e[3] = {0.0f, 0.0f, 0.0f};
  for (int k = 0; k < 4; ++k) {
    const JointRows& r = rows[m.joint[k]];
    for (int row = 0; row < 3; ++row) {
      const float* d = r.diff + row * 4;
      const float* q = r.ref + row * 4;
      e[row] += m.wq[k] * (d[0] * m.p.x + d[1] * m.p.y + d[2] * m.p.z + d[3]) +
                m.dw[k] * (q[0] * m.p.x + q[1] * m.p.y + q[2] * m.p.z + q[3]);
    }
  }
  return std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
}

// The k-th largest of a stream, exactly, in memory for 2k values: candidates above the running
// threshold are kept and trimmed to the k largest whenever 2k have gathered.
class LargestK {
 public:
  explicit LargestK(uint64_t k) : k_(std::max<uint64_t>(k, 1)) {}
  void add(float e) {
    if (kept_ >= k_ && !(e > threshold_)) return;
    values_.push_back(e);
    ++kept_;
    if (values_.size() >= 2 * k_) trim();
  }
  // The k-th largest value added (the smallest value when fewer were added).
  float kth() {
    trim();
    return values_.empty() ? 0.0f : *std::min_element(values_.begin(), values_.end());
  }

 private:
  void trim() {
    if (values_.size() > k_) {
      std::nth_element(values_.begin(), values_.begin() + std::ptrdiff_t(k_ - 1), values_.end(),
                       std::greater<float>());
      values_.resize(k_);
    }
    if (values_.size() >= k_) threshold_ = *std::min_element(values_.begin(), values_.end());
  }
  uint64_t k_;
  uint64_t kept_ = 0;
  float threshold_ = 0.0f;
  std::vector<float> values_;
};

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
                   double shell_distance, bool midpoints_only, ClipErrorReport* out,
                   std::vector<double>* interval_errors, const std::vector<uint32_t>* short_list) {
  const BakedClip& bc = p.clips[clip_index];
  const Clip& clip = character.clips[size_t(character.findClip(bc.name))];
  const size_t nj = character.skeleton.jointCount();
  std::vector<glm::mat4> emulated(nj);
  std::vector<JointRows> rows(nj);
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

  const std::vector<MeasureTime> times =
      measurementTimes(bc, midpoints_only, short_list != nullptr);
  uint64_t count = 0;
  for (const MeasureTime& mt : times)
    count += mt.all_vertices || short_list == nullptr ? vertices.size() : short_list->size();
  // The P99 exactly, in bounded memory: the largest `keep` samples in a min-heap, where the
  // 99th percentile is the keep-th largest (1 % of the samples, not all of them).
  const uint64_t rank = count == 0 ? 0 : std::min<uint64_t>(count - 1, uint64_t(std::ceil(0.99 * double(count))) - 1);
  const uint64_t keep = count - rank;
  LargestK largest(keep);
  std::vector<MeasuredVertex> all, few;
  for (uint32_t v : vertices) all.push_back(gatherVertex(mesh, gpu_mesh, v));
  if (short_list != nullptr)
    for (uint32_t v : *short_list) few.push_back(gatherVertex(mesh, gpu_mesh, v));
  uint64_t samples = 0;
  if (interval_errors != nullptr)
    interval_errors->assign(bc.frame_count > 1 ? bc.frame_count - 1 : 0, 0.0);
  for (const MeasureTime& mt : times) {
    const double t = mt.t;
    const FrameSample sample = sampleFrames(bc, t);
    Status s = emulateSkinningMatrices(p, clip_index, sample, emulated);
    if (s.isOk()) s = evaluateValidatedLocalPose(character.skeleton, clip, t, &pose);
    if (!s.isOk()) return s;
    for (size_t j = 0; j < nj; ++j) rows[j] = jointRows(emulated[j], pose.skinning[j]);
    double time_max = 0.0;
    const bool every = mt.all_vertices || short_list == nullptr;
    const std::vector<MeasuredVertex>& measured = every ? all : few;
    for (size_t i = 0; i < measured.size(); ++i) {
      const uint32_t v = every ? vertices[i] : (*short_list)[i];
      const float ef = vertexError(measured[i], rows);
      const double e = ef;
      largest.add(ef);
      ++samples;
      sum += e;
      time_max = std::max(time_max, e);
      if (e > r.max_error_units || samples == 1) {
        r.max_error_units = e;
        r.max_error_time_seconds = t;
        r.max_error_vertex = v;
        int best = 0;
        for (int k = 1; k < 4; ++k)
          if (mesh.weights[v][k] > mesh.weights[v][best]) best = k;
        r.max_error_joint = mesh.joints[v][best];
      }
    }
    if (interval_errors != nullptr && !interval_errors->empty()) {
      double& slot = (*interval_errors)[std::min<size_t>(sample.frame, interval_errors->size() - 1)];
      slot = std::max(slot, time_max);
    }
    if (clip.root_motion.extract) {  // The baked motion, lerped, against the reference's.
      GroundMotion exact;
      s = evaluateValidatedRootMotion(character.skeleton, clip, t, &exact);
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
  if (samples > 0) {
    r.samples = samples;
    r.mean_error_units = sum / double(samples);
    r.p99_error_units = largest.kth();
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
    // As emulateSkinning(): blend the influences' matrices (zero weights skipped), transform.
    for (uint32_t v : vertices) {
      glm::mat4 m(0.0f);
      for (int k = 0; k < 4; ++k) {
        const float w = gpu_mesh.weights[v][k];
        if (w == 0.0f) continue;
        const uint16_t j = gpu_mesh.joints[v][k];
        if (j >= nj) return {StatusCode::kOutOfRange, "clipBounds: a vertex's joint is out of range"};
        m += matrices[j] * w;
      }
      positions[v] = glm::vec3(m * glm::vec4(gpu_mesh.positions[v], 1.0f));
    }
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
