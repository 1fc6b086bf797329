// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Double-precision clip evaluation with glTF 2.0 sampler semantics (glTF 2.0 specification,
// "Animations" and Appendix C, "Interpolation"), and linear blend skinning.
#include "si/core/reference_evaluator.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "core/polar_rotation.h"
#include "core/root_motion_frame.h"
#include "core/str_cat.h"
#include "core/validated_evaluation.h"

namespace si {
using detail::strCat;

double clipLocalTime(const Clip& clip, double time_seconds, TimeWrap wrap) {
  const double d = clip.duration_seconds;
  bool loop = resolveLoopMode(clip.loop_mode) == LoopMode::kLoop;
  if (wrap == TimeWrap::kClamp) loop = false;
  if (wrap == TimeWrap::kLoop) loop = true;
  if (!(d > 0.0)) return 0.0;
  if (!loop) return std::clamp(time_seconds, 0.0, d);
  double t = std::fmod(time_seconds, d);
  if (t < 0.0) t += d;
  if (t >= d) t = 0.0;  // fmod of a negative tiny value plus d can round to d.
  return t;
}

namespace {

glm::dvec3 widen(const glm::vec3& v) { return glm::dvec3(v); }
glm::dquat widen(const glm::quat& q) { return glm::dquat(q.w, q.x, q.y, q.z); }

glm::dvec3 finish(const glm::dvec3& v) { return v; }
glm::dquat finish(const glm::dquat& q) { return safeNormalize(q); }

glm::dvec3 lerpValue(const glm::dvec3& a, const glm::dvec3& b, double u) { return a + (b - a) * u; }

// Spherical linear interpolation on the shorter arc, of normalized keys.
glm::dquat lerpValue(const glm::dquat& qa, const glm::dquat& qb, double u) {
  const glm::dquat a = safeNormalize(qa);
  glm::dquat b = safeNormalize(qb);
  double cosine = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (cosine < 0.0) {
    b = -b;
    cosine = -cosine;
  }
  double wa, wb;
  if (cosine > 1.0 - 1e-12) {
    wa = 1.0 - u;
    wb = u;
  } else {
    const double angle = std::acos(std::min(cosine, 1.0));
    const double s = std::sin(angle);
    wa = std::sin((1.0 - u) * angle) / s;
    wb = std::sin(u * angle) / s;
  }
  return safeNormalize(glm::dquat(wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y,
                                  wa * a.z + wb * b.z));
}

template <typename V>
V hermite(const V& p0, const V& m0, const V& p1, const V& m1, double u) {
  const double u2 = u * u, u3 = u2 * u;
  return p0 * (2 * u3 - 3 * u2 + 1) + m0 * (u3 - 2 * u2 + u) + p1 * (-2 * u3 + 3 * u2) +
         m1 * (u3 - u2);
}

// Value of key k (for CUBICSPLINE the middle element of its triple).
template <typename T>
auto keyValue(const Track<T>& track, size_t k) {
  const size_t stride = resolveInterpolation(track.interpolation) == Interpolation::kCubicSpline
                            ? 3 : 1;
  return widen(track.values[k * stride + (stride == 3 ? 1 : 0)]);
}

// Interpolates from key a (at time ta) to key b (at time tb) at time t, ta < tb.
template <typename T>
auto segment(const Track<T>& track, size_t a, size_t b, double ta, double tb, double t) {
  const double dt = tb - ta;
  const double u = std::clamp((t - ta) / dt, 0.0, 1.0);
  switch (resolveInterpolation(track.interpolation)) {
    case Interpolation::kStep:
      return finish(keyValue(track, a));
    case Interpolation::kCubicSpline: {
      const auto p0 = widen(track.values[a * 3 + 1]);
      const auto m0 = widen(track.values[a * 3 + 2]) * dt;  // out-tangent of a
      const auto p1 = widen(track.values[b * 3 + 1]);
      const auto m1 = widen(track.values[b * 3 + 0]) * dt;  // in-tangent of b
      return finish(hermite(p0, m0, p1, m1, u));
    }
    default:
      return finish(lerpValue(keyValue(track, a), keyValue(track, b), u));
  }
}

// Where clip-local time t falls on a track's key times: between keys a and b (at ta < tb; t
// moved by the wrap where it wraps), or on key a held (a == b).
struct KeySpan {
  size_t a = 0, b = 0;
  double ta = 0.0, tb = 0.0, t = 0.0;
};
KeySpan locateKeys(const std::vector<float>& times, double t, double wrap_to) {
  const size_t n = times.size();
  const double first = times.front(), last = times.back();
  if (wrap_to >= 0.0 && n > 1) {
    const double wrap_end = wrap_to + first;
    if (t > last && wrap_end > last) return {n - 1, 0, last, wrap_end, t};
    if (t < first && wrap_end > last) return {n - 1, 0, last, wrap_end, t + wrap_to};
  }
  if (n == 1 || t <= first) return {0, 0, first, first, t};
  if (t >= last) return {n - 1, n - 1, last, last, t};
  // First key strictly after t; t is inside (first, last) so 1 <= hi <= n - 1.
  const size_t hi = static_cast<size_t>(
      std::upper_bound(times.begin(), times.end(), t,
                       [](double x, float key) { return x < double(key); }) - times.begin());
  return {hi - 1, hi, times[hi - 1], times[hi], t};
}

template <typename T>
auto sampleImpl(const Track<T>& track, double t, double wrap_to) {
  const KeySpan k = locateKeys(track.times_seconds, t, wrap_to);
  if (k.a == k.b) return finish(keyValue(track, k.a));
  return segment(track, k.a, k.b, k.ta, k.tb, k.t);
}

// Target i's weight of a morph track at k (a glTF weights channel: per key target_count values,
// or for CUBICSPLINE three runs of them, in-tangents, values, out-tangents).
double morphWeightAt(const MorphWeightTrack& track, const KeySpan& k, size_t i) {
  const size_t n = track.target_count;
  const Interpolation interp = resolveInterpolation(track.interpolation);
  const auto& v = track.values;
  if (interp == Interpolation::kCubicSpline) {
    const double p0 = v[k.a * 3 * n + n + i];
    if (k.a == k.b) return p0;
    const double dt = k.tb - k.ta, u = std::clamp((k.t - k.ta) / dt, 0.0, 1.0);
    return hermite(p0, v[k.a * 3 * n + 2 * n + i] * dt, double(v[k.b * 3 * n + n + i]),
                   v[k.b * 3 * n + i] * dt, u);
  }
  const double p0 = v[k.a * n + i];
  if (k.a == k.b || interp == Interpolation::kStep) return p0;
  const double u = std::clamp((k.t - k.ta) / (k.tb - k.ta), 0.0, 1.0);
  return p0 + (double(v[k.b * n + i]) - p0) * u;
}

}  // namespace

glm::dvec3 sampleTrack(const Vec3Track& track, double t, double wrap_to) {
  return sampleImpl(track, t, wrap_to);
}
glm::dquat sampleTrack(const QuatTrack& track, double t, double wrap_to) {
  return sampleImpl(track, t, wrap_to);
}

Status composePose(const Skeleton& skeleton, Span<const TransformD> local,
                   Span<glm::dmat4> out_model, Span<glm::dmat4> out_skinning) {
  const size_t n = skeleton.jointCount();
  if (local.size() != n || out_model.size() != n || out_skinning.size() != n)
    return {StatusCode::kCountMismatch,
            strCat("composePose: spans hold ", local.size(), "/", out_model.size(), "/",
                   out_skinning.size(), " elements, the skeleton has ", n, " joints")};
  for (size_t j = 0; j < n; ++j) {
    const glm::dmat4 m = local[j].toMatrix();
    const int32_t p = skeleton.parents[j];
    out_model[j] = p == Skeleton::kNoParent ? m : out_model[size_t(p)] * m;
    out_skinning[j] = out_model[j] * glm::dmat4(skeleton.inverse_bind_matrices[j]);
  }
  return Status::ok();
}

Status paletteSkinning(const BakedPalette& palette, Span<const glm::dmat4> skinning,
                       Span<glm::mat4> out) {
  const size_t joints = palette.skeleton_to_palette.size();
  if (skinning.size() != joints || out.size() != palette.palette_joints.size())
    return {StatusCode::kCountMismatch,
            strCat("paletteSkinning: ", skinning.size(), " skinning matrices and ", out.size(),
                   " out, the palette was baked from ", joints, " joints and stores ",
                   palette.palette_joints.size())};
  for (size_t k = 0; k < out.size(); ++k) {
    const uint32_t joint = palette.palette_joints[k];
    if (joint >= joints)
      return {StatusCode::kOutOfRange,
              strCat("paletteSkinning: palette joint ", k, " is skeleton joint ", joint,
                     ", past the ", joints, " it was baked from")};
    out[k] = glm::mat4(skinning[joint]);
  }
  return Status::ok();
}

Status decomposePose(const Skeleton& skeleton, Span<const glm::dmat4> model,
                     Span<TransformD> out_local) {
  const size_t n = skeleton.jointCount();
  if (model.size() != n || out_local.size() != n)
    return {StatusCode::kCountMismatch,
            strCat("decomposePose: spans hold ", model.size(), "/", out_local.size(),
                   " elements, the skeleton has ", n, " joints")};
  // Each joint relative to its parent as composed again from the transforms found, not as
  // given: what a parent's decomposition drops (shear) is then not passed down its branch, and
  // every joint's origin comes back where `model` puts it.
  std::vector<glm::dmat4> composed(n);
  for (size_t j = 0; j < n; ++j) {
    const int32_t p = skeleton.parents[j];
    glm::dmat4 local = model[j];
    if (p != Skeleton::kNoParent) {
      const glm::dmat4& parent = composed[size_t(p)];
      const double det = glm::determinant(glm::dmat3(parent));
      if (!std::isfinite(det) || det == 0.0)
        return {StatusCode::kNotFinite,
                strCat("decomposePose: joint ", p, "'s matrix is singular or not finite")};
      local = glm::inverse(parent) * model[j];
    }
    TransformD t;
    t.translation = glm::dvec3(local[3]);
    if (!std::isfinite(t.translation.x + t.translation.y + t.translation.z) ||
        !detail::polarRotationScale(glm::dmat3(local), &t.rotation, &t.scale))
      return {StatusCode::kNotFinite,
              strCat("decomposePose: joint ", j, "'s matrix is singular or not finite")};
    out_local[j] = t;
    composed[j] = p == Skeleton::kNoParent ? t.toMatrix() : composed[size_t(p)] * t.toMatrix();
  }
  return Status::ok();
}

Status evaluateRestPose(const Skeleton& skeleton, ReferencePose* pose) {
  if (pose == nullptr) return {StatusCode::kInvalidArgument, "evaluateRestPose: pose is null"};
  Status s = skeleton.validate();
  if (!s.isOk()) return s;
  const size_t n = skeleton.jointCount();
  pose->local.resize(n);
  pose->model.resize(n);
  pose->skinning.resize(n);
  for (size_t j = 0; j < n; ++j) pose->local[j] = TransformD::fromFloat(skeleton.rest_pose[j]);
  return composePose(skeleton, pose->local, pose->model, pose->skinning);
}

namespace {
// Joint j's local transform of `clip` at clip-local time t (wrap_to as sampleTrack's).
TransformD localAt(const Skeleton& skeleton, const Clip& clip, size_t j, double t, double wrap_to) {
  TransformD x = TransformD::fromFloat(skeleton.rest_pose[j]);
  const JointTracks& jt = clip.joint_tracks[j];
  if (!jt.translation.empty()) x.translation = sampleTrack(jt.translation, t, wrap_to);
  if (!jt.rotation.empty()) x.rotation = sampleTrack(jt.rotation, t, wrap_to);
  if (!jt.scale.empty()) x.scale = sampleTrack(jt.scale, t, wrap_to);
  x.rotation = safeNormalize(x.rotation);
  return x;
}

// Joint `joint`'s model matrix at clip-local time t: its chain of ancestors only.
glm::dmat4 chainModelAt(const Skeleton& skeleton, const Clip& clip, uint32_t joint, double t,
                        double wrap_to) {
  glm::dmat4 m(1.0);
  for (int32_t j = int32_t(joint); j != Skeleton::kNoParent; j = skeleton.parents[size_t(j)])
    m = localAt(skeleton, clip, size_t(j), t, wrap_to).toMatrix() * m;
  return m;
}

double wrapTarget(const Clip& clip, bool loop) {
  return loop && clip.wrap_interpolates ? double(clip.duration_seconds) : -1.0;
}

// Checks what every evaluation needs; the root motion joint of a clip that extracts it.
Status checkInputs(const Skeleton& skeleton, const Clip& clip, double t, const void* out,
                   const char* what, uint32_t* root_joint, bool validated = false) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, strCat(what, ": output is null")};
  if (!std::isfinite(t)) return {StatusCode::kNotFinite, strCat(what, ": time is not finite")};
  Status s = validated ? Status::ok() : skeleton.validate();
  if (s.isOk() && !validated) s = clip.validate(skeleton.jointCount());
  if (s.isOk()) s = rootMotionJoint(skeleton, clip, root_joint);
  return s;
}

