// A hand-made upper body for the pointing tests: hips at 1 m, a spine and a
// chest, a neck and a head, and two arms (clavicle, upper arm 0.3 m, forearm
// 0.25 m, hand) hanging down with a slight elbow bend. The character faces +Z
// with +Y up; its left is +X.
#pragma once
#include <memory>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette::test {

inline std::shared_ptr<Asset> makeUpperBodyAsset() {
  auto asset = std::make_shared<Asset>();
  Skeleton& s = asset->skeleton;
  auto add = [&](const char* name, int parent, glm::vec3 offset) {
    Transform t;
    t.translation = offset;
    return s.addJoint(name, parent, t);
  };
  add("Hips", -1, {0.0f, 1.0f, 0.0f});
  add("Spine", 0, {0.0f, 0.15f, 0.0f});
  const int chest = add("Chest", 1, {0.0f, 0.2f, 0.0f});
  add("Neck", chest, {0.0f, 0.15f, 0.0f});
  add("Head", 3, {0.0f, 0.1f, 0.0f});
  for (float side : {1.0f, -1.0f}) {
    const bool left = side > 0.0f;
    const int clavicle = add(left ? "LeftShoulder" : "RightShoulder", chest, {side * 0.05f, 0.1f, 0.0f});
    const int upper = add(left ? "LeftArm" : "RightArm", clavicle, {side * 0.13f, 0.0f, 0.0f});
    const int lower = add(left ? "LeftForeArm" : "RightForeArm", upper, {0.0f, -0.3f, -0.02f});
    const int hand = add(left ? "LeftHand" : "RightHand", lower, {0.0f, -0.25f, 0.04f});
    add(left ? "LeftHandIndex1" : "RightHandIndex1", hand, {0.0f, -0.08f, 0.0f});
  }
  return asset;
}

inline CharacterProfile upperBodyProfile() {
  CharacterProfile p;
  p.hips = "Hips";
  p.spine = {"Spine", "Chest"};
  p.neck = "Neck";
  p.head = "Head";
  p.leftArm = {"LeftArm", "LeftForeArm", "LeftHand"};
  p.rightArm = {"RightArm", "RightForeArm", "RightHand"};
  return p;
}

inline std::shared_ptr<Rig> makeUpperBodyRig() {
  auto rig = std::make_shared<Rig>(*makeUpperBodyAsset());
  rig->setProfile(upperBodyProfile());
  return rig;
}

}  // namespace marionette::test
