// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's root motion (key R, --root-motion): the field plays the clips that carry root
// motion and the crowd moves every character by it (the embedded character's travelling clips
// added and baked the first time it is turned on); the mean travel is what the headless run
// reports.
#include "demo_scene.h"
#include "si/crowd/crowd_manager.h"

namespace demo {

si::Status DemoScene::addTravellingClips() {
  si::DefaultCharacterDesc moving;
  moving.moving_clips = true;
  si::Character c;
  si::Status s = si::makeDefaultCharacter(moving, &c);
  if (!s.isOk()) return s;
  for (si::Clip& clip : c.clips)
    if (clip.root_motion.extract) character_.clips.push_back(std::move(clip));
  s = bake();
  if (s.isOk() && gl_ready_)
    s = renderer_.replaceCharacter(si::CharacterId{}, character_, palette_);
  return s;
}

si::Status DemoScene::toggleRootMotion() {
  options_.root_motion = !options_.root_motion;
  si::Status s;
  bool travelling = false;
  for (const si::BakedClip& clip : palette_.clips) travelling |= !clip.root_motion.empty();
  // The embedded character, baked here without its travelling clips: add them now.
  if (options_.root_motion && !travelling && options_.model.empty() && options_.palette.empty() &&
      options_.clips.empty())
    s = addTravellingClips();
  if (s.isOk() && gl_ready_) s = buildCrowd();
  if (!s.isOk()) {
    options_.root_motion = !options_.root_motion;
    if (gl_ready_) (void)buildCrowd();
  }
  return s;
}

double DemoScene::meanTravel() const {
  double sum = 0.0;
  for (size_t i = 0; i < handles_.size(); ++i) {
    si::InstanceDesc d;
    if (crowd_.get(handles_[i], &d).isOk()) sum += glm::length(d.position - starts_[i]);
  }
  return handles_.empty() ? 0.0 : sum / double(handles_.size());
}

}  // namespace demo