// Evaluates at clip-local time t in [0, duration]; `loop` selects the wrap interpolation. A clip
// that extracts its root motion gives M(t)^-1 * pose (root joints' local transforms included).
Status evaluateAt(const Skeleton& skeleton, const Clip& clip, double t, bool loop,
                  ReferencePose* pose, bool validated = false) {
  uint32_t root_joint = 0;
  Status s = checkInputs(skeleton, clip, t, pose, "evaluatePose", &root_joint, validated);
  if (!s.isOk()) return s;
  t = std::clamp(t, 0.0, double(clip.duration_seconds));
  const double wrap_to = wrapTarget(clip, loop);
  const size_t n = skeleton.jointCount();
  pose->local.resize(n);
  pose->model.resize(n);
  pose->skinning.resize(n);
  for (size_t j = 0; j < n; ++j) pose->local[j] = localAt(skeleton, clip, j, t, wrap_to);
  s = composePose(skeleton, pose->local, pose->model, pose->skinning);
  if (!s.isOk() || !clip.root_motion.extract) return s;
  const GroundMotion motion = detail::groundMotionBetween(
      chainModelAt(skeleton, clip, root_joint, 0.0, wrap_to), pose->model[root_joint]);
  const glm::dmat4 in_place = groundMotionMatrix(inverseGroundMotion(motion));
  const glm::dquat turn = glm::angleAxis(-motion.yaw, glm::dvec3(0.0, 1.0, 0.0));
  for (size_t j = 0; j < n; ++j) {
    pose->model[j] = in_place * pose->model[j];
    pose->skinning[j] = in_place * pose->skinning[j];
    if (skeleton.parents[j] != Skeleton::kNoParent) continue;
    TransformD& local = pose->local[j];  // A rigid motion composes into translation and rotation.
    local.translation = glm::dvec3(in_place * glm::dvec4(local.translation, 1.0));
    local.rotation = safeNormalize(turn * local.rotation);
  }
  return s;
}
}  // namespace

