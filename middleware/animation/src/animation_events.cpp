#include "marionette/animation/animation_events.hpp"

#include <algorithm>
#include <cmath>

namespace marionette {

std::string_view animationEventKindName(AnimationEventKind kind) noexcept {
  switch (kind) {
    case AnimationEventKind::FootDown: return "foot down";
    case AnimationEventKind::FootUp: return "foot up";
    case AnimationEventKind::Marker: return "marker";
  }
  return "?";
}

std::string_view footSideName(FootSide side) noexcept {
  switch (side) {
    case FootSide::None: return "none";
    case FootSide::Left: return "left";
    case FootSide::Right: return "right";
  }
  return "?";
}

AnimationEventTrack::AnimationEventTrack(float duration, std::span<const ClipEvent> markers,
                                         std::span<const ContactInterval> leftFoot,
                                         std::span<const ContactInterval> rightFoot)
    : duration_(std::isfinite(duration) && duration > 0.0f ? duration : 0.0f) {
  auto nameIndex = [&](std::string_view name) {
    auto it = std::find(names_.begin(), names_.end(), name);
    if (it == names_.end()) it = names_.insert(names_.end(), std::string(name));
    return static_cast<std::uint32_t>(it - names_.begin());
  };
  // Feet: phases of the cycle to clip time. A contact's begin is the touchdown, its end the
  // lift-off; {0, 1} is a foot that never lifts (no event).
  const std::pair<FootSide, std::span<const ContactInterval>> feet[] = {{FootSide::Left, leftFoot},
                                                                        {FootSide::Right, rightFoot}};
  for (const auto& [side, contacts] : feet) {
    const bool left = side == FootSide::Left;
    for (const ContactInterval& c : contacts) {
      if (!std::isfinite(c.begin) || !std::isfinite(c.end) || (c.begin <= 0.0f && c.end >= 1.0f)) continue;
      const std::pair<AnimationEventKind, float> ends[] = {{AnimationEventKind::FootDown, c.begin},
                                                           {AnimationEventKind::FootUp, c.end}};
      for (const auto& [kind, phase] : ends) {
        const float time = std::clamp(phase, 0.0f, 1.0f) * duration_;
        const char* name = kind == AnimationEventKind::FootDown ? (left ? "left_foot_down" : "right_foot_down")
                                                                : (left ? "left_foot_up" : "right_foot_up");
        events_.push_back({time, kind, side, nameIndex(name)});
      }
    }
  }
  for (const ClipEvent& m : markers) {
    if (m.name.empty() || !std::isfinite(m.time) || m.time < 0.0f || m.time > duration_) continue;
    events_.push_back({m.time, AnimationEventKind::Marker, FootSide::None, nameIndex(m.name)});
  }
  if (duration_ == 0.0f) events_.clear();  // a clip without duration crosses nothing
  // Stable: at equal times, feet (left, right) before markers, markers in their order.
  std::stable_sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
  loopPoint_ = static_cast<std::size_t>(
      std::find_if(events_.begin(), events_.end(), [&](const Event& e) { return e.time >= duration_; }) - events_.begin());
}

}  // namespace marionette
