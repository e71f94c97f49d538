// Names of enum values, for files, BML, messages and the C API: one table per enum and one
// lookup, so that a name read from a file is matched the same way everywhere and an unknown
// one is reported with the list of valid names.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/text.hpp"

namespace marionette {

template <class E>
struct EnumName {
  std::string_view name;
  E value;
};

enum class NameCase : std::uint8_t { Exact, Ignored };  // Ignored: ASCII letters only

namespace names_detail {
[[nodiscard]] inline bool matches(std::string_view a, std::string_view b, NameCase c) noexcept {
  return c == NameCase::Exact ? a == b : equalsIgnoringCase(a, b);
}
}  // namespace names_detail

// The value named `name` in `table` (several rows may name one value: aliases), or nullopt.
template <class E>
[[nodiscard]] constexpr std::optional<E> valueOfName(std::string_view name, std::span<const EnumName<E>> table,
                                                     NameCase c = NameCase::Exact) noexcept {
  for (const EnumName<E>& row : table)
    if (names_detail::matches(name, row.name, c)) return row.value;
  return std::nullopt;
}

// The same for a table of names indexed by the enum's value (names[i] names E(i)).
template <class E>
[[nodiscard]] constexpr std::optional<E> valueOfIndexedName(std::string_view name, std::span<const std::string_view> names,
                                                            NameCase c = NameCase::Exact) noexcept {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names_detail::matches(name, names[i], c)) return static_cast<E>(i);
  return std::nullopt;
}

// The first name of `value` in `table`, or `fallback` when the table has none.
template <class E>
[[nodiscard]] constexpr std::string_view nameOfValue(E value, std::span<const EnumName<E>> table,
                                                    std::string_view fallback) noexcept {
  for (const EnumName<E>& row : table)
    if (row.value == value) return row.name;
  return fallback;
}

// "NOD, SHAKE or TILT": each value's first name in table order, for a message that lists the
// valid names (an alias row, naming a value already listed, is left out).
template <class E>
[[nodiscard]] std::string validNames(std::span<const EnumName<E>> table) {
  std::vector<std::string_view> firsts;  // each value's first name
  for (std::size_t i = 0; i < table.size(); ++i)
    if (nameOfValue<E>(table[i].value, table.first(i), {}).empty()) firsts.push_back(table[i].name);
  std::string out;
  for (std::size_t i = 0; i < firsts.size(); ++i) {
    if (i > 0) out += i + 1 == firsts.size() ? " or " : ", ";
    out += firsts[i];
  }
  return out;
}

}  // namespace marionette
