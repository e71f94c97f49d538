// BML attributes read into the middleware's typed behavior parameters
// (behavior/behavior_parameters.hpp): BML's spelling of targets ("x y z",
// "Bob", "Bob:Head"), lexemes, influences, modes, manners, degrees and rates
// lives here and nowhere below. A value that cannot be read is either replaced
// by its default with a warning (amount, influence, offset, mode, manner, speed,
// rate) or makes the behavior impossible with an error (no lexeme, a locomotion
// target that is not a place); the middleware checks ranges of the values it gets.
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/bml/document.hpp"

namespace marionette::bml {

struct ReadParameters {
  BehaviorParameters parameters{};  // monostate when `error` is set or the kind has none
  std::string error;                // why the behavior cannot be realized ("" = none)
  std::string warning;              // values replaced by defaults, joined with "; "
};

// The typed parameters of `behavior` as a request of `kind`.
[[nodiscard]] ReadParameters readParameters(const Behavior& behavior, BehaviorKind kind);

// A BML target: three numbers are a world point, anything else a character's
// name, optionally with ":joint"; empty text is no target.
[[nodiscard]] BehaviorTarget readTarget(std::string_view text);
// Case-insensitive BML names.
[[nodiscard]] std::optional<HeadLexeme> headLexemeFromName(std::string_view name) noexcept;
// A head direction as Greta names them (UP, DOWN_ASIDE_RIGHT, TILT_LEFT, ...; any case, words
// split by '_', '-' or spaces): degrees about the character's +X (down), +Y (left), +Z (roll
// right) for HeadLexeme::Orient; nothing for a name that is not one.
[[nodiscard]] std::optional<glm::vec3> headDirectionFromName(std::string_view name);
[[nodiscard]] std::optional<GazeInfluence> gazeInfluenceFromName(std::string_view name) noexcept;

}  // namespace marionette::bml
