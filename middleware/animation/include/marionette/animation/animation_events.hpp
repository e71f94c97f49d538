// Animation events of one clip: a foot down and up at its contacts (foot_contacts.hpp) and
// the authored markers (Clip::events), compiled once at command time into a track sorted by
// time with each name stored once; and, per frame, the events a playhead crosses moving from
// one clip time to another. The conventions (half-open intervals, loops, negative speed,
// the cap per frame) are docs/animation-events.md's.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/animation/foot_contacts.hpp"
#include "marionette/animation/sampling.hpp"

namespace marionette {

enum class AnimationEventKind : std::uint8_t { FootDown, FootUp, Marker };
enum class FootSide : std::uint8_t { None, Left, Right };  // the character's own left and right

[[nodiscard]] std::string_view animationEventKindName(AnimationEventKind kind) noexcept;  // "foot down", ...
[[nodiscard]] std::string_view footSideName(FootSide side) noexcept;                      // "left", "right", "none"

class AnimationEventTrack {
 public:
  // Passes over a looping clip whose events one playhead sends in one frame; the passes
  // after these are skipped (and counted, for a warning). 64 passes of the shortest
  // sensible cycle (about 15 ms) cover a one-second frame: only a frame far longer than a
  // second (Scene::update allows an hour) meets the cap.
  static constexpr int kMaxPassesPerFrame = 64;

  struct Event {
    float time = 0.0f;  // clip-local seconds, in [0, duration]
    AnimationEventKind kind = AnimationEventKind::Marker;
    FootSide side = FootSide::None;  // feet only
    std::uint32_t name = 0;          // into names()
  };

  AnimationEventTrack() = default;
  // The events of a clip of `duration` seconds: each contact of a foot (phases of the
  // cycle, foot_contacts.hpp) gives a FootDown at its begin and a FootUp at its end (none
  // for a foot that never lifts); each marker with a name and a time in [0, duration]
  // gives a Marker (readers report the others: they are skipped here). Sorted by time;
  // at equal times feet come first (left, then right), then markers in their given order.
  AnimationEventTrack(float duration, std::span<const ClipEvent> markers, std::span<const ContactInterval> leftFoot,
                      std::span<const ContactInterval> rightFoot);

  [[nodiscard]] bool empty() const noexcept { return events_.empty(); }
  [[nodiscard]] float duration() const noexcept { return duration_; }
  [[nodiscard]] std::span<const Event> events() const noexcept { return events_; }
  [[nodiscard]] std::span<const std::string> names() const noexcept { return names_; }
  [[nodiscard]] std::string_view name(const Event& e) const noexcept {
    return e.name < names_.size() ? std::string_view(names_[e.name]) : std::string_view();
  }

  // Calls visit(const Event&, double at) for every event a playhead crosses moving from
  // clip time `from` to `to` (unwrapped, as a layer counts them: loops keep counting),
  // in the order it crosses them; `at` is the crossing on that unwrapped time line.
  // - Half-open: an event at `from` is crossed, one at `to` is not (the next frame, which
  //   starts there, crosses it): an event is sent once however the frames cut the time.
  //   Backwards (to < from) the same: (to, from], in decreasing time.
  // - Loop: the clip repeats every duration(); an event at the duration is the loop point,
  //   crossed with those at 0 (before them). At most kMaxPassesPerFrame passes; the
  //   number of passes skipped is returned.
  // - Clamp: the playhead stays in [0, duration]; arriving at an end crosses the events
  //   there (it does not leave it, so the half-open rule would never send them).
  // - from == to (a held layer), a clip without duration, non-finite times: nothing.
  // Per-frame: no allocation.
  template <class Visit>
  std::uint64_t forEachCrossed(double from, double to, WrapMode wrap, Visit&& visit) const noexcept;

 private:
  float duration_ = 0.0f;
  std::vector<Event> events_;
  std::vector<std::string> names_;
  std::size_t loopPoint_ = 0;  // events_[loopPoint_, end) are at duration_ (the loop point)
};

// ---- implementation ------------------------------------------------------------------

template <class Visit>
std::uint64_t AnimationEventTrack::forEachCrossed(double from, double to, WrapMode wrap, Visit&& visit) const noexcept {
  const double d = duration_;
  if (events_.empty() || !(d > 0.0) || !std::isfinite(from) || !std::isfinite(to) || from == to) return 0;
  const std::span<const Event> all = events_;
  if (wrap == WrapMode::Clamp) {
    const double a = std::clamp(from, 0.0, d), b = std::clamp(to, 0.0, d);
    if (a == b) return 0;
    if (b > a) {
      for (const Event& e : all)
        if (e.time >= a && (e.time < b || b == d)) visit(e, static_cast<double>(e.time));
    } else {
      for (auto it = all.rbegin(); it != all.rend(); ++it)
        if (it->time <= a && (it->time > b || b == 0.0)) visit(*it, static_cast<double>(it->time));
    }
    return 0;
  }
  // Loop: cycle k spans [k d, (k + 1) d); an event's place in it is its time, the loop
  // point's events at 0. Each crossing is k * d + phase, computed the same way in every
  // frame, so a crossing at a frame's end is the next frame's start, bit for bit.
  const std::span<const Event> atLoopPoint = all.subspan(loopPoint_), inside = all.first(loopPoint_);
  auto phase = [&](const Event& e) { return &e >= atLoopPoint.data() ? 0.0 : static_cast<double>(e.time); };
  // The cycles the interval touches: [from, to) forwards, (to, from] backwards.
  const double firstCycle = std::floor(from / d), lastCycle = to > from ? std::ceil(to / d) - 1.0 : std::floor(to / d);
  const double cycles = std::fabs(lastCycle - firstCycle) + 1.0;
  const double passes = std::min(cycles, static_cast<double>(kMaxPassesPerFrame));
  const double step = to > from ? 1.0 : -1.0;
  for (double n = 0.0; n < passes; n += 1.0) {
    const double base = (firstCycle + step * n) * d;
    auto at = [&](const Event& e) { return base + phase(e); };
    if (to > from) {
      for (const std::span<const Event> part : {atLoopPoint, inside})
        for (const Event& e : part)
          if (const double u = at(e); u >= from && u < to) visit(e, u);
    } else {
      for (const std::span<const Event> part : {inside, atLoopPoint})
        for (auto it = part.rbegin(); it != part.rend(); ++it)
          if (const double u = at(*it); u <= from && u > to) visit(*it, u);
    }
  }
  return static_cast<std::uint64_t>(cycles - passes);
}

}  // namespace marionette
