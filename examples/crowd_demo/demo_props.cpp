// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// crowd_demo's props (key O, --props): the embedded character holds a staff in its left hand, a
// prop read from a glTF file (the sample RiggedSimple's cylinder, in its bind pose) attached at
// a socket before baking; every other character shows it (its variation bit).
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "demo_scene.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_prop.h"

namespace demo {

si::Status DemoScene::attachStaff() {
  si::GltfPropDesc pd;
  pd.name = "staff";
  si::PropMesh staff;
  si::GltfImportReport report;
  si::Status s = si::importGltfPropFile(
      std::string(SI_DEMO_ASSETS) + "/RiggedSimple/glTF-Binary/RiggedSimple.glb", pd, &staff,
      &report);
  if (!s.isOk()) return {s.code(), "props: " + s.message()};
  // The cylinder (2 units wide, about 9 long along Z) held upright in the hand: thin and 1.6
  // units long, its axis along the forearm's down direction.
  glm::mat4 offset = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
  offset = glm::scale(offset, glm::vec3(0.025f, 0.025f, 0.17f));
  si::Socket grip;
  s = si::makeSocket(character_.skeleton, "left grip", "l_hand", offset, &grip);
  if (s.isOk()) s = si::attachProp(grip, staff, &character_, &staff_bit_);
  if (!s.isOk()) return {s.code(), "props: " + s.message()};
  return s;
}

si::Status DemoScene::applyProps() {
  props_ = 0;
  if (staff_bit_ == kNoStaff) {
    if (options_.props)
      return {si::StatusCode::kUnsupported, "props: only the embedded character holds one"};
    return si::Status::ok();
  }
  for (size_t i = 1; i < handles_.size(); i += 2) {
    si::InstanceDesc d;
    si::Status s = crowd_.get(handles_[i], &d);
    const uint32_t bit = 1u << staff_bit_;
    if (s.isOk())
      s = crowd_.setVariationMask(
          handles_[i], options_.props ? d.variation_mask | bit : d.variation_mask & ~bit);
    if (!s.isOk()) return s;
    props_ += options_.props ? 1 : 0;
  }
  return si::Status::ok();
}

si::Status DemoScene::toggleProps() {
  return toggleOption(&options_.props, [&] { return applyProps(); });
}

}  // namespace demo
