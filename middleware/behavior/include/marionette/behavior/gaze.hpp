// Gaze: turn a joint chain (eyes, head, neck, spine) toward a target, tracking
// it smoothly. The chain's yaw and pitch follow the target through an exactly
// integrated critically damped spring (stable and overshoot-free from rest for
// any dt, 0 to 1 s and beyond; a moving target is taken as a ramp between this
// frame's and the last frame's value, exact for that) with an angular speed limit; the angle is shared
// along the chain in proportion to each joint's limit, so all reach their limits
// together; the eyes take what the chain has not reached yet (eyes lead, the
// head follows) within their own limits.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "marionette/behavior/behavior_parameters.hpp"  // GazeInfluence
#include "marionette/behavior/spatial_target.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct RigJoints;

struct GazeSettings {
  float timeConstant = 0.12f;     // seconds: 1/omega of the spring (about 95 % of a step in 4 of them)
  float maxSpeed = 6.0f;          // rad/s for the chain (a fast head turn is about 5 to 7 rad/s)
  float eyeMaxSpeed = 15.0f;      // rad/s (saccades are faster still; this keeps them visible)
  // Per-joint limits, radians (yaw either way, pitch either way).
  float eyeYaw = 0.61f, eyePitch = 0.44f;     // 35, 25 degrees
  float headYaw = 1.05f, headPitch = 0.61f;   // 60, 35
  float neckYaw = 0.70f, neckPitch = 0.44f;   // 40, 25
  float spineYaw = 0.26f, spinePitch = 0.09f; // 15, 5 per spine joint
  float hipsYaw = 0.52f;                       // 30 (WHOLE only)
};

// The yaw and pitch of a direction in the character's frame (+Z forward, +Y up):
// yaw > 0 turns left (toward +X), pitch > 0 looks down. `hint` picks the side for a
// target straight behind (the yaw's 2*pi branch closest to it), so a target that
// wobbles across the back does not flip the gaze from one side to the other.
struct YawPitch {
  float yaw = 0.0f, pitch = 0.0f;
};
[[nodiscard]] YawPitch yawPitchOf(const glm::vec3& direction, float hint) noexcept;

// A damped angle: position and velocity.
struct DampedAngle {
  float value = 0.0f, velocity = 0.0f;
  // Exact critically damped step toward `target` over dt (any dt >= 0), then the
  // speed limit on both the step and the velocity. Never NaN for finite input.
  void step(float target, float dt, float timeConstant, float maxSpeed) noexcept;
  // The same for a target moving linearly from `from` to `to` over the step: exact
  // for that motion (the spring's steady lag behind a ramp, 2 r / w, included),
  // so a moving target is followed to second order in dt (docs/accuracy.md).
  void stepRamp(float from, float to, float dt, float timeConstant, float maxSpeed) noexcept;
};

// Per-request gaze state (lives in the request's timeline entry).
struct GazeState {
  GazeInfluence influence = GazeInfluence::Neck;
  SpatialTarget target;         // a character without a joint: its head
  float offsetYaw = 0.0f, offsetPitch = 0.0f;  // radians (GazeParameters)
  bool useEyes = true;          // false for headDirectionShift: the head points, the eyes stay centred
  DampedAngle chainYaw, chainPitch, eyeYaw, eyePitch;
  float lastTarget[4] = {};     // the last frame's targets (chain yaw, pitch, eye yaw, pitch), for the ramp
  bool started = false;         // false until the first step (which has no last target)
  int restTopJoint = -1;        // the chain's top joint whose rest model rotation is cached below
  glm::quat restTop{1, 0, 0, 0};
};

// One frame of a gaze: steps the state toward `targetModel` (a model-frame point)
// over dt and turns the chain its influence selects, scaled by `weight`. The
// target is seen from between the eyes (else the head, else the neck); one
// closer than 1 mm, or an unknown one (`targetKnown` false: a target character
// that left the scene), keeps the current direction. Per-frame: no allocation.
void updateGaze(GazeState& state, const glm::vec3& targetModel, bool targetKnown, float weight,
                const GazeSettings& settings, const Skeleton& skeleton, const RigJoints& joints,
                std::span<Transform> pose, float dt) noexcept;

}  // namespace marionette
