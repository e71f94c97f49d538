// Other realizers' gesture names to the procedural set (gesture_vocabulary.hpp says how).
#include "marionette/rig/gesture_vocabulary.hpp"

#include <algorithm>
#include <cctype>

#include <nlohmann/json.hpp>

#include "default_gesture_vocabulary.hpp"  // generated from assets/gestures/vocabulary.json

namespace marionette {

namespace {

char upper(char c) noexcept { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); }

std::size_t literalCharacters(std::string_view pattern) noexcept {
  return static_cast<std::size_t>(std::count_if(pattern.begin(), pattern.end(), [](char c) { return c != '*' && c != '?'; }));
}

}  // namespace

bool gesturePatternMatches(std::string_view pattern, std::string_view name) noexcept {
  // Iterative glob with one backtrack point (the last *): linear in practice, never recursive.
  std::size_t p = 0, n = 0, star = std::string_view::npos, resume = 0;
  while (n < name.size()) {
    if (p < pattern.size() && (pattern[p] == '?' || upper(pattern[p]) == upper(name[n]))) {
      ++p, ++n;
    } else if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      resume = n;
    } else if (star != std::string_view::npos) {
      p = star + 1;
      n = ++resume;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

const GestureVocabularyEntry* matchGestureVocabulary(std::string_view name, const GestureVocabulary& vocabulary) noexcept {
  const GestureVocabularyEntry* best = nullptr;
  for (const GestureVocabularyEntry& e : vocabulary) {
    if (!gesturePatternMatches(e.pattern, name)) continue;
    if (!best) {
      best = &e;
      continue;
    }
    const std::size_t a = literalCharacters(e.pattern), b = literalCharacters(best->pattern);
    if (a > b || (a == b && (e.pattern.size() > best->pattern.size() ||
                             (e.pattern.size() == best->pattern.size() && e.pattern < best->pattern))))
      best = &e;
  }
  return best;
}

GestureVocabulary parseGestureVocabulary(std::string_view json, const std::string& name, Diagnostics& diagnostics) {
  GestureVocabulary out;
  const nlohmann::json doc = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    diagnostics.error(name, "a gesture vocabulary is a JSON object of \"pattern\": \"LEXEME\"");
    return out;
  }
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    if (it.key() == "comment") continue;
    if (it.key().empty() || !it->is_string() || it->get<std::string>().empty()) {
      diagnostics.warning(name, "gesture vocabulary entry '" + it.key() + "': expected \"pattern\": \"LEXEME\"; ignored");
      continue;
    }
    std::string lexeme = it->get<std::string>();
    std::transform(lexeme.begin(), lexeme.end(), lexeme.begin(), upper);
    out.push_back({it.key(), std::move(lexeme)});
  }
  return out;
}

const GestureVocabulary& defaultGestureVocabulary() {
  static const GestureVocabulary shipped = [] {
    Diagnostics ignored;  // the shipped file is checked by a test (GestureVocabulary.*)
    return parseGestureVocabulary(kDefaultGestureVocabularyJson, "assets/gestures/vocabulary.json", ignored);
  }();
  return shipped;
}

}  // namespace marionette
