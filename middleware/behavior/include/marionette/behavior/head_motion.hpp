// Procedural head movements (BML head NOD, SHAKE, TILT): a rotation in the
// character's frame (+X right, +Y up, +Z forward), added over whatever the
// layers and clip behaviors put on the neck and head, timed by the request's
// stroke phases (one per repetition).
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "marionette/behavior/behavior_parameters.hpp"  // HeadLexeme
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// Peak angles at amount 1, radians: a nod dips 25 degrees, a shake turns 30, a tilt rolls 20.
[[nodiscard]] float headPeakAngle(HeadLexeme lexeme) noexcept;

// One stroke phase, scene seconds.
struct HeadStroke {
  double start = 0.0, peak = 0.0, end = 0.0;
};

// The movement's shape at time t, in [-1, 1]: 0 outside the strokes. A nod and
// a tilt rise smoothly to 1 at the stroke and fall back by its end; a shake
// turns one way then the other within each stroke (zero velocity at its ends).
[[nodiscard]] float headShape(HeadLexeme lexeme, std::span<const HeadStroke> strokes, double t) noexcept;

// The model-frame rotation axis of a lexeme (+X nods down, +Y turns left, +Z rolls).
[[nodiscard]] glm::vec3 headAxis(HeadLexeme lexeme) noexcept;

// Rotates joint `joint` of the local pose by `delta`, given in the model frame
// (rootTransform included), by conjugating with the joint's parent model rotation.
void rotateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::quat& delta) noexcept;

}  // namespace marionette
