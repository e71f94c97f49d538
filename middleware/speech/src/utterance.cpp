// Utterance look-ups and the timing repair every speech source goes through.
#include "marionette/speech/utterance.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>

namespace marionette::speech {

std::optional<double> Utterance::markTime(std::string_view id) const noexcept {
  for (const Mark& mark : marks)
    if (mark.id == id) return mark.time;
  return std::nullopt;
}

namespace {

void warn(Utterance& u, std::size_t count, const char* what) {
  if (count == 0) return;
  u.warnings.push_back("timing repaired: " + std::to_string(count) + " " + what);
}

}  // namespace

void normalizeTiming(Utterance& u) {
  // A phoneme without a finite start cannot be placed anywhere: drop it. One
  // with only a bad end keeps its place and ends where the next one starts.
  const auto before = u.phonemes.size();
  std::erase_if(u.phonemes, [](const Phoneme& p) { return !std::isfinite(p.start); });
  warn(u, before - u.phonemes.size(), "phoneme(s) dropped: their start time was not a finite number");

  std::size_t badEnds = 0;
  for (Phoneme& p : u.phonemes)
    if (!std::isfinite(p.end)) {
      p.end = std::numeric_limits<double>::quiet_NaN();  // filled in below, once the order is known
      ++badEnds;
    }

  // Stable: phonemes with equal starts keep the source's order (the order it spoke them).
  std::size_t outOfOrder = 0;
  for (std::size_t i = 1; i < u.phonemes.size(); ++i)
    if (u.phonemes[i].start < u.phonemes[i - 1].start) ++outOfOrder;
  if (outOfOrder > 0)
    std::stable_sort(u.phonemes.begin(), u.phonemes.end(),
                     [](const Phoneme& a, const Phoneme& b) { return a.start < b.start; });
  warn(u, outOfOrder, "phoneme start time(s) went backwards; phonemes sorted by start");

  // The audio is the truth about how long the utterance is; without audio the phonemes say.
  const bool hasAudio = !u.audio.empty() && u.sampleRate > 0;
  if (!u.audio.empty() && u.sampleRate <= 0)
    u.warnings.push_back("timing: the audio has no sample rate (" + std::to_string(u.sampleRate) +
                         "); the duration is taken from the phonemes instead");
  double duration = 0.0;
  if (hasAudio) {
    duration = static_cast<double>(u.audio.size()) / u.sampleRate;
  } else {
    for (const Phoneme& p : u.phonemes) duration = std::max({duration, p.start, std::isnan(p.end) ? 0.0 : p.end});
  }
  u.duration = duration;

  std::size_t clamped = 0;
  for (Phoneme& p : u.phonemes) {
    const double s = std::clamp(p.start, 0.0, duration);
    const double e = std::isnan(p.end) ? p.end : std::clamp(p.end, 0.0, duration);
    if (s != p.start || (!std::isnan(e) && e != p.end)) ++clamped;
    p.start = s;
    p.end = e;
  }
  warn(u, clamped, "phoneme(s) had times outside the utterance [0, duration]; clamped");

  std::size_t reversed = 0, overlaps = 0;
  for (std::size_t i = 0; i < u.phonemes.size(); ++i) {
    Phoneme& p = u.phonemes[i];
    const double next = i + 1 < u.phonemes.size() ? u.phonemes[i + 1].start : duration;
    if (std::isnan(p.end)) {
      p.end = next;
      continue;
    }
    if (p.end < p.start) {
      p.end = p.start;
      ++reversed;
    }
    if (i + 1 < u.phonemes.size() && p.end > next) {
      p.end = next;
      ++overlaps;
    }
  }
  warn(u, badEnds, "phoneme end time(s) were not finite numbers; each now ends where the next begins");
  warn(u, reversed, "phoneme(s) ended before they started; made zero-length");
  warn(u, overlaps, "phoneme(s) overlapped the next one; cut at the next one's start");

  // Marks are kept whatever their time (a scheduler waits on every id): a
  // non-finite time takes the previous mark's time, then all are clamped and
  // made non-decreasing in text order.
  std::size_t badMarks = 0, clampedMarks = 0, backwardMarks = 0;
  double previous = 0.0;
  for (Mark& m : u.marks) {
    if (!std::isfinite(m.time)) {
      m.time = std::isinf(m.time) && m.time > 0 ? duration : previous;
      ++badMarks;
    }
    const double t = std::clamp(m.time, 0.0, duration);
    if (t != m.time) ++clampedMarks;
    m.time = t;
    if (m.time < previous) {
      m.time = previous;
      ++backwardMarks;
    }
    previous = m.time;
  }
  warn(u, badMarks, "mark time(s) were not finite numbers; replaced by the previous mark's time (+inf: the end)");
  warn(u, clampedMarks, "mark time(s) were outside the utterance [0, duration]; clamped");
  warn(u, backwardMarks, "mark time(s) went backwards in text order; moved to the previous mark's time");
}

}  // namespace marionette::speech
