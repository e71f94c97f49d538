// The strtod shim that stands in for floating-point std::from_chars where the standard
// library lacks it (emscripten's libc++): the same values, ends and errors as from_chars.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "marionette/core/float_chars.hpp"

namespace marionette {
namespace {

template <class T>
void expectSameAsFromChars(const std::string& text) {
  const char* first = text.data();
  const char* last = first + text.size();
  T expected = T(-7), actual = T(-7);
  const auto want = std::from_chars(first, last, expected);
  const auto got = fromCharsViaStrtod(first, last, actual);
  EXPECT_EQ(static_cast<int>(got.ec), static_cast<int>(want.ec)) << "'" << text << "'";
  EXPECT_EQ(got.ptr - first, want.ptr - first) << "'" << text << "'";
  if (want.ec == std::errc()) {
    if (std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(actual)) << "'" << text << "'";
    } else {
      EXPECT_EQ(std::memcmp(&actual, &expected, sizeof(T)), 0) << "'" << text << "': " << actual << " vs " << expected;
    }
  } else {
    EXPECT_EQ(actual, T(-7)) << "'" << text << "': the value is left as it was on an error";
  }
}

const std::vector<std::string>& samples() {
  static const std::vector<std::string> s = {
      "0", "-0", "1", "-1", "1.5", ".5", "5.", "-.5", "0.1", "3.14159265358979323846", "1e10", "1E-10", "1e", "1e+",
      "1e+5x", "2.5e-3", "123456789012345678901234567890", "1e38", "3.5e38", "1e39", "-1e39", "1e308", "1e309",
      "1e-38", "1e-45", "1e-46", "1e-320", "1e-400", "-1e-400", "0e999", "inf", "-inf", "INF", "Infinity", "-infinityx",
      "infin", "nan", "-NaN", "nan(123)", "nan(", "nanx", "", "-", ".", "-.", "+1", " 1", "0x1p3", "0x10", "1.5 2",
      "1,5", "abc", "e5", "00012", "1.2.3", "9999999999999999999999999999999999999999999999999999999999999999999.5",
      std::string(200, '1'), "0." + std::string(100, '0') + "1", "1.17549435e-38", "1.4e-45", "0.7e-45",
      "3.4028235e38", "3.4028236e38", "2.2250738585072014e-308", "4.9e-324", "2.4e-324",
      // Halfway and just past it: a double rounded again to float is not the nearest float.
      "1.000000059604644775390625", "1.000000059604644775390625000001", "1.0000000596046447753906249999",
      "16777217", "16777217.000000001", "3.4028235677973366e38", "3.40282357e38", "1.1754942e-38",
      "7.00649232162408535461864791644958065640130970938257885878534141944895541342930300743319094181060791015625e-46",
      "7.0064923216240862e-46", "1.401298464324817e-45", "2.4703282292062327e-324", "2.4703282292062328e-324",
      "9007199254740993", "0.1000000000000000055511151231257827"};
  return s;
}

TEST(FloatChars, TheShimReadsWhatFromCharsReadsAsFloats) {
  for (const std::string& text : samples()) expectSameAsFromChars<float>(text);
}

TEST(FloatChars, TheShimReadsWhatFromCharsReadsAsDoubles) {
  for (const std::string& text : samples()) expectSameAsFromChars<double>(text);
}

TEST(FloatChars, TheShimRoundTripsRandomValuesBitForBit) {
  std::uint64_t state = 0x9e3779b97f4a7c15ull;
  char buf[64];
  for (int i = 0; i < 20000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const std::uint32_t bits = static_cast<std::uint32_t>(state >> 32);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    if (!std::isfinite(f)) continue;
    const auto end = std::to_chars(buf, buf + sizeof buf, f).ptr;
    expectSameAsFromChars<float>(std::string(buf, end));
    double d = static_cast<double>(f) * 1.0000001;
    const auto endD = std::to_chars(buf, buf + sizeof buf, d).ptr;
    expectSameAsFromChars<double>(std::string(buf, endD));
  }
}

}  // namespace
}  // namespace marionette

namespace marionette {
namespace {

TEST(FloatChars, TheSnprintfShimWritesWhatToCharsWritesWithAPrecision) {
  const double values[] = {0.0, -0.0, 1.0, -1.5, 0.1, 1.0 / 3.0, 123456.789, 1e-7, 1e21, -2.5e-300, 1.7976931348623157e308,
                           4.9e-324, 0.5, 1.5, 2.5, 1e15 + 0.3};
  const std::chars_format formats[] = {std::chars_format::fixed, std::chars_format::scientific, std::chars_format::general};
  for (double v : values)
    for (std::chars_format format : formats)
      for (int precision : {0, 1, 6, 9, 17}) {
        char want[400], got[400];
        const auto a = std::to_chars(want, want + sizeof want, v, format, precision);
        const auto b = toCharsViaSnprintf(got, got + sizeof got, v, format, precision);
        ASSERT_EQ(static_cast<int>(b.ec), static_cast<int>(a.ec)) << v;
        EXPECT_EQ(std::string(got, b.ptr), std::string(want, a.ptr)) << v << " precision " << precision;
      }
  char big[2000], want[2000];  // longer than the shim's own buffer
  const auto a = std::to_chars(want, want + sizeof want, 1e300, std::chars_format::fixed, 600);
  const auto b = toCharsViaSnprintf(big, big + sizeof big, 1e300, std::chars_format::fixed, 600);
  ASSERT_EQ(static_cast<int>(b.ec), static_cast<int>(a.ec));
  EXPECT_EQ(std::string(big, b.ptr), std::string(want, a.ptr));
  char tiny[4];
  EXPECT_EQ(toCharsViaSnprintf(tiny, tiny + sizeof tiny, 12345.0, std::chars_format::fixed, 2).ec, std::errc::value_too_large);
}

}  // namespace
}  // namespace marionette
