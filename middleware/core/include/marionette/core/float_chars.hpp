// std::from_chars (and to_chars with a precision) for float and double where the standard library has it, and a strtod
// shim with the same contract where it does not: libc++ before 17 (emscripten's, for
// the web build) has only the integer overloads. Command-time code.
#pragma once
#include <charconv>
#include <system_error>

namespace marionette {

// from_chars's contract (general format, C locale): an optional '-', then digits with
// an optional point and exponent, or "inf"/"infinity"/"nan" in any case. No leading
// '+', whitespace or "0x". Returns where the number ends and errc::invalid_argument
// (ptr == first) or errc::result_out_of_range (value left unchanged).
std::from_chars_result fromCharsViaStrtod(const char* first, const char* last, float& value) noexcept;
std::from_chars_result fromCharsViaStrtod(const char* first, const char* last, double& value) noexcept;

#if defined(_LIBCPP_VERSION) && _LIBCPP_VERSION < 170000
#define MARIONETTE_FLOAT_FROM_CHARS_SHIM 1
#endif

// The one entry point the library reads floating-point text through.
template <class T>
inline std::from_chars_result floatFromChars(const char* first, const char* last, T& value) noexcept {
#if MARIONETTE_FLOAT_FROM_CHARS_SHIM
  return fromCharsViaStrtod(first, last, value);
#else
  return std::from_chars(first, last, value);
#endif
}

// std::to_chars(first, last, value, format, precision), which printf's %.*f, %.*e and
// %.*g define (the standard says so); the shim is snprintf in the C locale.
std::to_chars_result toCharsViaSnprintf(char* first, char* last, double value, std::chars_format format,
                                        int precision) noexcept;

inline std::to_chars_result floatToChars(char* first, char* last, double value, std::chars_format format,
                                         int precision) noexcept {
#if MARIONETTE_FLOAT_FROM_CHARS_SHIM
  return toCharsViaSnprintf(first, last, value, format, precision);
#else
  return std::to_chars(first, last, value, format, precision);
#endif
}

}  // namespace marionette
