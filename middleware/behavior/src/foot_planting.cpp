#include "marionette/behavior/foot_planting.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/animation/pose.hpp"

namespace marionette {

namespace {
constexpr float kEaseSpeed = 0.4f;  // m/s
constexpr float kPi = 3.14159265f;
// A catch-up step rises to this fraction of its length at mid-step, so that the
// foot is clear of the ground while it moves (a quarter let small steps at a
// stop shuffle along the ground), and moves across in the middle of the step,
// from kStepLiftOff to 1 - kStepLiftOff of its time: up first, down last.
constexpr float kStepLift = 0.5f;
constexpr float kStepLiftOff = 0.2f;
// Sine of the knee angle above which the animated leg's bend axis is measured
// (about 3 degrees): below it thigh x shin is mostly rounding.
constexpr float kHingeMinSine = 0.05f;

// The animated leg's bend axis in the upper joint's frame, or zero when the leg
// is too straight to tell.
glm::vec3 measureHinge(const glm::mat4& upperModel, const glm::vec3& knee, const glm::vec3& end) noexcept {
  const glm::vec3 hip(upperModel[3]);
  const glm::vec3 thigh = knee - hip, shin = end - knee;
  const glm::vec3 axis = glm::cross(thigh, shin);
  const float lengths = glm::length(thigh) * glm::length(shin);
  if (!(glm::length(axis) > kHingeMinSine * lengths)) return glm::vec3(0.0f);
  const glm::mat3 linear(upperModel);
  const float det = glm::determinant(linear);
  if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return glm::vec3(0.0f);
  const glm::vec3 local = glm::inverse(linear) * axis;
  const float n = glm::length(local);
  return n > 0.0f && std::isfinite(n) ? local / n : glm::vec3(0.0f);
}
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
  auto toModel = [&](const glm::vec3& world) { return glm::vec3(modelFromWorld * glm::vec4(world, 1.0f)); };
  auto toWorld = [&](const glm::vec3& model) { return glm::vec3(worldFromModel * glm::vec4(model, 1.0f)); };
  for (int f = 0; f < 2; ++f) {
    Foot& foot = feet_[f];
    const LimbIk& leg = legs_[f];
    const int joint = feet_joints_[f];
    const glm::vec3 animated(modelMatrixOf(skeleton, pose, joint)[3]);
    // Once the gait is gone (the character stopped) the feet ease into the posture's stance.
    const bool contact = !gaitGone && animated.y <= floor[f] + settings.contactHeight;
    if (contact && !foot.locked && !foot.stepping) {
      foot.locked = true;
      foot.lockWorld = toWorld(animated);
    }
    if (!foot.locked && !foot.stepping && foot.release <= 0.0f) continue;  // the animation's own
    // The animated leg, before the correction. Its knee's bend axis is measured
    // whenever the leg is bent (a hinge: the axis stays put in the thigh's frame,
    // so one from an earlier step still holds when the leg is straight now).
    const glm::mat4 upperModel = modelMatrixOf(skeleton, pose, leg.upper);
    const glm::vec3 hip(upperModel[3]);
    const glm::vec3 knee(modelMatrixOf(skeleton, pose, leg.lower)[3]);
    // Where the leg ends as animated: the foot joint itself, except for a detached
    // foot, which the pose may hold some way off the shin (RobotExpressive: up to
    // 5 cm in its clips, up to 19 cm while the gait blends over the idle).
    const glm::vec3 animatedEnd = limbEndModel(skeleton, pose, leg);
    if (const glm::vec3 h = measureHinge(upperModel, knee, animatedEnd); h != glm::vec3(0.0f)) foot.hinge = h;
    const float legLength = glm::length(knee - hip) + glm::length(animatedEnd - knee);
    glm::vec3 target = animated;
    bool stepStarts = false;
    if (foot.locked) {
      target = toModel(foot.lockWorld);
      target.y = animated.y;  // the foot keeps its animated height: it still rolls heel to toe
      if (contact && glm::length(animatedEnd + (target - animated) - hip) > legLength + settings.maxOverreach) {
        // The lock is out of the leg's reach: the body went on without the foot (the
        // gait blending out at a stop leaves a planted foot behind; an idle stance the
        // gait blended in over did too). Held, the straight leg would drag the foot
        // after the body and up off the ground (up to 0.5 m, 0.68 m from its lock);
        // released to the animation, the foot would slide along the ground to where
        // the clip has it. It takes a step there instead. The leg's length, not the
        // IK's miss: the soft reach leaves a foot short by design (up to 11 cm at a
        // softness of 0.2) well within reach.
        foot.locked = false;
        foot.stepping = true;
        stepStarts = true;
        foot.step = 0.0f;
        foot.stepFrom = foot.lockWorld;
        foot.stepTo = toWorld(animated);
        foot.stepLift = kStepLift * std::hypot(target.x - animated.x, target.z - animated.z);
        ++steps_;
      } else if (!contact) {  // lift-off (or stop): fade the correction out from here
        foot.locked = false;
        foot.releaseOffset = target - animated;
        foot.release = 1.0f;
        // A foot still on the ground eases over at most kEaseSpeed (0.4 m/s, below the
        // 0.5 m/s where a grounded foot is seen to skate); a lifted one in releaseSeconds.
        const float distance = glm::length(foot.releaseOffset);
        foot.releaseSeconds = gaitGone ? std::max(settings.releaseSeconds, distance / kEaseSpeed) : settings.releaseSeconds;
      }
    }
    if (foot.stepping) {
      // Up on an arc; across, from where it stood to the animated place, while it is
      // up; the place it comes down on is held from the top of the arc, so that it
      // does not slide in, and it plants there at the end. If the animation lifts
      // the foot meanwhile (the step began near the end of its stance), the step
      // ends there and the foot is released to the animation as at a lift-off.
      // It leaves the ground on the frame after the one it left its lock on, so a
      // step is never shorter than a frame (at long frame steps it would otherwise
      // go from one lock to the next unseen).
      if (!stepStarts)
        foot.step = settings.stepSeconds > 0.0f ? std::min(1.0f, foot.step + dt / settings.stepSeconds) : 1.0f;
      if (foot.step <= 0.5f) foot.stepTo = toWorld(animated);
      const float u = std::clamp((foot.step - kStepLiftOff) / (1.0f - 2.0f * kStepLiftOff), 0.0f, 1.0f);
      target = glm::mix(toModel(foot.stepFrom), toModel(foot.stepTo), u * u * (3.0f - 2.0f * u));
      target.y = animated.y + foot.stepLift * std::sin(kPi * foot.step);
      if (!contact) {
        foot.stepping = false;
        foot.releaseOffset = target - animated;
        foot.release = 1.0f;
        foot.releaseSeconds = settings.releaseSeconds;
      } else if (foot.step >= 1.0f) {
        foot.stepping = false;
        foot.locked = true;
        foot.lockWorld = toWorld(target);
      }
    } else if (!foot.locked) {
      foot.release = foot.releaseSeconds > 0.0f ? std::max(0.0f, foot.release - dt / foot.releaseSeconds) : 0.0f;
      target = animated + foot.releaseOffset * foot.release;
    }
    // The correction moves the leg's end as much as it moves the foot, so that
    // no correction leaves the animated pose as it is: a detached foot's offset
    // from the shin is the clip's, and the leg does not jump by that offset when
    // the foot locks or when the release fade ends.
    const glm::vec3 endTarget = animatedEnd + (target - animated);
    // The knee bends about its hinge as the thigh now carries it: for the chain
    // to bend about axis h the knee goes toward u x h, u the line to the target.
    // (A pole from the animated knee alone flips across that line when the leg
    // is nearly straight and the target is not where the animated foot is.)
    // Before any bend was seen, the current knee's side.
    glm::vec3 pole = knee;
    if (foot.hinge != glm::vec3(0.0f))
      pole = hip + glm::cross(endTarget - hip, glm::mat3(upperModel) * foot.hinge);
    const float miss = solveTwoBoneIk(skeleton, pose, leg, endTarget, pole, 1.0f, settings.ik);
    if (std::isfinite(miss)) residual_ = std::max(residual_, miss);
    if (!leg.endIsDescendant) {
      // A detached foot (an IK target in its file, RobotExpressive) goes with the
      // leg's end, at its animated offset from it.
      const int parent = skeleton.parents[static_cast<std::size_t>(joint)];
      const glm::mat4 parentModel = modelMatrixOf(skeleton, pose, parent);
      const glm::vec3 placed = limbEndModel(skeleton, pose, leg) + (animated - animatedEnd);
      pose[static_cast<std::size_t>(joint)].translation = glm::vec3(glm::inverse(parentModel) * glm::vec4(placed, 1.0f));
    }
  }
}

}  // namespace marionette
