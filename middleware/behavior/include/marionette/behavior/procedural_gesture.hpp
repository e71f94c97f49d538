// Gestures without clips (issue 24, 7): every humanoid whose profile (or joint map) names
// its arms can BEAT, POINT, WAVE, SHRUG, ... A lexeme is where the hands go, in the
// character's own frame (out from the shoulder, up, forward) and in arm lengths, at the
// BML phases: the hands rise to the lexeme's ready place during preparation (start to
// ready, the request's weight ramping in), move through the stroke (strokeStart, stroke,
// strokeEnd; repeated with BML repetitions), hold until relax and retract with the weight
// (relax to end). Two-bone IK places each hand, the elbow hanging out and back. The same
// numbers on any skeleton: RobotExpressive and Godette differ only in arm length.
// A clip of the lexeme's name, or the profile's "gestures" map, comes first (the mapping
// plays the clip instead).
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/behavior/two_bone_ik.hpp"

namespace marionette {

struct GestureState {
  int shape = -1;                  // into the lexeme table (procedural_gesture.cpp)
  bool arm[2] = {};                // left, right in use
  LimbIk limb[2];
  float armLength[2] = {};         // upper + lower, rest pose (m)
  glm::vec3 left{1.0f, 0.0f, 0.0f};  // the character's left, model frame (RigJoints::leftAxis)
  struct Stroke {
    double start = 0.0, peak = 0.0, end = 0.0;  // strokeStart, stroke, strokeEnd (scene times)
  };
  std::vector<Stroke> strokes;     // one per repetition, in time order (made at command time)
};

// The lexemes the set has, upper case (docs, messages, bml-check).
[[nodiscard]] std::span<const std::string_view> proceduralGestureLexemes() noexcept;
[[nodiscard]] bool hasProceduralGesture(std::string_view lexeme) noexcept;

// Binds a gesture request (GestureParameters) to the set. Empty when it can be performed,
// else why not (an unknown lexeme, listing the known ones; a character without arms);
// `warning` notes a hand the rig lacks.
[[nodiscard]] std::string bindProceduralGesture(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                                                GestureState& state, std::string& warning);

// One frame at scene time `clock`, blended by `weight` (the request's: it ramps in
// over the preparation and out over the retraction). Per-frame: no allocation.
void updateProceduralGesture(const GestureState& state, double clock, float weight, const Skeleton& skeleton,
                             std::span<Transform> pose) noexcept;

// Where the gesture puts a hand at `clock`, model frame, given the shoulder's model
// position (for tests and measurements).
[[nodiscard]] glm::vec3 proceduralGestureHand(const GestureState& state, int side, double clock,
                                              const glm::vec3& shoulder) noexcept;

}  // namespace marionette
