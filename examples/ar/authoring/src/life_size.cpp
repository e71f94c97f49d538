#include "marionette_ar/authoring/life_size.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace marionette::ar {

namespace {

// Metres as a user reads them: 4.46, 1.7, 120 (two decimals at most, no trailing zeros).
std::string metres(float m) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2f", static_cast<double>(m));
  std::string out = s;
  if (out.find('.') != std::string::npos) {
    while (out.back() == '0') out.pop_back();
    if (out.back() == '.') out.pop_back();
  }
  if (out == "0" && m != 0.0f) {  // a few millimetres: its first digits
    std::snprintf(s, sizeof s, "%.2g", static_cast<double>(m));
    out = s;
  }
  return out;
}

}  // namespace

LifeSize lifeSizeHeight(const std::string& name, const std::string& asset, float fileHeightMetres,
                        std::optional<float> profileLifeHeightMetres) {
  if (profileLifeHeightMetres && std::isfinite(*profileLifeHeightMetres) && *profileLifeHeightMetres > 0.0f)
    return {*profileLifeHeightMetres, LifeSize::From::Profile, {}};
  const bool measured = std::isfinite(fileHeightMetres) && fileHeightMetres > 0.0f;
  if (measured && fileHeightMetres >= kPersonHeightMinMetres && fileHeightMetres <= kPersonHeightMaxMetres)
    return {fileHeightMetres, LifeSize::From::File, {}};
  const std::string file = asset.empty() ? std::string() : std::filesystem::path(asset).filename().string();
  const std::string itsFile = file.empty() ? "its file" : "its file " + file;
  const std::string why = measured ? itsFile + " is " + metres(fileHeightMetres) + " m tall, not a person's height (" +
                                         metres(kPersonHeightMinMetres) + " to " + metres(kPersonHeightMaxMetres) + " m)"
                                   : itsFile + " has no height to measure";
  return {kDefaultLifeHeightMetres, LifeSize::From::Default,
          name + ": " + why + "; placed at " + metres(kDefaultLifeHeightMetres) +
              " m (set \"lifeHeight\" in its profile)"};
}

}  // namespace marionette::ar
