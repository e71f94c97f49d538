// Private to the profile reader: a profile's "events", the authored animation events of
// its asset's clips by clip name (docs/character-profiles.md):
//   "events": {"Walking": [{"time": 0.12, "name": "footstep_L"}, ...], ...}
#pragma once
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"

namespace marionette::profile_detail {

// Reports a problem at a JSON pointer ("/events/Walking/2/time"); `atKey`: at its key.
using EventWarning = std::function<void(const std::string& pointer, const std::string& message, bool atKey)>;

// Reads `events` into profile.events. A clip the asset lacks, an entry without a name, a
// time that is not a number within the clip's [0, duration]: a warning at its place, and
// the entry (or the clip's list) is left out. Returns the number of events read.
std::size_t readProfileEvents(const nlohmann::json& events, const Asset& asset, CharacterProfile& profile,
                              const EventWarning& warn);

}  // namespace marionette::profile_detail
