#include "marionette/core/float_chars.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <type_traits>

namespace marionette {
namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }
char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

// How many characters from p match `word` case-insensitively (all of it, or 0).
std::size_t matchWord(const char* p, const char* last, const char* word) {
  const std::size_t n = std::strlen(word);
  if (static_cast<std::size_t>(last - p) < n) return 0;
  for (std::size_t i = 0; i < n; ++i)
    if (lower(p[i]) != word[i]) return 0;
  return n;
}

// The length of the longest prefix from_chars would read, 0 if none: the grammar is
// checked here, so strtod never sees what from_chars would refuse (hex, '+', spaces).
std::size_t numberLength(const char* first, const char* last) {
  const char* p = first;
  if (p < last && *p == '-') ++p;
  if (std::size_t n = matchWord(p, last, "infinity"); n) return static_cast<std::size_t>(p - first) + n;
  if (std::size_t n = matchWord(p, last, "inf"); n) return static_cast<std::size_t>(p - first) + n;
  if (std::size_t n = matchWord(p, last, "nan"); n) {
    p += n;  // nan(chars): letters, digits and '_' in parentheses
    if (p < last && *p == '(') {
      const char* q = p + 1;
      while (q < last && (isDigit(*q) || (lower(*q) >= 'a' && lower(*q) <= 'z') || *q == '_')) ++q;
      if (q < last && *q == ')') p = q + 1;
    }
    return static_cast<std::size_t>(p - first);
  }
  const char* digits = p;
  while (p < last && isDigit(*p)) ++p;
  bool any = p > digits;
  if (p < last && *p == '.') {
    const char* fraction = ++p;
    while (p < last && isDigit(*p)) ++p;
    any = any || p > fraction;
  }
  if (!any) return 0;
  if (p < last && (*p == 'e' || *p == 'E')) {
    const char* q = p + 1;
    if (q < last && (*q == '+' || *q == '-')) ++q;
    const char* exponent = q;
    while (q < last && isDigit(*q)) ++q;
    if (q > exponent) p = q;  // "1e" reads as 1, as from_chars does
  }
  return static_cast<std::size_t>(p - first);
}

template <class T>
std::from_chars_result viaStrtod(const char* first, const char* last, T& value) noexcept {
  const std::size_t n = numberLength(first, last);
  if (n == 0) return {first, std::errc::invalid_argument};
  char small[64];
  std::string large;
  const char* text = small;
  try {
    if (n < sizeof small) {
      std::memcpy(small, first, n);
      small[n] = '\0';
    } else {
      large.assign(first, n);
      text = large.c_str();
    }
  } catch (...) {
    return {first, std::errc::not_enough_memory};
  }
  errno = 0;
  char* end = nullptr;
  // strtof for float: a double rounded again to float is not always the nearest float.
  T v;
  if constexpr (std::is_same_v<T, float>) v = std::strtof(text, &end);
  else v = std::strtod(text, &end);
  const bool rangeError = errno == ERANGE;
  // from_chars: out of range when the value overflows to infinity ("inf" itself sets no
  // ERANGE), or underflows to zero from a number that is not zero (a subnormal result is a
  // value: some C libraries set ERANGE for it anyway).
  const bool overflow = std::isinf(v) && rangeError;
  const bool underflow = v == T(0) && rangeError;
  if (overflow || underflow) return {first + n, std::errc::result_out_of_range};
  value = v;
  return {first + n, std::errc()};
}

}  // namespace

std::from_chars_result fromCharsViaStrtod(const char* first, const char* last, float& value) noexcept {
  return viaStrtod(first, last, value);
}
std::from_chars_result fromCharsViaStrtod(const char* first, const char* last, double& value) noexcept {
  return viaStrtod(first, last, value);
}

std::to_chars_result toCharsViaSnprintf(char* first, char* last, double value, std::chars_format format,
                                        int precision) noexcept {
  const char* spec = format == std::chars_format::fixed ? "%.*f" : format == std::chars_format::scientific ? "%.*e" : "%.*g";
  const std::ptrdiff_t room = last - first;
  char buffer[512];
  const int n = std::snprintf(buffer, sizeof buffer, spec, precision, value);
  if (n < 0 || n > room) return {last, std::errc::value_too_large};
  if (n < static_cast<int>(sizeof buffer)) {
    std::memcpy(first, buffer, static_cast<std::size_t>(n));
    return {first + n, std::errc()};
  }
  try {  // longer than the buffer (a large precision): once more, at its length
    std::string text(static_cast<std::size_t>(n) + 1, '\0');
    std::snprintf(text.data(), text.size(), spec, precision, value);
    std::memcpy(first, text.data(), static_cast<std::size_t>(n));
    return {first + n, std::errc()};
  } catch (...) {
    return {last, std::errc::value_too_large};
  }
}

}  // namespace marionette
