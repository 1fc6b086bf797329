// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Animations (glTF 2.0 specification, "Animations"): translation, rotation and scale channels
// of the skeleton's joints and weights channels of the morph targets kept, LINEAR, STEP or
// CUBICSPLINE; other targets are skipped with a warning each. Animation markers come from the
// animation's extras (below).
#include <algorithm>
#include <cmath>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

// The markers of an animation's extras, by this library's convention:
//   "extras": {"markers": [{"time": 0.25, "name": "left_foot"}, ...]}
// An entry that is not an object with a finite number "time" within [0, duration] and a
// non-empty string "name" is skipped with a warning naming it; extras without "markers" (any
// other application data) are left alone.
void readMarkers(const tinygltf::Value& extras, const std::string& where,
                 std::vector<std::string>* warnings, Clip* clip) {
  if (!extras.IsObject() || !extras.Has("markers")) return;
  const tinygltf::Value& list = extras.Get("markers");
  if (!list.IsArray()) {
    warnings->push_back(where + ": extras.markers is not an array: skipped");
    return;
  }
  for (size_t i = 0; i < list.ArrayLen(); ++i) {
    const tinygltf::Value& e = list.Get(int(i));
    const std::string w = strCat(where, ": extras.markers[", i, "]");
    if (!e.IsObject() || !e.Has("time") || !e.Has("name") || !e.Get("time").IsNumber() ||
        !e.Get("name").IsString() || e.Get("name").Get<std::string>().empty()) {
      warnings->push_back(w + " is not {\"time\": number, \"name\": non-empty string}: skipped");
      continue;
    }
    const double t = e.Get("time").GetNumberAsDouble();
    if (!std::isfinite(t) || t < 0.0 || t > double(clip->duration_seconds)) {
      warnings->push_back(strCat(w, ": time ", t, " s is outside the clip's [0, ",
                                 clip->duration_seconds, "] s: skipped"));
      continue;
    }
    clip->markers.push_back({t, e.Get("name").Get<std::string>()});
  }
}

}  // namespace

