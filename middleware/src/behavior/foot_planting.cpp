#include "marionette/behavior/foot_planting.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/animation/pose.hpp"

namespace marionette {

namespace {
constexpr float kEaseSpeed = 0.4f;  // m/s
}  // namespace

FootPlanter::FootPlanter(const Skeleton& skeleton, const RigJoints& joints) {
  legs_[0] = makeLimbIk(skeleton, joints.leftLeg);
  legs_[1] = makeLimbIk(skeleton, joints.rightLeg);
  feet_joints_[0] = joints.leftLeg.end;
  feet_joints_[1] = joints.rightLeg.end;
}

void FootPlanter::reset() noexcept {
  feet_[0] = {};
  feet_[1] = {};
}

void FootPlanter::apply(const Skeleton& skeleton, std::span<Transform> pose, const glm::mat4& worldFromModel,
                        const float floor[2], float weight, float dt, const FootPlantSettings& settings) noexcept {
  residual_ = 0.0f;
  if (!settings.enabled || !usable() || !(dt >= 0.0f)) {
    reset();
    return;
  }
  const bool gaitGone = !(weight > 0.0f);
  const glm::mat4 modelFromWorld = glm::inverse(worldFromModel);
  for (int f = 0; f < 2; ++f) {
    Foot& foot = feet_[f];
    const LimbIk& leg = legs_[f];
    const int joint = feet_joints_[f];
    const glm::vec3 animated(modelMatrixOf(skeleton, pose, joint)[3]);
    // Once the gait is gone (the character stopped) the feet ease into the posture's stance.
    const bool contact = !gaitGone && animated.y <= floor[f] + settings.contactHeight;
    if (contact && !foot.locked) {
      foot.locked = true;
      foot.lockWorld = glm::vec3(worldFromModel * glm::vec4(animated, 1.0f));
    }
    glm::vec3 target = animated;
    if (foot.locked) {
      target = glm::vec3(modelFromWorld * glm::vec4(foot.lockWorld, 1.0f));
      target.y = animated.y;  // the foot keeps its animated height: it still rolls heel to toe
      if (!contact) {        // lift-off (or stop): fade the correction out from here
        foot.locked = false;
        foot.releaseOffset = target - animated;
        foot.release = 1.0f;
        // A foot still on the ground eases over at most kEaseSpeed (0.4 m/s, below the
        // 0.5 m/s where a grounded foot is seen to skate); a lifted one in releaseSeconds.
        const float distance = glm::length(foot.releaseOffset);
        foot.releaseSeconds = gaitGone ? std::max(settings.releaseSeconds, distance / kEaseSpeed) : settings.releaseSeconds;
      }
    }
    if (!foot.locked) {
      if (foot.release <= 0.0f) continue;
      foot.release = foot.releaseSeconds > 0.0f ? std::max(0.0f, foot.release - dt / foot.releaseSeconds) : 0.0f;
      target = animated + foot.releaseOffset * foot.release;
    }
    // The knee bends the way it does now: the pole is in front of the current knee.
    const glm::vec3 knee(modelMatrixOf(skeleton, pose, leg.lower)[3]);
    const glm::vec3 pole = knee + (knee - 0.5f * (glm::vec3(modelMatrixOf(skeleton, pose, leg.upper)[3]) + animated));
    const float w = 1.0f;  // a planted foot stays planted however far the gait has blended in
    const float miss = solveTwoBoneIk(skeleton, pose, leg, target, pole, w, settings.ik);
    if (std::isfinite(miss)) residual_ = std::max(residual_, miss);
    if (!leg.endIsDescendant) {
      // A detached foot (an IK target in its file, RobotExpressive): put it where the leg now ends.
      const int parent = skeleton.parents[static_cast<std::size_t>(joint)];
      const glm::mat4 parentModel = modelMatrixOf(skeleton, pose, parent);
      const glm::vec3 reached = limbEndModel(skeleton, pose, leg);
      const glm::vec3 local(glm::inverse(parentModel) * glm::vec4(reached, 1.0f));
      Transform& t = pose[static_cast<std::size_t>(joint)];
      t.translation = glm::mix(t.translation, local, w);
    }
  }
}

}  // namespace marionette
