// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What folding a vertex's influences to 4 costs: each folded vertex skinned with its 4 kept
// influences and with all of them, in double, over the poses the character's clips take.
#include <algorithm>
#include <cmath>

#include "gltf/gltf_convert.h"
#include "si/core/reference_evaluator.h"

namespace si::detail {

namespace {

// Where `influences` put bind-pose point `p` under `skinning`.
glm::dvec3 skinned(const glm::dvec3& p, const Influence* influences, size_t count,
                   const std::vector<glm::dmat4>& skinning) {
  glm::dvec3 out(0.0);
  for (size_t k = 0; k < count; ++k)
    out += double(influences[k].weight) *
           glm::dvec3(skinning[influences[k].joint] * glm::dvec4(p, 1.0));
  return out;
}

}  // namespace

Status measureInfluenceFold(const Character& c, const std::vector<WideVertex>& wide,
                            GltfImportReport* report) {
  if (wide.empty()) return Status::ok();
  std::vector<GltfImportReport::FoldedVertex>& folded = report->folded_vertices;
  folded.resize(wide.size());
  const auto measure = [&](const ReferencePose& pose) {
    for (size_t k = 0; k < wide.size(); ++k) {
      const WideVertex& w = wide[k];
      const glm::dvec3 p(c.mesh.positions[w.vertex]);
      Influence kept[kMaxInfluences];
      for (size_t i = 0; i < kMaxInfluences; ++i) kept[i] = c.mesh.influence(w.vertex, i);
      const double error = glm::length(skinned(p, kept, kMaxInfluences, pose.skinning) -
                                       skinned(p, w.influences, w.count, pose.skinning));
      folded[k].error_units = std::max(folded[k].error_units, error);
    }
  };
  // The poses: the clips at kFoldSampleHz, or evenly slower where that would pass either
  // budget (each pose evaluates the skeleton; each vertex-pose skins up to 12 influences).
  double poses_at_rate = 0.0;
  for (const Clip& clip : c.clips)
    poses_at_rate += std::ceil(double(clip.duration_seconds) * kFoldSampleHz) + 1.0;
  const double budget = std::min(kFoldMaxPoses, kFoldMaxVertexPoses / double(wide.size()));
  const double rate = kFoldSampleHz * std::min(1.0, budget / std::max(poses_at_rate, 1.0));
  report->fold_sample_hz = rate;
  ReferencePose pose;
  Status s = evaluateRestPose(c.skeleton, &pose);
  if (!s.isOk()) return corrupt("measuring the fold to 4 influences: " + s.message());
  measure(pose);
  for (const Clip& clip : c.clips) {
    const double duration = double(clip.duration_seconds);
    const double steps = std::ceil(duration * rate);  // At least the start and the end.
    for (double i = 0; i <= steps; ++i) {
      s = evaluateLocalPose(c.skeleton, clip, steps > 0 ? duration * i / steps : 0.0, &pose);
      if (!s.isOk()) return corrupt("measuring the fold to 4 influences: " + s.message());
      measure(pose);
    }
  }
  const double height = double(c.height());
  for (size_t k = 0; k < wide.size(); ++k) {
    folded[k].vertex = wide[k].vertex;
    folded[k].dropped_weight = wide[k].dropped_weight;
    report->max_fold_error_units = std::max(report->max_fold_error_units, folded[k].error_units);
  }
  report->max_fold_error_height = height > 0.0 ? report->max_fold_error_units / height : 0.0;
  report->warnings.push_back(strCat(
      wide.size(),
      " vertices have more than 4 influences: each keeps its 4 largest, which moves "
      "it by up to ",
      report->max_fold_error_units, " units (", report->max_fold_error_height, " of the height)"));
  return Status::ok();
}

void keepWideInfluences(const std::vector<WideVertex>& wide, float tolerance,
                        GltfImportReport* report, Character* c) {
  if (wide.empty() || !(report->max_fold_error_height > double(tolerance))) return;
  SkinnedMesh& mesh = c->mesh;
  mesh.joints1.assign(mesh.vertexCount(), glm::u16vec4(0));
  mesh.weights1.assign(mesh.vertexCount(), glm::vec4(0.0f));
  for (const WideVertex& w : wide) {
    Influence sorted[8];
    std::copy(w.influences, w.influences + w.count, sorted);
    std::stable_sort(sorted, sorted + w.count,
                     [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
    glm::u16vec4 joints[2] = {glm::u16vec4(0), glm::u16vec4(0)};
    glm::vec4 weights[2] = {glm::vec4(0.0f), glm::vec4(0.0f)};
    for (uint32_t k = 0; k < w.count; ++k) {
      joints[k / 4][int(k % 4)] = uint16_t(sorted[k].joint);
      weights[k / 4][int(k % 4)] = sorted[k].weight;
    }
    mesh.joints[w.vertex] = joints[0];
    mesh.weights[w.vertex] = weights[0];
    mesh.joints1[w.vertex] = joints[1];
    mesh.weights1[w.vertex] = weights[1];
  }
  report->kept_eight_influences = true;
  report->warnings.push_back(strCat("kept all 8 influences of the ", wide.size(),
                                    " vertices that have them: folding them to 4 would pass "
                                    "the tolerance of ",
                                    tolerance, " of the height"));
}

}  // namespace si::detail
