// Gesture names of other realizers' vocabularies (Greta's greet_*, *deictic_self, INFORM_GES_*;
// SmartBody's METAPHORIC, ChrX@..._Beat*; AsapRealizer's) to the procedural gestures
// (behavior/procedural_gesture.hpp): a gesture whose lexeme names no clip of the character and
// is not in its profile's "gestures" map plays the procedural gesture its name maps to, with a
// warning naming the mapping (docs/controllers.md, "Procedural gestures").
//
// A vocabulary is JSON: {"pattern": "LEXEME", ...}, patterns with * (any run of characters) and ?
// (one character), matched in any case; the most specific pattern that matches wins (the most
// characters other than * and ?; on a tie, the longer pattern, then the first in alphabetical
// order: the order of the keys never matters). The shipped one is
// assets/gestures/vocabulary.json, built in; a character profile's "gestureVocabulary" (the same
// form) is looked up first.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette {

struct GestureVocabularyEntry {
  std::string pattern;  // as written
  std::string lexeme;   // upper case
};
using GestureVocabulary = std::vector<GestureVocabularyEntry>;

// The shipped vocabulary (parsed once).
[[nodiscard]] const GestureVocabulary& defaultGestureVocabulary();

// A vocabulary from JSON text; a key "comment" is skipped, entries that are not a non-empty
// pattern with a non-empty string are warnings in `diagnostics` naming `name` and the key.
[[nodiscard]] GestureVocabulary parseGestureVocabulary(std::string_view json, const std::string& name,
                                                       Diagnostics& diagnostics);

// Whether `name` matches `pattern` (* and ?, any case).
[[nodiscard]] bool gesturePatternMatches(std::string_view pattern, std::string_view name) noexcept;

// The most specific entry matching `name`, or null.
[[nodiscard]] const GestureVocabularyEntry* matchGestureVocabulary(std::string_view name,
                                                                   const GestureVocabulary& vocabulary) noexcept;

}  // namespace marionette
