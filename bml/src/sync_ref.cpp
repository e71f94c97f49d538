#include "marionette/bml/sync_ref.hpp"

#include "marionette/core/float_chars.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>
#include <vector>

namespace marionette::bml {

namespace {
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

bool isIdChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
}

// A number at `i` (digits, optional fraction, optional exponent); advances `i`.
std::optional<double> readNumber(std::string_view s, std::size_t& i) {
  const std::size_t begin = i;
  while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.')) ++i;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    if (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) {
      i = j;
      while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    }
  }
  if (i == begin) return std::nullopt;
  double v = 0.0;
  auto [ptr, ec] = floatFromChars(s.data() + begin, s.data() + i, v);
  if (ec != std::errc() || ptr != s.data() + i || !std::isfinite(v)) return std::nullopt;
  return v;
}

SyncRefParse fail(std::string message, std::size_t column) {
  SyncRefParse r;
  r.error = std::move(message);
  r.errorColumn = static_cast<int>(column);
  return r;
}
}  // namespace

std::string SyncRef::toString() const {
  std::ostringstream out;
  if (absolute) {
    out << offset;
    return out.str();
  }
  if (!block.empty()) out << block << ':';
  out << behavior << ':' << syncPoint;
  if (repetition > 0) out << ':' << repetition;
  if (offset > 0) out << '+' << offset;
  if (offset < 0) out << offset;
  return out.str();
}

SyncRefParse parseSyncRef(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size() && isSpace(text[i])) ++i;
  std::size_t end = text.size();
  while (end > i && isSpace(text[end - 1])) --end;
  const std::string_view s = text.substr(0, end);
  if (i == s.size()) return fail("empty sync reference", i);

  SyncRef ref;
  if (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.' ||
      ((s[i] == '-' || s[i] == '+') && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
    // An absolute time, possibly with an offset chain ("2+1").
    const bool negative = s[i] == '-';
    if (s[i] == '-' || s[i] == '+') ++i;
    auto v = readNumber(s, i);
    if (!v) return fail("expected a number", i);
    ref.absolute = true;
    ref.offset = negative ? -*v : *v;
  } else {
    // Colon-separated identifiers: behavior:sync, block:behavior:sync, + an optional repetition.
    std::vector<std::string> parts;
    for (;;) {
      const std::size_t begin = i;
      while (i < s.size() && isIdChar(s[i]) && !((s[i] == '-') && i > begin && false)) {
        // '-' inside ids is allowed, but "sync-2" means an offset: stop at '-' followed by a number.
        if (s[i] == '-' && i + 1 < s.size() && (std::isdigit(static_cast<unsigned char>(s[i + 1])) || s[i + 1] == '.'))
          break;
        ++i;
      }
      if (i == begin) return fail("expected an identifier", i);
      parts.emplace_back(s.substr(begin, i - begin));
      if (i < s.size() && s[i] == ':') {
        ++i;
        continue;
      }
      break;
    }
    // A trailing all-digit part is a repetition index ("beat1:stroke:2").
    if (parts.size() >= 3 && std::all_of(parts.back().begin(), parts.back().end(),
                                         [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
      // from_chars, not stoi: a 100-digit index must be an error, not an exception (found by libFuzzer).
      const std::string& digits = parts.back();
      int rep = 0;
      auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), rep);
      if (ec != std::errc() || ptr != digits.data() + digits.size() || rep < 1 || rep > 100000)
        return fail("repetition index must be a whole number from 1 to 100000", i);
      ref.repetition = rep;
      parts.pop_back();
    }
    if (parts.size() == 2) {
      ref.behavior = parts[0];
      ref.syncPoint = parts[1];
    } else if (parts.size() == 3) {
      ref.block = parts[0];
      ref.behavior = parts[1];
      ref.syncPoint = parts[2];
    } else {
      return fail(parts.size() < 2 ? "expected behavior:syncPoint" : "too many ':' parts (expected [block:]behavior:sync)",
                  0);
    }
  }
  // Offset chain.
  while (i < s.size()) {
    while (i < s.size() && isSpace(s[i])) ++i;
    if (i == s.size()) break;
    if (s[i] != '+' && s[i] != '-') return fail(std::string("unexpected '") + s[i] + "'", i);
    const bool minus = s[i] == '-';
    ++i;
    while (i < s.size() && isSpace(s[i])) ++i;
    auto v = readNumber(s, i);
    if (!v) return fail("expected a number after the sign", i);
    ref.offset += minus ? -*v : *v;
  }
  SyncRefParse r;
  r.ref = std::move(ref);
  return r;
}

}  // namespace marionette::bml