namespace {
Status rootMotionAt(const Skeleton& skeleton, const Clip& clip, double local_time_seconds,
                    GroundMotion* out, bool validated) {
  uint32_t root_joint = 0;
  Status s = checkInputs(skeleton, clip, local_time_seconds, out, "evaluateRootMotion",
                         &root_joint, validated);
  if (!s.isOk()) return s;
  const double t = std::clamp(local_time_seconds, 0.0, double(clip.duration_seconds));
  const double wrap_to = wrapTarget(clip, resolveLoopMode(clip.loop_mode) == LoopMode::kLoop);
  *out = detail::groundMotionBetween(chainModelAt(skeleton, clip, root_joint, 0.0, wrap_to),
                                     chainModelAt(skeleton, clip, root_joint, t, wrap_to));
  return Status::ok();
}
}  // namespace

Status evaluateRootMotion(const Skeleton& skeleton, const Clip& clip, double local_time_seconds,
                          GroundMotion* out) {
  return rootMotionAt(skeleton, clip, local_time_seconds, out, false);
}

namespace detail {
void evaluateValidatedMorphWeights(const SkinnedMesh& mesh, const Clip& clip,
                                   double local_time_seconds, Span<double> out) {
  for (size_t i = 0; i < out.size(); ++i) out[i] = double(mesh.morph_targets[i].default_weight);
  const double t = std::clamp(local_time_seconds, 0.0, double(clip.duration_seconds));
  const double wrap_to = wrapTarget(clip, resolveLoopMode(clip.loop_mode) == LoopMode::kLoop);
  for (const MorphWeightTrack& track : clip.morph_tracks) {
    if (track.times_seconds.empty()) continue;
    const KeySpan k = locateKeys(track.times_seconds, t, wrap_to);
    for (size_t i = 0; i < track.target_count; ++i)
      out[track.first_target + i] = morphWeightAt(track, k, i);
  }
}

Status evaluateValidatedLocalPose(const Skeleton& skeleton, const Clip& clip,
                                  double local_time_seconds, ReferencePose* pose) {
  return evaluateAt(skeleton, clip, local_time_seconds,
                    resolveLoopMode(clip.loop_mode) == LoopMode::kLoop, pose, true);
}
Status evaluateValidatedRootMotion(const Skeleton& skeleton, const Clip& clip,
                                   double local_time_seconds, GroundMotion* out) {
  return rootMotionAt(skeleton, clip, local_time_seconds, out, true);
}
}  // namespace detail