Status convertClips(const tinygltf::Model& m, const GltfImportDesc& desc,
                    const SkinBinding& binding, const std::vector<NodeMorphTargets>& node_targets,
                    GltfImportReport* report, Character* c) {
  std::vector<std::string>& warnings = report->warnings;
  const std::vector<int32_t>& node_to_joint = binding.node_to_joint;
  const size_t node_count = m.nodes.size();
  // ---- Animations.
  const LoopMode loop = desc.loop_mode == LoopMode::kDefault ? LoopMode::kLoop : desc.loop_mode;
  for (size_t ai = 0; ai < m.animations.size(); ++ai) {
    const tinygltf::Animation& anim = m.animations[ai];
    Clip clip;
    clip.name = anim.name.empty() ? strCat("animation", ai) : anim.name;
    clip.loop_mode = loop;
    clip.joint_tracks.resize(c->skeleton.jointCount());
    const std::string where = strCat("animation '", clip.name, "'");
    for (size_t ch = 0; ch < anim.channels.size(); ++ch) {
      const tinygltf::AnimationChannel& channel = anim.channels[ch];
      const std::string cw = strCat(where, " channel ", ch);
      if (channel.target_node < 0 || size_t(channel.target_node) >= node_count)
        return corrupt(strCat(cw, ": target node ", channel.target_node, " does not exist"));
      const tinygltf::Node& target = m.nodes[size_t(channel.target_node)];
      const bool weights = channel.target_path == "weights";
      const int32_t joint = node_to_joint[size_t(channel.target_node)];
      if (weights && node_targets[size_t(channel.target_node)].count == 0) {
        warnings.push_back(strCat(cw, ": weights of node '", target.name,
                                  "', which has no morph targets (or they were dropped): skipped"));
        continue;
      }
      if (!weights && joint < 0) {
        warnings.push_back(
            strCat(cw, ": targets node '", target.name, "' outside the skeleton: skipped"));
        continue;
      }
      const bool rotation = channel.target_path == "rotation";
      if (!weights && !rotation && channel.target_path != "translation" &&
          channel.target_path != "scale") {
        warnings.push_back(
            strCat(cw, ": unknown target path '", channel.target_path, "': skipped"));
        continue;
      }
      if (channel.sampler < 0 || size_t(channel.sampler) >= anim.samplers.size())
        return corrupt(strCat(cw, ": sampler ", channel.sampler, " does not exist"));
      const tinygltf::AnimationSampler& sampler = anim.samplers[size_t(channel.sampler)];
      Interpolation interp = Interpolation::kLinear;
      if (sampler.interpolation == "STEP") interp = Interpolation::kStep;
      else if (sampler.interpolation == "CUBICSPLINE") interp = Interpolation::kCubicSpline;
      else if (!sampler.interpolation.empty() && sampler.interpolation != "LINEAR")
        return corrupt(strCat(cw, ": unknown interpolation '", sampler.interpolation, "'"));
      std::vector<double> times, values;
      Status s = readAccessor(m, sampler.input, {TINYGLTF_TYPE_SCALAR}, kFloat, cw + " input", &times);
      if (!s.isOk()) return s;
      for (size_t k = 0; k < times.size(); ++k)
        if (times[k] < 0.0 || (k > 0 && !(times[k] > times[k - 1])))
          return corrupt(strCat(cw, ": key times not increasing (or negative) at key ", k));
      const size_t per_key = interp == Interpolation::kCubicSpline ? 3 : 1;
      if (weights) {
        const NodeMorphTargets range = node_targets[size_t(channel.target_node)];
        s = readAccessor(m, sampler.output, {TINYGLTF_TYPE_SCALAR}, kFloatOrNormalized,
                         cw + " output", &values);
        if (!s.isOk()) return s;
        if (values.size() != times.size() * per_key * range.count)
          return corrupt(strCat(cw, ": ", values.size(), " output weights for ", times.size(),
                                " key times of ", range.count, " morph targets"));
        if (std::any_of(clip.morph_tracks.begin(), clip.morph_tracks.end(),
                        [&](const MorphWeightTrack& t) { return t.first_target == range.first; })) {
          warnings.push_back(cw + ": a second weights channel for the same node: skipped");
          continue;
        }
        MorphWeightTrack track;
        track.first_target = range.first;
        track.target_count = range.count;
        track.interpolation = interp;
        for (double t : times) track.times_seconds.push_back(float(t));
        for (double v : values) track.values.push_back(float(v));
        if (!times.empty()) {
          clip.duration_seconds = std::max(clip.duration_seconds, float(times.back()));
          clip.morph_tracks.push_back(std::move(track));
        }
        continue;
      }
      s = readAccessor(m, sampler.output, {rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3},
                       rotation ? kFloatOrNormalized : kFloat, cw + " output", &values);
      if (!s.isOk()) return s;
      const size_t comps = rotation ? 4 : 3;
      if (values.size() != times.size() * comps * per_key)
        return corrupt(strCat(cw, ": ", values.size() / comps, " output values for ", times.size(),
                              " key times"));
      if (!times.empty())
        clip.duration_seconds = std::max(clip.duration_seconds, float(times.back()));
      JointTracks& jt = clip.joint_tracks[size_t(joint)];
      const auto fill = [&](auto& track) {
        if (!track.empty()) {
          warnings.push_back(cw + ": a second channel for the same joint and path: skipped");
          return;
        }
        track.interpolation = interp;
        for (double t : times) track.times_seconds.push_back(float(t));
      };
      if (rotation) {
        fill(jt.rotation);
        if (jt.rotation.values.empty() && !jt.rotation.times_seconds.empty())
          for (size_t v = 0; v < values.size() / 4; ++v)
            jt.rotation.values.push_back(glm::quat(float(values[v * 4 + 3]), float(values[v * 4]),
                                                   float(values[v * 4 + 1]), float(values[v * 4 + 2])));
      } else {
        Vec3Track& track = channel.target_path == "translation" ? jt.translation : jt.scale;
        fill(track);
        if (track.values.empty() && !track.times_seconds.empty())
          for (size_t v = 0; v < values.size() / 3; ++v)
            track.values.push_back(glm::vec3(float(values[v * 3]), float(values[v * 3 + 1]),
                                             float(values[v * 3 + 2])));
      }
    }
    readMarkers(anim.extras, where, &warnings, &clip);
    c->clips.push_back(std::move(clip));
  }
  return Status::ok();
}

}  // namespace si::detail
