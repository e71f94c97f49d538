#include "profile_blend_spaces.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/rig/detail/json_places.hpp"

namespace marionette::profile_detail {

namespace {
using Json = nlohmann::json;
using json_detail::JsonPlaces;

// One space; false (with a warning) when it is left out.
bool readSpace(const std::string& name, const Json& j, const std::string& where, const Asset& asset,
               BlendSpaceDefinition& out, const BlendSpaceWarning& warn) {
  if (!j.is_object()) {
    warn(where, "expected {\"dimensions\": 1 or 2, \"samples\": [{\"clip\", \"x\", \"y\"}, ...]}; the space is left out", false);
    return false;
  }
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "dimensions" && it.key() != "samples" && it.key() != "phaseAligned" && it.key() != "comment")
      warn(where + "/" + JsonPlaces::escape(it.key()), "unknown key '" + it.key() + "' ignored", true);
  out.name = name;
  if (!j.contains("samples") || !j["samples"].is_array() || j["samples"].empty()) {
    warn(j.contains("samples") ? where + "/samples" : where,
         "expected \"samples\": a non-empty list of {\"clip\", \"x\", \"y\"}; the space is left out", false);
    return false;
  }
  const Json& samples = j["samples"];
  bool anyY = false;
  for (const Json& s : samples) anyY = anyY || (s.is_object() && s.contains("y"));
  out.dimensions = anyY ? 2 : 1;
  if (j.contains("dimensions")) {
    const Json& d = j["dimensions"];
    if (!d.is_number_integer() || (d.get<long long>() != 1 && d.get<long long>() != 2)) {
      warn(where + "/dimensions", "expected 1 or 2; the space is left out", false);
      return false;
    }
    out.dimensions = static_cast<int>(d.get<long long>());
  }
  if (j.contains("phaseAligned")) {
    if (!j["phaseAligned"].is_boolean()) {
      warn(where + "/phaseAligned", "expected true or false; the space is left out", false);
      return false;
    }
    out.phaseAligned = j["phaseAligned"].get<bool>();
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string at = where + "/samples/" + std::to_string(i);
    const Json& s = samples[i];
    if (!s.is_object()) {
      warn(at, "expected {\"clip\": NAME, \"x\": NUMBER" + std::string(out.dimensions == 2 ? ", \"y\": NUMBER}" : "}") +
                   "; the space is left out", false);
      return false;
    }
    for (auto it = s.begin(); it != s.end(); ++it)
      if (it.key() != "clip" && it.key() != "x" && it.key() != "y")
        warn(at + "/" + JsonPlaces::escape(it.key()), "unknown key '" + it.key() + "' ignored", true);
    if (!s.contains("clip") || !s["clip"].is_string() || s["clip"].get<std::string>().empty()) {
      warn(s.contains("clip") ? at + "/clip" : at, "expected \"clip\": a clip name; the space is left out", false);
      return false;
    }
    const std::string clip = s["clip"].get<std::string>();
    if (std::none_of(asset.clips.begin(), asset.clips.end(), [&](const Clip& c) { return c.name == clip; })) {
      const std::string file = asset.sourcePath.empty() ? std::string("the asset") : "'" + asset.sourcePath + "'";
      warn(at + "/clip", "no clip named '" + clip + "' in " + file + "; the space is left out", false);
      return false;
    }
    BlendSpaceSampleDefinition sample{clip, 0.0f, 0.0f};
    const char* axes[] = {"x", "y"};
    for (int a = 0; a < out.dimensions; ++a) {
      const std::string axis = at + "/" + axes[a];
      const bool finite = s.contains(axes[a]) && s[axes[a]].is_number() && std::isfinite(s[axes[a]].get<double>()) &&
                          std::fabs(s[axes[a]].get<double>()) < 1e30;
      if (!finite) {
        warn(s.contains(axes[a]) ? axis : at, std::string("expected \"") + axes[a] + "\": a finite number; the space is left out",
             false);
        return false;
      }
      (a == 0 ? sample.x : sample.y) = static_cast<float>(s[axes[a]].get<double>());
    }
    if (out.dimensions == 1 && s.contains("y")) warn(at + "/y", "ignored: the space has 1 dimension", true);
    out.samples.push_back(std::move(sample));
  }
  if (std::string why = validateBlendSpaceDefinition(out); !why.empty()) {
    warn(where, why + "; the space is left out", true);
    return false;
  }
  return true;
}

}  // namespace

std::size_t readProfileBlendSpaces(const Json& spaces, const Asset& asset, CharacterProfile& profile,
                                   const BlendSpaceWarning& warn) {
  if (!spaces.is_object()) {
    warn("/blendSpaces", "expected an object of NAME: {\"dimensions\", \"samples\"}; ignored", false);
    return 0;
  }
  std::size_t read = 0;
  for (auto it = spaces.begin(); it != spaces.end(); ++it) {
    const std::string where = "/blendSpaces/" + JsonPlaces::escape(it.key());
    if (it.key().empty()) {
      warn(where, "a blend space needs a name; left out", true);
      continue;
    }
    BlendSpaceDefinition d;
    if (!readSpace(it.key(), *it, where, asset, d, warn)) continue;
    profile.blendSpaces.push_back(std::move(d));
    ++read;
  }
  return read;
}

}  // namespace marionette::profile_detail
