// What a gaze or a pointing aims at, resolved from a BehaviorTarget: a world
// point (metres), a character (a joint the behavior picks, e.g. the head for a
// gaze) or a joint of one. A character target is looked up again before every
// frame (Scene::update reads all of them from the last frame first, so the
// order of characters and threads does not change the result).
#pragma once
#include <functional>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "marionette/behavior/behavior_parameters.hpp"

namespace marionette {

struct SpatialTarget {
  glm::vec3 point{0.0f};   // the world target when `character` is empty
  std::string character;   // a character's name, and optionally one of its joints
  std::string joint;
  int jointIndex = -1;     // in the target character's skeleton; -1: 1.6 m above its root
  // A character target as found before this frame's updates.
  glm::vec3 resolvedPoint{0.0f};
  bool resolvedKnown = false;

  [[nodiscard]] bool external() const noexcept { return !character.empty(); }
  // The world point to aim at this frame, and whether it is known (false for a
  // target character that has left the scene: hold the current direction).
  [[nodiscard]] glm::vec3 world() const noexcept { return external() ? resolvedPoint : point; }
  [[nodiscard]] bool known() const noexcept { return !external() || resolvedKnown; }
};

// Answers the joint index of `joint` in the character named `character`, or the
// behavior's default joint of that character when `joint` is empty (-1: none, or the
// name is a scene object: a place without joints); -2 when the scene has no such
// character or object; -3 when it names an object and a joint.
using TargetJointFinder = std::function<int(std::string_view character, std::string_view joint)>;

// Resolves `target` into `out`. Empty when it is usable, else why not, naming the
// behavior (`what`, e.g. "gaze") and the target: none, a point that is not
// finite, an unknown character or joint.
[[nodiscard]] std::string resolveSpatialTarget(const BehaviorTarget& target, std::string_view what,
                                               const TargetJointFinder& findJoint, SpatialTarget& out);
// A target as messages quote it: "x y z" (%g) or "name" / "name:joint".
[[nodiscard]] std::string describeTarget(const BehaviorTarget& target);

}  // namespace marionette
