// The shipped profiles and joint maps built into the library, for a build without a file
// system to install them in (the web build: MARIONETTE_C_SHIPPED_DATA). Natively the same
// files are read from share/marionette or the source tree.
#pragma once
#include <cstddef>
#include <string_view>

#include "marionette/core/file_reader.hpp"

namespace marionette::capi {

struct ShippedFile {
  std::string_view path;  // "/marionette/profiles/RobotExpressive.json", ...
  std::string_view text;
};
extern const ShippedFile kShippedFiles[];
extern const std::size_t kShippedFileCount;

// Where the built-in profiles are, and a reader of the built-in files (joint maps included:
// a profile names its map relative to itself).
inline constexpr const char* kShippedProfileFolder = "/marionette/profiles";
[[nodiscard]] FileReader shippedFileReader();

}  // namespace marionette::capi
