// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The baker's measurements: the error report (the shell metric follows N. Frechette's Animation
// Compression Library, docs/error_metrics.md) and the culling boxes.
#include "bake/clip_measurement.h"
#include "bake/morph_measurement.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "bake/error_kernel.h"
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

}  // namespace

// Per stored joint, the 8 drawn vertices weighted to it that lie farthest from its bind
// position, and per morph target the 8 it moves farthest. Interpolation error grows with the
// lever arm and the delta, so these bound the search's error cheaply; the final report still
// measures every drawn vertex.
std::vector<uint32_t> searchVertices(const Character& character, const SkinnedMesh& mesh,
                                     const std::vector<uint32_t>& drawn) {
  const size_t nj = character.skeleton.jointCount();
  std::vector<glm::vec3> joint_pos(nj);  // Bind positions, once per joint.
  for (size_t j = 0; j < nj; ++j)
    joint_pos[j] = glm::vec3(glm::inverse(character.skeleton.inverse_bind_matrices[j])[3]);
  std::vector<std::vector<std::pair<float, uint32_t>>> per_joint(nj);
  for (uint32_t v : drawn)
    for (size_t k = 0; k < mesh.influenceCount(); ++k) {
      const Influence in = mesh.influence(v, k);
      if (in.weight <= 0.0f) continue;
      per_joint[in.joint].push_back({glm::length(mesh.positions[v] - joint_pos[in.joint]), v});
    }
  std::vector<uint32_t> out;
  for (auto& list : per_joint) {
    const size_t keep = std::min<size_t>(8, list.size());
    std::partial_sort(list.begin(), list.begin() + std::ptrdiff_t(keep), list.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    for (size_t i = 0; i < keep; ++i) out.push_back(list[i].second);
  }
  // Per morph target, the 8 drawn vertices it moves farthest: a weight's interpolation error
  // grows with the delta.
  std::vector<uint8_t> is_drawn(mesh.morph_targets.empty() ? 0 : mesh.vertexCount(), 0);
  for (uint32_t v : drawn)
    if (!is_drawn.empty()) is_drawn[v] = 1;
  for (const MorphTarget& t : mesh.morph_targets) {
    std::vector<std::pair<float, uint32_t>> list;
    for (size_t e = 0; e < t.vertices.size(); ++e)
      if (is_drawn[t.vertices[e]])
        list.push_back({glm::length(t.position_deltas[e]), t.vertices[e]});
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
  // The morph targets keep the entries of the subset's vertices, renumbered.
  std::vector<int64_t> index(mesh.morph_targets.empty() ? 0 : mesh.vertexCount(), -1);
  for (size_t i = 0; i < vertices.size() && !index.empty(); ++i) index[vertices[i]] = int64_t(i);
  for (const MorphTarget& t : mesh.morph_targets) {
    MorphTarget kept;
    kept.name = t.name;
    kept.default_weight = t.default_weight;
    std::vector<std::pair<uint32_t, size_t>> entries;  // (new vertex, entry).
    for (size_t e = 0; e < t.vertices.size(); ++e)
      if (index[t.vertices[e]] >= 0) entries.push_back({uint32_t(index[t.vertices[e]]), e});
    std::sort(entries.begin(), entries.end());
    for (const auto& [v, e] : entries) {
      kept.vertices.push_back(v);
      kept.position_deltas.push_back(t.position_deltas[e]);
      if (!t.normal_deltas.empty()) kept.normal_deltas.push_back(t.normal_deltas[e]);
    }
    subset.morph_targets.push_back(std::move(kept));
  }
  for (uint32_t v : vertices) {
    subset.positions.push_back(mesh.positions[v]);
    subset.normals.push_back(mesh.normals[v]);
    subset.joints.push_back(mesh.joints[v]);
    subset.weights.push_back(mesh.weights[v]);
    if (mesh.joints1.empty()) continue;
    subset.joints1.push_back(mesh.joints1[v]);
    subset.weights1.push_back(mesh.weights1[v]);
  }
  return subset;
}

SkinnedMesh storedWeightsMesh(const SkinnedMesh& mesh) {
  SkinnedMesh stored = mesh;
  for (size_t v = 0; v < stored.weights.size(); ++v) {
    glm::vec4& w = stored.weights[v];
    if (stored.weights1.empty()) {
      w = dequantizeWeights(quantizeWeights(w));
      continue;
    }
    glm::u16vec4 q, q1;
    quantizeWeights(w, stored.weights1[v], &q, &q1);
    w = dequantizeWeights(q);
    stored.weights1[v] = dequantizeWeights(q1);
  }
  return stored;
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
  // The P99 exactly, in bounded memory: the 99th percentile is the keep-th largest sample.
  const uint64_t rank = count == 0 ? 0 : std::min<uint64_t>(count - 1, uint64_t(std::ceil(0.99 * double(count))) - 1);
  const uint64_t keep = count - rank;
  LargestK largest(keep);
  const InfluenceGroups all(mesh, gpu_mesh, vertices);
  const InfluenceGroups few(mesh, gpu_mesh, short_list != nullptr ? *short_list : std::vector<uint32_t>{});
  const MorphedSlots all_morphed(mesh, gpu_mesh, all), few_morphed(mesh, gpu_mesh, few);
  const size_t targets = mesh.morph_targets.size();
  std::vector<float> emulated_weights(targets);
  std::vector<double> reference_weights(targets);
  std::vector<float> errors;
  uint64_t samples = 0;
  if (interval_errors != nullptr)
    interval_errors->assign(bc.frame_count > 1 ? bc.frame_count - 1 : 0, 0.0);
  for (const MeasureTime& mt : times) {
    const double t = mt.t;
    const FrameSample sample = sampleFrames(bc, t);
    Status s = emulateSkinningMatrices(p, clip_index, sample, emulated);
    if (s.isOk()) s = evaluateValidatedLocalPose(character.skeleton, clip, t, &pose);
    if (!s.isOk()) return s;
    const bool everyone = mt.all_vertices || short_list == nullptr;
    const InfluenceGroups& measured = everyone ? all : few;
    measured.errors(emulated, pose.skinning, &errors);
    if (targets > 0) {  // The morphed vertices again, with their targets at both weights.
      const PaletteLayout& l = p.layout;
      s = emulateMorphWeights(p, l.frameTexel(clip_index, sample.frame),
                              l.frameTexel(clip_index, sample.next_frame), sample.fraction,
                              sample.mode, emulated_weights);
      if (!s.isOk()) return s;
      evaluateValidatedMorphWeights(mesh, clip, t, reference_weights);
      (everyone ? all_morphed : few_morphed)
          .patchErrors(emulated, emulated_weights, pose.skinning, reference_weights, &errors);
    }
    // Sum and max in four lanes (the loop's latency, not its arithmetic, bounds it), then the
    // P99's candidates.
    double lane_sum[4] = {0.0, 0.0, 0.0, 0.0};
    float lane_max[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const size_t n4 = errors.size() / 4 * 4;
    for (size_t i = 0; i < n4; i += 4)
      for (int l = 0; l < 4; ++l) {
        lane_sum[l] += double(errors[i + size_t(l)]);
        lane_max[l] = std::max(lane_max[l], errors[i + size_t(l)]);
      }
    for (size_t i = n4; i < errors.size(); ++i) {
      lane_sum[0] += double(errors[i]);
      lane_max[0] = std::max(lane_max[0], errors[i]);
    }
    sum += (lane_sum[0] + lane_sum[1]) + (lane_sum[2] + lane_sum[3]);
    const float top = std::max(std::max(lane_max[0], lane_max[1]), std::max(lane_max[2], lane_max[3]));
    size_t worst = 0;
    while (worst < errors.size() && errors[worst] != top) ++worst;
    if (worst == errors.size()) worst = 0;  // NaN: the first, as before.
    for (float e : errors) largest.add(e);
    const double time_max = errors.empty() ? 0.0 : double(errors[worst]);
    const bool first = samples == 0 && !errors.empty();
    samples += errors.size();
    if (!errors.empty() && (time_max > r.max_error_units || first)) {
      const uint32_t v = measured.vertex(worst);
      r.max_error_units = time_max;
      r.max_error_time_seconds = t;
      r.max_error_vertex = v;
      size_t best = 0;
      for (size_t k = 1; k < mesh.influenceCount(); ++k)
        if (mesh.influence(v, k).weight > mesh.influence(v, best).weight) best = k;
      r.max_error_joint = mesh.influence(v, best).joint;
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
  for (uint32_t v : vertices)
    for (size_t k = 0; k < gpu_mesh.influenceCount(); ++k)
      if (gpu_mesh.influence(v, k).weight != 0.0f && gpu_mesh.influence(v, k).joint >= nj)
        return {StatusCode::kOutOfRange, "clipBounds: a vertex's joint is out of range"};
  const InfluenceGroups groups(gpu_mesh, gpu_mesh, vertices);
  const MorphedSlots morphed(gpu_mesh, gpu_mesh, groups);
  std::vector<float> weights(l.morph_target_count);
  if (gpu_mesh.morph_targets.size() != l.morph_target_count)
    return {StatusCode::kCountMismatch,
            "clipBounds: the mesh's morph targets are not the palette's"};
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
    groups.positions(matrices, &positions);  // Per slot, as emulateSkinning().
    if (!morphed.empty()) {
      const Status s = emulateMorphWeights(p, texel, texel, 0.0f, IntervalMode::kLinear, weights);
      if (!s.isOk()) return s;
      morphed.patchPositions(matrices, weights, &positions);
    }
    if (f >= 0 && f < n)
      for (const glm::vec3& q : positions) box.extend(q);
    // Interval i = f - 2 reads at most frames i - 1 to i + 2 = f, all in the ring now.
    const int64_t i = f - 2;
    if (!cubic || i < 0 || i + 1 >= n) continue;
    const auto mode = static_cast<IntervalMode>(bc.interval_modes[size_t(i)]);
    const int64_t first = mode == IntervalMode::kCubic || mode == IntervalMode::kCubicEndsNext
                              ? i - 1 : i;
    const int64_t last = mode == IntervalMode::kCubic || mode == IntervalMode::kCubicStartsHere
                             ? i + 2 : i + 1;
    for (size_t v = 0; v < groups.size(); ++v) {
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