Status evaluatePose(const Skeleton& skeleton, const Clip& clip, double time_seconds,
                    ReferencePose* pose, TimeWrap wrap) {
  if (!std::isfinite(time_seconds))
    return {StatusCode::kNotFinite, "evaluatePose: time_seconds is not finite"};
  bool loop = resolveLoopMode(clip.loop_mode) == LoopMode::kLoop;
  if (wrap != TimeWrap::kDefault) loop = wrap == TimeWrap::kLoop;
  return evaluateAt(skeleton, clip, clipLocalTime(clip, time_seconds, wrap), loop, pose);
}

Status evaluateLocalPose(const Skeleton& skeleton, const Clip& clip, double local_time_seconds,
                         ReferencePose* pose) {
  return evaluateAt(skeleton, clip, local_time_seconds,
                    resolveLoopMode(clip.loop_mode) == LoopMode::kLoop, pose);
}

Status evaluateMorphWeights(const SkinnedMesh& mesh, const Clip& clip, double local_time_seconds,
                            Span<double> out) {
  if (out.size() != mesh.morph_targets.size())
    return {StatusCode::kCountMismatch,
            strCat("evaluateMorphWeights: ", out.size(), " weights for ", mesh.morph_targets.size(),
                   " morph targets")};
  if (!std::isfinite(local_time_seconds))
    return {StatusCode::kNotFinite, "evaluateMorphWeights: time is not finite"};
  const Status s = clip.validate(clip.joint_tracks.size(), mesh.morph_targets.size());
  if (!s.isOk()) return s;
  detail::evaluateValidatedMorphWeights(mesh, clip, local_time_seconds, out);
  return Status::ok();
}

