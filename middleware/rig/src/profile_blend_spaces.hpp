// Private to the profile reader: a profile's "blendSpaces", clips of its asset placed in
// a 1D or 2D parameter space by name (docs/character-profiles.md, docs/blend-spaces.md):
//   "blendSpaces": {"locomotion": {"dimensions": 1, "samples": [{"clip": "Walking", "x": 1.6}, ...]}}
#pragma once
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"

namespace marionette::profile_detail {

// Reports a problem at a JSON pointer ("/blendSpaces/locomotion/samples/1/x"); `atKey`: at its key.
using BlendSpaceWarning = std::function<void(const std::string& pointer, const std::string& message, bool atKey)>;

// Reads `spaces` into profile.blendSpaces. A space with a problem (a clip the asset lacks,
// a missing or non-finite coordinate, two samples at one point, a 2D layout on one line,
// unknown keys aside) is a warning at its place and is left out whole: a space with a
// sample missing would blend to a different motion than the one written. Returns the
// number of spaces read.
std::size_t readProfileBlendSpaces(const nlohmann::json& spaces, const Asset& asset, CharacterProfile& profile,
                                   const BlendSpaceWarning& warn);

}  // namespace marionette::profile_detail
