// What a character reports: what became of a behavior request, where a locomotion
// stands, and what each controller cost in the last frame.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

namespace marionette {

// What became of a behavior request (Character::addBehavior).
struct BehaviorResult {
  bool added = false;     // on the timeline: it has a channel, a weight envelope, an owner
  bool realized = false;  // some controller moves the body for it
  std::string message;    // why not added, or why not realized; empty when both hold
};

// Where a locomotion request stands (Character::locomotionStatus).
struct LocomotionStatus {
  enum class State : std::uint8_t { Unknown, Pending, Moving, Done, Superseded } state = State::Unknown;
  double doneTime = -1.0;  // character clock at arrival (and final facing), for State::Done
};

// How far the last update moved and turned a character (root motion and locomotion; not
// setPosition / setHeading between updates): world metres and radians about +Y.
struct PlacementDelta {
  glm::vec3 translation{0.0f};
  float turn = 0.0f;  // in [-pi, pi]
};

// The behavior controllers, in the order a frame runs them (DESIGN.md): clip behaviors
// (postures) over the layers, locomotion, upper-body clips (gestures), breathing (added on the
// chest before the aiming controllers, which then aim from where it leaves the body), gaze,
// head movements added on top of it, saccades, procedural gestures, pointing and reaching
// (after the gaze has turned the torso, so the arms move from where it ends up), face
// expressions, blinks (over the face's lids), speech. One list: each frame's passes and the
// stats below are indexed by it.
enum class Controller : std::uint8_t {
  ClipBehaviors, Locomotion, UpperBodyClips, Breathing, Gaze, Head, Saccade, Gesture, Pointing, Reach, Face, Blink, Speech
};
inline constexpr std::size_t kControllerCount = static_cast<std::size_t>(Controller::Speech) + 1;
[[nodiscard]] std::string_view controllerName(Controller controller) noexcept;  // "clip behaviors", ...

struct CharacterStats {
  double lastUpdateMicros = 0.0;  // wall time of the last update (when stats are on)
  int activeLayers = 0;           // clip layers that exist now
  bool sampledDirect = false;     // the last frame took the one-clip fast path
  // Per controller: whether it has run at least once (controllers exist only while a
  // behavior uses them) and its wall time in the last frame (while the scene's stats are on).
  std::array<bool, kControllerCount> controllerUsed{};
  std::array<double, kControllerCount> controllerMicros{};
  [[nodiscard]] bool used(Controller c) const noexcept { return controllerUsed[static_cast<std::size_t>(c)]; }
  [[nodiscard]] double micros(Controller c) const noexcept { return controllerMicros[static_cast<std::size_t>(c)]; }
};

}  // namespace marionette
