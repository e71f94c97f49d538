// Saccades (issue 24; SmartBody's <saccade>): the rapid eye movements between fixations,
// added on the eye joints over whatever the gaze does. Either one saccade (a magnitude
// toward a direction, then held until the request ends) or a model that runs until a later
// saccade request replaces or finishes it: Talk, Listen or Think, after Lee, Badler and
// Badler, "Eyes Alive" (SIGGRAPH 2002), as SmartBody configures it: a direction from eight
// 45-degree bins with the mode's shares, a magnitude from an exponential law (mean 5 degrees)
// cut at the mode's limit, a duration of 25 ms + 2.4 ms per degree, and the eyes going away
// and back to the gaze in turn, holding each for a time drawn from the mode's interval.
// Deterministic: the random draws come from the request id, and each frame only advances
// the state to the scene time. Per frame: no allocation.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct SaccadeState {
  SaccadeMode mode = SaccadeMode::None;
  int eye[2] = {-1, -1};             // left, right (-1: the rig lacks it)
  int head = -1;                     // the eyes turn in its frame; -1: the model frame
  glm::quat headRest{1.0f, 0.0f, 0.0f, 0.0f};  // its rest model rotation
  glm::vec3 left{1.0f, 0.0f, 0.0f};  // the character's left at rest (RigJoints::leftAxis)
  // The saccade in progress: from -> to (yaw left +, pitch down +; radians) over
  // [start, start + duration] on the scene clock.
  glm::vec2 from{0.0f}, to{0.0f};
  double start = 0.0, duration = 0.0;
  double next = 0.0;                 // the model's next saccade
  std::uint64_t random = 0;          // splitmix64 state
  bool away = false;                 // the model's eyes are off the gaze now
};

// Binds a saccade request (SaccadeParameters). Empty when it can be performed, else why
// not (a character without eye joints; a magnitude out of range is clamped with a warning).
// A `finish` request binds to nothing: it ends earlier models by replacing them.
[[nodiscard]] std::string bindSaccade(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                                      SaccadeState& state, std::string& warning);

// The eyes' offset at `clock` (yaw, pitch, radians), advancing the model's draws to it.
[[nodiscard]] glm::vec2 advanceSaccade(SaccadeState& state, double clock) noexcept;

// One frame: advances to `clock` and turns the eyes by the offset times `weight`.
void updateSaccade(SaccadeState& state, double clock, float weight, const Skeleton& skeleton,
                   std::span<Transform> pose) noexcept;

}  // namespace marionette
