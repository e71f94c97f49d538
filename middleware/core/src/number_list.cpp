#include "marionette/core/number_list.hpp"

#include "marionette/core/float_chars.hpp"

#include <charconv>
#include <cmath>

#include "marionette/core/text.hpp"

namespace marionette {

std::optional<std::vector<float>> parseNumberList(std::string_view text) {
  std::vector<float> out;
  const char* p = text.data();
  const char* end = p + text.size();
  auto separator = [](char c) { return c == ' ' || c == ',' || c == '\t' || c == '\n' || c == '\r'; };
  for (;;) {
    while (p < end && separator(*p)) ++p;
    if (p == end) break;
    // from_chars does not read "nan"/"inf" in every library: spell them out.
    const char* tokenEnd = p;
    while (tokenEnd < end && !separator(*tokenEnd)) ++tokenEnd;
    const std::string_view token(p, static_cast<std::size_t>(tokenEnd - p));
    const bool negative = !token.empty() && token.front() == '-';
    const std::string word = toUpper(negative || (!token.empty() && token.front() == '+') ? token.substr(1) : token);
    if (word == "NAN") {
      out.push_back(std::nanf(""));
    } else if (word == "INF" || word == "INFINITY") {
      out.push_back(negative ? -INFINITY : INFINITY);
    } else {
      float v = 0.0f;
      const char* first = !token.empty() && token.front() == '+' ? p + 1 : p;
      const auto [next, ec] = floatFromChars(first, tokenEnd, v);
      if (ec == std::errc::result_out_of_range) v = negative ? -INFINITY : INFINITY;
      else if (ec != std::errc() || next != tokenEnd) return std::nullopt;
      out.push_back(v);
    }
    p = tokenEnd;
  }
  return out;
}

}  // namespace marionette
