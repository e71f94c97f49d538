#include "profile_events.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/rig/detail/json_places.hpp"

namespace marionette::profile_detail {

std::size_t readProfileEvents(const nlohmann::json& events, const Asset& asset, CharacterProfile& profile,
                              const EventWarning& warn) {
  using json_detail::JsonPlaces;
  if (!events.is_object()) {
    warn("/events", "expected an object of clip name: [{\"time\": seconds, \"name\": text}, ...]; ignored", false);
    return 0;
  }
  std::size_t read = 0;
  for (auto it = events.begin(); it != events.end(); ++it) {
    const std::string where = "/events/" + JsonPlaces::escape(it.key());
    const auto clip = std::find_if(asset.clips.begin(), asset.clips.end(), [&](const Clip& c) { return c.name == it.key(); });
    if (clip == asset.clips.end()) {
      warn(where, "no clip named '" + it.key() + "' in " +
                      (asset.sourcePath.empty() ? std::string("the asset") : "'" + asset.sourcePath + "'") +
                      "; its events are ignored", true);
      continue;
    }
    if (!it->is_array()) {
      warn(where, "expected a list of {\"time\": seconds, \"name\": text}; ignored", false);
      continue;
    }
    std::vector<ClipEvent>& out = profile.events[it.key()];
    for (std::size_t i = 0; i < it->size(); ++i) {
      const nlohmann::json& e = (*it)[i];
      const std::string at = where + "/" + std::to_string(i);
      if (!e.is_object() || !e.contains("name") || !e["name"].is_string() || e["name"].get<std::string>().empty()) {
        warn(at, "expected {\"time\": seconds, \"name\": text} with a name; the event is ignored", false);
        continue;
      }
      const std::string name = e["name"].get<std::string>();
      const bool number = e.contains("time") && e["time"].is_number();
      const double time = number ? e["time"].get<double>() : NAN;
      if (!std::isfinite(time) || time < 0.0 || static_cast<float>(time) > clip->duration) {
        warn(number ? at + "/time" : at,
             "event '" + name + "' has time " + (number ? std::to_string(time) : std::string("missing or not a number")) +
                 ", not within the clip's [0, " + std::to_string(clip->duration) + "] s; the event is ignored",
             false);
        continue;
      }
      out.push_back({static_cast<float>(time), name});
      ++read;
    }
    std::stable_sort(out.begin(), out.end(), [](const ClipEvent& x, const ClipEvent& y) { return x.time < y.time; });
    if (out.empty()) profile.events.erase(it.key());
  }
  return read;
}

}  // namespace marionette::profile_detail
