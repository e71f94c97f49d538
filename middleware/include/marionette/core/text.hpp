// Small text helpers for names in files and BML (ASCII case folding).
#pragma once
#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

namespace marionette {

[[nodiscard]] inline bool equalsIgnoringCase(std::string_view a, std::string_view b) noexcept {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

[[nodiscard]] inline std::string toUpper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace marionette
