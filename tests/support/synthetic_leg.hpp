// A hand-made leg for the IK and foot-contact tests: hips at 1 m, a thigh and a
// shin of about 0.45 m whose knee sits 5 cm forward (+Z) in the rest pose, a
// foot and a toe. The character faces +Z with +Y up; the leg is its left (+X).
#pragma once
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::test {

struct SyntheticLeg {
  Skeleton skeleton;
  int hips = 0, thigh = 1, shin = 2, foot = 3, toe = 4;
};

// `kneeForward` is the knee's rest offset ahead of the hip-ankle line (0: a
// straight leg).
inline SyntheticLeg makeSyntheticLeg(float kneeForward = 0.05f) {
  SyntheticLeg leg;
  auto add = [&](const char* name, int parent, glm::vec3 offset) {
    Transform t;
    t.translation = offset;
    return leg.skeleton.addJoint(name, parent, t);
  };
  add("Hips", -1, {0.0f, 1.0f, 0.0f});
  add("LeftUpLeg", 0, {0.1f, 0.0f, 0.0f});
  add("LeftLeg", 1, {0.0f, -0.45f, kneeForward});
  add("LeftFoot", 2, {0.0f, -0.45f, -kneeForward});
  add("LeftToeBase", 3, {0.0f, -0.05f, 0.12f});
  return leg;
}

}  // namespace marionette::test
