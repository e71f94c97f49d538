// Lists of numbers in attribute text ("1.5 0 -2", "1, 2"): what BML targets and
// profile values are made of. Command-time code (may allocate).
#pragma once
#include <optional>
#include <string_view>
#include <vector>

namespace marionette {

// The numbers in `text`, separated by spaces, tabs or commas. "nan" and "inf"
// (any case, signed, "infinity") are read as such so that callers can reject them
// by name; a value out of float range reads as infinite. nullopt when any token is
// not a number (so "Bob" or "1 2 x" are not number lists).
[[nodiscard]] std::optional<std::vector<float>> parseNumberList(std::string_view text);

}  // namespace marionette
