// Procedural head movements (BML <head>): a rotation in the character's frame (+X to its left,
// +Y up, +Z forward), added over whatever the layers and clip behaviors put on the neck and
// head, timed by the request's stroke phases (one per repetition), or held from ready to relax.
//
// The catalogue (docs/behaviors.md, "Head movements"), angles at amount 1:
//   NOD     25 degrees down and back, per stroke
//   SHAKE   30 degrees, one turn each way per stroke
//   TILT    20 degrees of roll and back, per stroke
//   TOSS    15 degrees of roll and back, per stroke: SmartBody's sideways toss
//   WIGGLE   8 degrees down and up twice per stroke: small quick nods
//   WAGGLE  10 degrees of roll each way twice per stroke: side to side
//   Orient  a held direction (Greta's head signals), HeadParameters::orientDegrees
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/behavior/behavior_parameters.hpp"  // HeadLexeme
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

enum class HeadShape : std::uint8_t {
  RiseFall,   // to the peak at the stroke, back by the stroke's end
  Oscillate,  // `cycles` turns each way within each stroke, zero velocity at its ends
  Hold,       // to the direction by ready, held until relax, back by end
};
struct HeadMove {
  glm::vec3 degrees{0.0f};  // about +X (down), +Y (to the character's left), +Z (roll to its right)
  HeadShape shape = HeadShape::RiseFall;
  int cycles = 1;
};
// A lexeme's move (Orient: the parameters' direction).
[[nodiscard]] HeadMove headMove(const HeadParameters& parameters) noexcept;

// Peak angle at amount 1, radians, and the model-frame axis of a single-axis lexeme.
[[nodiscard]] float headPeakAngle(HeadLexeme lexeme) noexcept;
[[nodiscard]] glm::vec3 headAxis(HeadLexeme lexeme) noexcept;

// One stroke phase, scene seconds.
struct HeadStroke {
  double start = 0.0, peak = 0.0, end = 0.0;
};
// A held move's phases, scene seconds.
struct HeadPhases {
  double start = 0.0, ready = 0.0, relax = 0.0, end = 0.0;
};

// The move's shape at time t, in [-1, 1]: 0 outside its strokes (or phases). A rise and fall
// eases to 1 at the stroke and back by its end; an oscillation turns one way then the other;
// a hold eases to 1 by ready and back from relax to end.
[[nodiscard]] float headShape(const HeadMove& move, std::span<const HeadStroke> strokes, const HeadPhases& phases,
                              double t) noexcept;
[[nodiscard]] float headShape(HeadLexeme lexeme, std::span<const HeadStroke> strokes, double t) noexcept;

// What a body can do (docs/behaviors.md, "Head movements"): a stroke lasts at least
// kMinHeadStrokeSeconds (faster repetitions are thinned: merged), and the head turns at most
// kMaxHeadDegreesPerSecond (a rise or a return too quick for its angle is slowed: the peak, or a
// hold's ready and relax, moves; where there is no room, the angle is made smaller). Returns the
// amount to use, the strokes and phases changed in place; `warning` says what was changed.
inline constexpr double kMinHeadStrokeSeconds = 0.15;
inline constexpr double kMaxHeadDegreesPerSecond = 400.0;
[[nodiscard]] float fitHeadToABody(const HeadMove& move, float amount, std::vector<HeadStroke>& strokes,
                                   HeadPhases& phases, std::string& warning);

// The rotation of a move's angles (radians, about +X, +Y, +Z): yaw, then pitch, then roll.
[[nodiscard]] glm::quat headRotation(const glm::vec3& radians) noexcept;

// Rotates joint `joint` of the local pose by `delta`, given in the model frame
// (rootTransform included), by conjugating with the joint's parent model rotation.
void rotateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::quat& delta) noexcept;
// Moves joint `joint` of the local pose by `delta`, a model-frame offset (rootTransform
// included: the parent's whole model matrix, scale too, takes it to the joint's parent frame).
void translateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::vec3& delta) noexcept;

}  // namespace marionette
