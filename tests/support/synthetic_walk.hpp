// A walk whose foot contacts are known exactly: hips 0.9 m up, travelling +Z at
// 1 m/s over a 1 s cycle (or in place); each foot stands still on the ground
// (y = 0) for 60 % of the cycle, the left over [0, 0.6), the right over
// [0.5, 1.1) (wrapping to [0.5, 1) and [0, 0.1)), and swings 1 m forward and
// 15 cm up in the rest. Linear keys, so positions between keys are exact.
#pragma once
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::test {

struct SyntheticWalk {
  Skeleton skeleton;
  Clip clip;
  int hips = 0, leftFoot = 1, rightFoot = 2;
};

inline SyntheticWalk makeSyntheticWalk(bool travels = true) {
  SyntheticWalk w;
  auto joint = [&](const char* name, int parent, glm::vec3 offset) {
    Transform t;
    t.translation = offset;
    return w.skeleton.addJoint(name, parent, t);
  };
  joint("Hips", -1, {0.0f, 0.9f, 0.0f});
  joint("LeftFoot", 0, {0.1f, -0.9f, 0.0f});
  joint("RightFoot", 0, {-0.1f, -0.9f, 0.0f});
  auto track = [](int j, std::vector<float> times, std::vector<glm::vec3> values) {
    JointTrack t;
    t.joint = j;
    t.translation.times = std::move(times);
    t.translation.values = std::move(values);
    return t;
  };
  w.clip.name = travels ? "walk" : "walk in place";
  w.clip.tracks.push_back(track(0, {0.0f, 1.0f}, {{0, 0.9f, 0}, {0, 0.9f, travels ? 1.0f : 0.0f}}));
  // Foot = hips + local: a planted foot's local z falls at the hips' speed. The
  // same local keys serve the walk in place, whose ground moves at -1 m/s instead.
  w.clip.tracks.push_back(track(1, {0.0f, 0.6f, 0.8f, 1.0f},
                                {{0.1f, -0.9f, 0.0f}, {0.1f, -0.9f, -0.6f}, {0.1f, -0.75f, -0.3f}, {0.1f, -0.9f, 0.0f}}));
  w.clip.tracks.push_back(track(2, {0.0f, 0.1f, 0.3f, 0.5f, 1.0f},
                                {{-0.1f, -0.9f, -0.5f}, {-0.1f, -0.9f, -0.6f}, {-0.1f, -0.75f, -0.3f},
                                 {-0.1f, -0.9f, 0.0f}, {-0.1f, -0.9f, -0.5f}}));
  w.clip.updateDuration();
  return w;
}

}  // namespace marionette::test
