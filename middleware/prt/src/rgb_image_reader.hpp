// Internal to marionette::prt: reading any image OpenImageIO decodes as linear float RGB,
// shared by loadEnvironmentMap and loadLightProbe (not installed, not part of the API).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::prt::detail {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // width*height*3, rows top to bottom
};

// Reads `path` as linear float RGB with loadEnvironmentMap's channel rules and clamping
// (negative, NaN and +-Inf become 0, with one warning naming the file). `noun` names the
// kind of file in the error messages ("environment map", "light probe"). Empty on error,
// each error naming the file.
[[nodiscard]] std::optional<RgbImage> readRgbImage(const std::string& path, const std::string& noun,
                                                   Diagnostics& diagnostics);

// The warning loadEnvironmentMap gives for an image that is not 2:1 (nothing when it is).
void warnIfNotTwoToOne(const std::string& path, int width, int height, Diagnostics& diagnostics);

}  // namespace marionette::prt::detail
