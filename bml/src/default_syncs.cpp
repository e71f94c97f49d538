// Default sync times of each behavior type (`defaultSyncs`): proportions of a default duration, the
// full BML 1.0 phase structure for gestures and head movements, speech timed by its text.
#include "default_syncs.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

#include "marionette/bml/scheduler.hpp"
#include "marionette/core/number_list.hpp"

namespace marionette::bml {

namespace detail {

bool repeats(std::string_view type) { return type == "head" || type == "gesture" || type == "pointing"; }

}  // namespace detail

namespace {

// Default sync times: proportions of a default duration, in the standard order.
SyncTemplate fromProportions(std::initializer_list<std::pair<const char*, double>> p, double duration,
                             bool stretchable = true) {
  SyncTemplate t;
  t.stretchable = stretchable;
  for (auto [name, f] : p) t.syncs.push_back({name, f * duration});
  return t;
}

// repetition="R": a whole number >= 1; anything else counts as 1. Values above
// kMaxBehaviorRepetitions are clamped (digits are read saturating, so no overflow).
int repetitionsOf(const Behavior& b) {
  const Attribute* a = b.attribute("repetition");
  if (!a || a->value.empty()) return 1;
  long long n = 0;
  for (char c : a->value) {
    if (c < '0' || c > '9') return 1;
    n = std::min<long long>(n * 10 + (c - '0'), kMaxBehaviorRepetitions);
  }
  return n < 1 ? 1 : static_cast<int>(n);
}

// The full BML 1.0 phase structure with the stroke phase repeated `reps` times,
// each repetition `unit` long. The proportions of one repetition (.1 .2 .3 .5 .8 1)
// are kept at the ends; the stroke phases share the time between ready and relax,
// each starting, peaking and ending at 1/7, 2/7 and 4/7 of its period.
SyncTemplate repeatedStroke(double unit, int reps) {
  SyncTemplate t;
  t.repetitions = reps;
  t.syncs.reserve(4 + 3 * static_cast<std::size_t>(reps));
  const double total = reps * unit;
  const double ready = 0.1 * unit;
  const double period = (total - 0.3 * unit) / reps;
  t.syncs.push_back({"start", 0.0});
  t.syncs.push_back({"ready", ready});
  for (int n = 1; n <= reps; ++n) {
    const std::string suffix = n == 1 ? "" : ":" + std::to_string(n);
    const double from = ready + (n - 1) * period;
    t.syncs.push_back({"strokeStart" + suffix, from + period / 7});
    t.syncs.push_back({"stroke" + suffix, from + 2 * period / 7});
    t.syncs.push_back({"strokeEnd" + suffix, from + 4 * period / 7});
  }
  t.syncs.push_back({"relax", total - 0.2 * unit});
  t.syncs.push_back({"end", total});
  return t;
}

}  // namespace

SyncTemplate defaultSyncs(const Behavior& b, const SchedulerOptions& options) {
  const std::string& t = b.type;
  if (t == "speech") {
    SyncTemplate s;
    s.stretchable = false;  // speech keeps its own timing
    const double spc = options.speechSecondsPerCharacter;
    std::optional<SpeechTiming> said;
    if (options.speechTiming) said = options.speechTiming(b);
    if (said && !(std::isfinite(said->duration) && said->duration >= 0.0)) said.reset();
    double end = std::max(options.minimumSpeechSeconds, static_cast<double>(b.text.size()) * spc);
    if (said) end = said->duration;
    s.syncs.push_back({"start", 0.0});
    double last = 0.0;  // marks stay in text order and inside the speech
    for (const WordMark& m : b.marks) {
      double at = static_cast<double>(m.characterOffset) * spc;
      if (said)
        for (const auto& [id, time] : said->marks)
          if (id == m.id && std::isfinite(time)) at = time;
      last = std::clamp(at, last, end);
      s.syncs.push_back({m.id, last});
    }
    s.syncs.push_back({"end", end});
    return s;
  }
  if (t == "wait") return fromProportions({{"start", 0}, {"end", 1}}, 0.0);
  // An event is an instant: SmartBody times it by its stroke, BML by its start.
  if (t == "event") return fromProportions({{"start", 0}, {"stroke", 0}, {"end", 0}}, 0.0, false);
  if (t == "interrupt" || t == "activate") return fromProportions({{"start", 0}, {"end", 0}}, 0.0, false);
  // The character's own length for the behavior, when it knows one. Checked against
  // the repetition cap too, so that R times it stays finite.
  std::optional<double> natural;
  if (options.defaultDuration)
    if (auto d = options.defaultDuration(b); d && std::isfinite(*d * kMaxBehaviorRepetitions) && *d > 0) natural = *d;
  // Gestures and head movements have the full BML 1.0 phase structure.
  if (detail::repeats(t)) return repeatedStroke(natural.value_or(t == "head" ? 1.0 : 2.0), repetitionsOf(b));
  if (t == "animation") return repeatedStroke(natural.value_or(2.0), 1);  // a gesture's phases, once
  if (t == "reach") {  // there (sbm:reach-duration, else 1 s), held 1 s, back as long; contact = ready
    const Attribute* a = b.attribute("reach-duration");
    const auto v = a ? parseNumberList(a->value) : std::nullopt;
    const double go = v && v->size() == 1 && (*v)[0] > 0.0f && (*v)[0] <= 3600.0f ? (*v)[0] : 1.0, total = 2.0 * go + 1.0;
    return fromProportions({{"start", 0}, {"ready", go / total}, {"stroke", go / total}, {"relax", (go + 1.0) / total}, {"end", 1}},
                           total);
  }
  if (t == "gaze" || t == "posture" || t == "locomotion")
    return fromProportions({{"start", 0}, {"ready", .25}, {"relax", .75}, {"end", 1}}, natural.value_or(2.0));
  if (t == "faceLexeme" || t == "faceFacs" || t == "face")
    return fromProportions({{"start", 0}, {"attackPeak", .2}, {"relax", .8}, {"end", 1}}, natural.value_or(1.5));
  // gazeShift, headDirectionShift, postureShift, faceShift: a transition to a new state.
  return fromProportions({{"start", 0}, {"end", 1}}, natural.value_or(1.0));
}

}  // namespace marionette::bml
