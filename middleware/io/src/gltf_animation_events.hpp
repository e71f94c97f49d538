// Private to the glTF importer: an animation's authored events, from its `extras`:
//   "extras": {"events": [{"time": 0.5, "name": "footstep_L"}, ...]}
// or `extras` being that list itself. Times are seconds of the clip, within [0, duration];
// names are not empty. A bad entry is a warning naming the animation and the entry, and is
// left out; other `extras` (an object without "events") belong to someone else: not read.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>

#include "gltf_context.hpp"
#include "marionette/animation/clip.hpp"

namespace marionette::gltf_detail {

inline void readAnimationEvents(const Context& ctx, std::size_t a, Clip& clip) {
  const Json* animation = element(member(ctx.json, "animations"), a);
  const Json* extras = animation ? member(*animation, "extras") : nullptr;
  if (!extras) return;
  const Json* list = extras->is_array() ? extras : member(*extras, "events");
  std::string where = "animation '" + clip.name + "' (animations/" + std::to_string(a) + "/extras";
  if (!list) return;
  if (list != extras) where += "/events";
  if (!list->is_array()) {
    ctx.warning(where + "): expected a list of {\"time\": seconds, \"name\": text}; the events are ignored");
    return;
  }
  for (std::size_t i = 0; i < list->size(); ++i) {
    const Json& e = (*list)[i];
    const std::string at = where + "/" + std::to_string(i) + ")";
    const std::optional<double> time = asNumber(member(e, "time"));
    const Json* name = member(e, "name");
    if (!e.is_object() || !name || !name->is_string() || name->get<std::string>().empty()) {
      ctx.warning(at + ": expected {\"time\": seconds, \"name\": text} with a name; the event is ignored");
      continue;
    }
    const std::string text = name->get<std::string>();
    if (!time || !std::isfinite(*time) || *time < 0.0 || static_cast<float>(*time) > clip.duration) {
      const std::string said = time ? std::to_string(*time) : std::string("missing or not a number");
      ctx.warning(at + ": event '" + text + "' has time " + said + ", not within the clip's [0, " +
                  std::to_string(clip.duration) + "] s; the event is ignored");
      continue;
    }
    clip.events.push_back({static_cast<float>(*time), text});
  }
  std::stable_sort(clip.events.begin(), clip.events.end(),
                   [](const ClipEvent& x, const ClipEvent& y) { return x.time < y.time; });
}

}  // namespace marionette::gltf_detail
