// Foot planting: while a foot of the gait is on the ground, keep it where it
// touched down and bend the leg to reach it (two-bone IK), so that feet do not
// slide when the steering, the speed blend or the sway move the body a little
// differently from the clip. A foot is on the ground while its animated height
// (model space) is within `contactHeight` of the gait's floor for that foot; it
// is locked at its world place (x, z) when it touches down, keeps its animated
// height (the foot still rolls), and on lift-off the correction fades out over
// `releaseSeconds`. A planted foot the leg can no longer reach (farther than the
// leg's length plus `maxOverreach`: the body went on while a blend between the
// gait and the posture carried the animated foot away) takes a catch-up step: it lifts, swings
// to where the animation has it and plants there, in `stepSeconds`, instead of
// being dragged by a straight leg. When the character stops (the gait's weight
// reaches 0) the planted feet ease to the posture's stance no faster than
// 0.4 m/s: a slow slide, below what reads as skating (a stop-step clip would do
// better; none of the assets has one). The knee bends about its hinge: the axis of the animated
// leg's bend, kept in the thigh's frame from the last frame the leg was bent, so
// a leg that straightens (a trailing leg at push-off) keeps its knee forward
// instead of flipping it. The correction (lock place minus animated place) moves
// the leg's end and the foot alike: a detached foot (an IK target that is not
// the shin's child) keeps its animated offset from the leg's end, and with no
// correction the pose is the animation's. Per-frame code: no allocation.
#pragma once
#include <span>

#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

struct FootPlantSettings {
  bool enabled = true;
  float contactHeight = 0.06f;   // m above the foot's floor
  float releaseSeconds = 0.12f;  // fade of the correction after lift-off
  // A planted foot farther from the hip than the leg's length plus maxOverreach
  // (m) is not held: it steps to where the animation has it, in stepSeconds, and
  // plants there.
  float maxOverreach = 0.05f;
  float stepSeconds = 0.25f;
  TwoBoneIkSettings ik;
};

class FootPlanter {
 public:
  FootPlanter(const Skeleton& skeleton, const RigJoints& joints);
  [[nodiscard]] bool usable() const noexcept { return legs_[0].upper >= 0 && legs_[1].upper >= 0; }

  // After the gait was blended into `pose`. `floor` is each foot's lowest model
  // height in the gait (left, right); `weight` the gait's weight over the posture
  // (planting fades with it); `worldFromModel` the character's placement this frame.
  void apply(const Skeleton& skeleton, std::span<Transform> pose, const glm::mat4& worldFromModel,
             const float floor[2], float weight, float dt, const FootPlantSettings& settings) noexcept;
  void reset() noexcept;
  [[nodiscard]] bool planted(int foot) const noexcept { return feet_[foot].locked; }
  // True while a foot is planted or easing back to the animation (the planter still has work).
  [[nodiscard]] bool active() const noexcept {
    return feet_[0].locked || feet_[1].locked || feet_[0].release > 0.0f || feet_[1].release > 0.0f ||
           feet_[0].stepping || feet_[1].stepping;
  }
  // True while a foot takes a catch-up step (its lock went out of the leg's reach).
  [[nodiscard]] bool stepping(int foot) const noexcept { return feet_[foot].stepping; }
  [[nodiscard]] int steps() const noexcept { return steps_; }  // catch-up steps taken since construction
  // Largest distance the IK left between a planted foot and its target last frame (m).
  [[nodiscard]] float lastResidual() const noexcept { return residual_; }

 private:
  struct Foot {
    bool locked = false;
    glm::vec3 lockWorld{0.0f};
    glm::vec3 releaseOffset{0.0f};  // model space, at lift-off
    float release = 0.0f;           // 1 at lift-off, down to 0
    float releaseSeconds = 0.0f;
    // The knee's bend axis (thigh x shin) in the upper joint's frame, from the last
    // frame the animated leg was bent; zero until then.
    glm::vec3 hinge{0.0f};
    // A catch-up step: from stepFrom (world) to the animated foot, lifted by stepLift at mid-step.
    bool stepping = false;
    glm::vec3 stepFrom{0.0f}, stepTo{0.0f};
    float step = 0.0f;  // progress, 0 to 1
    float stepLift = 0.0f;
  };
  LimbIk legs_[2];
  int feet_joints_[2] = {-1, -1};
  Foot feet_[2];
  float residual_ = 0.0f;
  int steps_ = 0;
};

}  // namespace marionette
