// The rig's animation events per clip (Rig::events): foot contacts of the profile's feet and
// the markers of the clip and the profile, found when a clip's events are first asked for.
#include <algorithm>
#include <cmath>

#include "marionette/animation/foot_contacts.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

namespace {

// Samples per second of the foot-contact analysis behind the events: a contact's ends are
// found within half a sample (4 ms), finer than a 30 or 60 fps clip's frames, at a quarter
// of the analysis' default cost (it runs once per clip played, at its first play).
constexpr int kFootEventSamplesPerSecond = 60;

// Hip to knee to ankle in the rest pose; 0 when the leg is incomplete (the human defaults).
float restLegLength(const std::vector<glm::mat4>& rest, const RigJoints::LimbJoints& leg) {
  const auto at = [&](int j) { return glm::vec3(rest[static_cast<std::size_t>(j)][3]); };
  const auto valid = [&](int j) { return j >= 0 && static_cast<std::size_t>(j) < rest.size(); };
  if (!valid(leg.upper) || !valid(leg.lower) || !valid(leg.end)) return 0.0f;
  const float length = glm::distance(at(leg.upper), at(leg.lower)) + glm::distance(at(leg.lower), at(leg.end));
  return std::isfinite(length) ? length : 0.0f;
}

}  // namespace

void Rig::updateEvents(std::size_t c) const {
  const AnimationClip& clip = *clips_[c];
  ClipEvents& out = events_.clips[c];
  const RigJoints::LimbJoints* legs[2] = {&joints_.leftLeg, &joints_.rightLeg};
  const int toes[2] = {joints_.leftToe, joints_.rightToe};
  std::vector<glm::mat4> rest;
  for (int f = 0; f < 2; ++f) {
    const int foot = legs[f]->end >= 0 ? legs[f]->end : toes[f];  // the ankle, else the toe
    if (foot >= 0 && rest.empty()) rest = skeleton_.restModelMatrices();
    const float leg = foot >= 0 ? restLegLength(rest, *legs[f]) : 0.0f;
    if (out.track && out.foot[f] == foot && out.leg[f] == leg) continue;  // found before for these feet
    out.foot[f] = foot;
    out.leg[f] = leg;
    out.contacts[f].clear();
    if (foot < 0) continue;
    FootContactOptions options = footContactOptionsForLeg(leg);
    options.samplesPerSecond = kFootEventSamplesPerSecond;
    out.contacts[f] = detectFootContacts(clip, skeleton_, foot, options);
  }
  std::vector<ClipEvent> markers = clip.clip.events;
  if (auto it = profile_.events.find(clip.clip.name); it != profile_.events.end())
    markers.insert(markers.end(), it->second.begin(), it->second.end());
  out.track = std::make_shared<const AnimationEventTrack>(clip.clip.duration, markers, out.contacts[0], out.contacts[1]);
  out.current = true;
}

std::shared_ptr<const AnimationEventTrack> Rig::events(const AnimationClip& clip) const noexcept {
  std::lock_guard lock(events_.mutex);
  for (std::size_t c = 0; c < clips_.size() && c < events_.clips.size(); ++c) {
    if (clips_[c].get() != &clip) continue;
    try {
      if (!events_.clips[c].current) updateEvents(c);
    } catch (...) {  // only std::bad_alloc: events are optional, the clip still plays
      return nullptr;
    }
    return events_.clips[c].track;
  }
  return nullptr;
}

}  // namespace marionette
