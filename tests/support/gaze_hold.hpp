// Measuring whether a gaze holds over a clip that moves the head: a clip that turns a
// joint about the character's vertical (and back), and the angle between where the
// gaze chain's top joint faces and the target, seen from where the gaze aims from.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>

#include "joint_rotation.hpp"
#include "marionette/animation/animation_clip.hpp"
#include "marionette/scene/character.hpp"

namespace marionette::test {

// A looping clip of `seconds` that holds the rest pose, then turns `joint` by up to
// `degrees` about the model frame's +Y and back, between 40 % and 70 % of the clip.
inline std::shared_ptr<const AnimationClip> headTurnClip(const Skeleton& s, int joint, float degrees, float seconds) {
  Clip clip;
  clip.name = "head_turn";
  JointTrack t;
  t.joint = joint;
  // The model frame's +Y in the joint's parent frame at rest (root rotation included).
  glm::mat3 root(s.rootTransform);
  for (int c = 0; c < 3; ++c) root[c] = glm::normalize(root[c]);
  glm::quat parent = glm::quat_cast(root);
  std::vector<int> chain;
  for (int p = s.parents[static_cast<std::size_t>(joint)]; p >= 0; p = s.parents[static_cast<std::size_t>(p)]) chain.push_back(p);
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) parent = parent * s.restPose[static_cast<std::size_t>(*it)].rotation;
  const glm::vec3 up = glm::inverse(parent) * glm::vec3(0, 1, 0);
  const glm::quat rest = s.restPose[static_cast<std::size_t>(joint)].rotation;
  for (int k = 0; k <= 60; ++k) {
    const float u = static_cast<float>(k) / 60.0f;
    const float phase = std::clamp((u - 0.4f) / 0.3f, 0.0f, 1.0f);
    const float angle = glm::radians(degrees) * std::sin(3.14159265f * phase);
    t.rotation.times.push_back(u * seconds);
    t.rotation.values.push_back(glm::angleAxis(angle, glm::normalize(up)) * rest);
  }
  clip.tracks.push_back(std::move(t));
  clip.updateDuration();
  AnimationClipOptions keepEveryKey;
  keepEveryKey.optimizeClips = false;
  return makeAnimationClip(std::move(clip), s, keepEveryKey);
}

// Degrees between where `joint` faces (its rest forward +Z carried by its gained rotation,
// in the world) and the direction from `from` (a world point: the gaze's origin) to `target`.
inline float gazeErrorDegrees(const Character& c, int joint, const glm::quat& restModel, const glm::vec3& from,
                              const glm::vec3& target) {
  const glm::quat worldTurn = glm::angleAxis(c.heading(), glm::vec3(0, 1, 0));
  const glm::vec3 facing = worldTurn * ((modelRotation(c, joint) * glm::inverse(restModel)) * glm::vec3(0, 0, 1));
  const float cosine = glm::dot(glm::normalize(facing), glm::normalize(target - from));
  return glm::degrees(std::acos(std::clamp(cosine, -1.0f, 1.0f)));
}

// The gaze's origin in the world: between the eyes, else the head (gaze.cpp's rule).
inline glm::vec3 gazeOriginWorld(const Character& c) {
  const RigJoints& j = c.rig().joints();
  auto world = [&](int joint) {
    return glm::vec3(c.worldMatrix() * c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)][3]);
  };
  if (j.leftEye >= 0 && j.rightEye >= 0) return 0.5f * (world(j.leftEye) + world(j.rightEye));
  return world(j.head >= 0 ? j.head : j.neck);
}

}  // namespace marionette::test