namespace {
// sign(det) * cofactor matrix of the upper 3x3: equals |det| times the inverse transpose, so
// normals keep their direction under mirroring and stay finite for singular matrices.
glm::dmat3 normalMatrix(const glm::dmat4& m) {
  const glm::dmat3 a(m);
  glm::dmat3 cof;
  cof[0] = glm::cross(a[1], a[2]);
  cof[1] = glm::cross(a[2], a[0]);
  cof[2] = glm::cross(a[0], a[1]);
  const double det = glm::dot(a[0], cof[0]);
  return det < 0.0 ? -cof : cof;
}
}  // namespace

Status skinVertices(const SkinnedMesh& mesh, Span<const glm::dmat4> skinning,
                    Span<glm::dvec3> out_positions, Span<glm::dvec3> out_normals,
                    Span<glm::dvec4> out_tangents, Span<const double> morph_weights) {
  const size_t n = mesh.vertexCount();
  if (out_positions.size() != n || (!out_normals.empty() && out_normals.size() != n) ||
      (!out_tangents.empty() && out_tangents.size() != n) ||
      (!out_tangents.empty() && mesh.tangents.size() != n) || mesh.joints.size() != n ||
      mesh.weights.size() != n || (!out_normals.empty() && mesh.normals.size() != n) ||
      (!mesh.joints1.empty() && (mesh.joints1.size() != n || mesh.weights1.size() != n)))
    return {StatusCode::kCountMismatch,
            strCat("skinVertices: output spans or mesh attributes do not match the ", n,
                   " vertices")};
  const size_t influences = mesh.influenceCount();
  for (size_t v = 0; v < n; ++v)
    for (size_t i = 0; i < influences; ++i) {
      const Influence in = mesh.influence(v, i);
      if (in.weight != 0.0f && in.joint >= skinning.size())
        return {StatusCode::kOutOfRange, strCat("skinVertices: vertex ", v, " uses joint ",
                                                in.joint, " of ", skinning.size())};
    }
  // The bind pose with the morph targets added (the mesh's own attributes without them).
  std::vector<glm::dvec3> positions(mesh.positions.begin(), mesh.positions.end());
  std::vector<glm::dvec3> normals;
  std::vector<glm::dvec4> tangents;
  if (!out_normals.empty()) normals.assign(mesh.normals.begin(), mesh.normals.end());
  if (!out_tangents.empty()) tangents.assign(mesh.tangents.begin(), mesh.tangents.end());
  if (!mesh.morph_targets.empty()) {
    Status s = validateMorphTargets(mesh.morph_targets, n, !mesh.tangents.empty());
    const std::vector<double> defaults = defaultMorphWeights(mesh.morph_targets);
    if (s.isOk())
      s = applyMorphTargets(mesh.morph_targets,
                            morph_weights.empty() ? Span<const double>(defaults) : morph_weights,
                            positions, normals, tangents);
    if (!s.isOk()) return s;
  } else if (!morph_weights.empty()) {
    return {StatusCode::kCountMismatch, strCat("skinVertices: ", morph_weights.size(),
                                               " morph weights for a mesh without targets")};
  }
  for (size_t v = 0; v < n; ++v) {
    const glm::dvec4 p(positions[v], 1.0);
    glm::dvec3 pos(0.0), nrm(0.0), tan(0.0);
    for (size_t i = 0; i < influences; ++i) {
      const Influence in = mesh.influence(v, i);
      const double w = in.weight;
      if (w == 0.0) continue;  // Zero weights are skipped, as the shader does.
      const glm::dmat4& m = skinning[in.joint];
      pos += w * glm::dvec3(m * p);
      if (!out_normals.empty()) nrm += w * (normalMatrix(m) * normals[v]);
      if (!out_tangents.empty()) tan += w * (glm::dmat3(m) * glm::dvec3(tangents[v]));
    }
    out_positions[v] = pos;
    if (!out_normals.empty()) {
      const double len = glm::length(nrm);
      out_normals[v] = len > 1e-300 && std::isfinite(len) ? nrm / len : normals[v];
    }
    if (!out_tangents.empty()) {
      const double len = glm::length(tan);
      const glm::dvec3 t3 =
          len > 1e-300 && std::isfinite(len) ? tan / len : glm::dvec3(tangents[v]);
      out_tangents[v] = glm::dvec4(t3, double(mesh.tangents[v].w));
    }
  }
  return Status::ok();
}

}  // namespace si
