// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's live poses (key G, --live), all drawn in the crowd's own batches: the characters
// nearest the camera turn their heads to it (a look-at on their baked pose each frame, handed
// over from the clip and back), and every two seconds one of them falls flat and gets back up
// into its clip (a procedural fall: its pose when it trips, turned about its feet).
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "common/face_targets.h"
#include "demo_scene.h"
#include "si/core/look_at.h"
#include "si/core/reference_evaluator.h"
#include "si/crowd/crowd_manager.h"

namespace demo {

namespace {
constexpr double kHandOverSeconds = 0.4;
constexpr double kFallEvery = 2.0;
// A fall's timeline, seconds from the trip: down (accelerating), lying, up (eased), then the
// clip takes over again.
constexpr double kDown = 0.6, kLying = 1.0, kUp = 1.0;

// How far a fall has turned the body, radians, `t` seconds after the trip.
double fallAngle(double t) {
  const double flat = 0.5 * 3.141592653589793;
  if (t < kDown) return flat * (t / kDown) * (t / kDown);
  if (t < kDown + kLying) return flat;
  const double u = std::min((t - kDown - kLying) / kUp, 1.0);
  return flat * (1.0 - u * u * (3.0 - 2.0 * u));
}
}  // namespace

si::Status DemoScene::applyLive() {
  if (options_.live) {
    const char* head = si::examples::findHeadJoint(character_.skeleton);
    const int32_t h = head != nullptr ? character_.skeleton.findJoint(head) : -1;
    const int32_t neck = h >= 0 ? character_.skeleton.parents[size_t(h)] : -1;
    if (h < 0 || neck < 0)
      return {si::StatusCode::kNotFound, "live: the skeleton has no head joint under a neck"};
    look_.chain = {{uint32_t(neck), 0.4, 0.6}, {uint32_t(h), 1.0, 0.9}};
    look_.forward = glm::dvec3(0.0, 0.0, 1.0);  // glTF's front, and the embedded character's.
    next_fall_ = crowd_.clockSeconds() + 0.5;
    return si::Status::ok();
  }
  for (size_t i = 0; i < looking_.size(); ++i) {  // Back to their clips.
    if (!looking_[i] && !falling_[i]) continue;
    const si::Status s = crowd_.clearLivePose(handles_[i], kHandOverSeconds);
    if (!s.isOk()) return s;
  }
  looking_.assign(handles_.size(), 0);
  falling_.assign(handles_.size(), 0);
  falls_.clear();
  return si::Status::ok();
}

si::Status DemoScene::toggleLive() {
  return toggleOption(&options_.live, [&] { return applyLive(); });
}

// The instance's pose `skinning` (one per skeleton joint, model space) set as its live pose.
si::Status DemoScene::setLive(size_t i, const std::vector<glm::dmat4>& skinning) {
  live_slots_.resize(palette_.palette_joints.size());
  si::Status s = si::paletteSkinning(palette_, skinning, live_slots_);
  if (s.isOk()) s = crowd_.setLivePose(handles_[i], live_slots_, kHandOverSeconds);
  return s;
}

si::Status DemoScene::poseLive(const si::Camera& camera) {
  if (!options_.live) return si::Status::ok();
  looking_.resize(handles_.size(), 0);
  falling_.resize(handles_.size(), 0);
  const si::Skeleton& sk = character_.skeleton;
  const size_t n = sk.jointCount();
  std::vector<si::TransformD> local(n);
  std::vector<glm::dmat4> model(n), skinning(n);
  // The nearest characters in front of the camera, within 12 m: the lookers (each read once).
  const glm::dvec3 forward = -glm::dvec3(glm::transpose(camera.view_rotation)[2]);
  struct Near {
    double distance;
    size_t index;  // Into handles_.
    si::InstanceDesc desc;
  };
  std::vector<Near> near;
  for (size_t i = 0; i < handles_.size(); ++i) {
    si::InstanceDesc d;
    if (!crowd_.get(handles_[i], &d).isOk()) continue;
    const glm::dvec3 to = d.position - camera.position;
    const double distance = glm::length(to);
    if (distance < 12.0 * unit_ && glm::dot(to, forward) > 0.0) near.push_back({distance, i, d});
  }
  std::sort(near.begin(), near.end(), [](const Near& a, const Near& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.index < b.index);
  });
  near.resize(std::min<size_t>(near.size(), kLookers));
  std::vector<uint8_t> wanted(handles_.size(), 0);
  for (const Near& c : near) wanted[c.index] = 1;
  // One of them trips every two seconds.
  const double clock = crowd_.clockSeconds();
  if (clock >= next_fall_ && !near.empty()) {
    next_fall_ = clock + kFallEvery;
    // Of the twelve nearest, one of the three nearest the middle of the view, in turn.
    std::vector<std::pair<double, size_t>> central;
    for (size_t k = 0; k < std::min<size_t>(near.size(), 12); ++k) {
      const glm::dvec3 to = glm::normalize(near[k].desc.position - camera.position);
      central.push_back({-glm::dot(to, forward), near[k].index});
    }
    std::sort(central.begin(), central.end());
    const size_t i = central[falls_started_++ % std::min<size_t>(central.size(), 3)].second;
    if (!falling_[i]) {
      si::Status s = crowd_.localPose(handles_[i], sk, local);
      if (s.isOk()) s = si::composePose(sk, local, model, skinning);
      if (!s.isOk()) return s;
      falls_.push_back({i, clock, skinning});
      falling_[i] = 1;
      looking_[i] = 0;
    }
  }
  for (size_t k = 0; k < falls_.size();) {
    Fall& f = falls_[k];
    const double t = clock - f.start;
    si::Status s;
    if (t >= kDown + kLying + kUp) {  // Up again: the clip takes over.
      s = crowd_.clearLivePose(handles_[f.index], kHandOverSeconds);
      falling_[f.index] = 0;
      f = falls_.back();
      falls_.pop_back();
    } else {  // Turned about the feet (the model origin), face down along +z.
      const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), fallAngle(t), glm::dvec3(1.0, 0.0, 0.0));
      for (size_t j = 0; j < n; ++j) skinning[j] = turn * f.pose[j];
      s = setLive(f.index, skinning);
      ++k;
    }
    if (!s.isOk()) return s;
  }
  // Heads to the camera: those no longer near hand back to their clips; the near ones take the
  // look-at on their baked pose, in the instance's model space.
  for (size_t i = 0; i < handles_.size(); ++i) {
    if (!looking_[i] || wanted[i] || falling_[i]) continue;
    looking_[i] = 0;
    const si::Status s = crowd_.clearLivePose(handles_[i], kHandOverSeconds);
    if (!s.isOk()) return s;
  }
  looking_count_ = 0;
  for (const Near& c : near) {
    if (falling_[c.index]) continue;
    const si::InstanceDesc& d = c.desc;
    const glm::dvec3 target =
        glm::inverse(glm::dquat(d.rotation)) * (camera.position - d.position) / double(d.scale);
    si::Status s = crowd_.localPose(handles_[c.index], sk, local);
    if (s.isOk()) s = si::applyLookAt(sk, look_, target, local);
    if (s.isOk()) s = si::composePose(sk, local, model, skinning);
    if (s.isOk()) s = setLive(c.index, skinning);
    if (!s.isOk()) return s;
    looking_[c.index] = 1;
    ++looking_count_;
  }
  return si::Status::ok();
}

}  // namespace demo
