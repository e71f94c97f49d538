// Measures of lip-sync curves against phoneme times, shared by the speech tests
// and the lip-sync work-precision program (docs/accuracy.md).
//
// Viseme onset error. Phonemes are taken in order of start; consecutive ones that
// show the same viseme form a run (say "t d" -> DD DD), measured as one unit from
// the first one's start to the last one's end. Pauses and phonemes whose viseme is
// sil (the mouth at rest) are not measured and end a run. For a unit [s, e] on
// viseme channel v: the peak P is the largest value of v over [s, e] (evaluated
// every 0.5 ms, and at e); from the first instant of that peak, the search goes
// backwards to where v was last below P / 2 (linear between the two 0.5 ms
// points around it); the onset error is that instant minus s (negative: the lips
// move before the sound). When the channel rises again on the way back (by a
// tenth of P above the lowest value seen: an earlier phoneme with the same
// viseme, say "aa" in "a-ta", whose shape never fully went), the onset is the
// bottom of that dip instead (counted in `dips`). Before the curves' start the
// mouth is at rest, so the search always ends.
//
// Bilabial closure. A P / B / M is closed when PP >= 0.9 and jawOpen <= 0.1 at
// some instant of [start, end] (every 0.5 ms, and at both ends; a zero-length one
// at its start).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "marionette/speech/lipsync.hpp"

namespace marionette::test {

inline constexpr double kLipMeasureStep = 0.0005;

struct OnsetReport {
  std::vector<double> errors;  // seconds, one per measured unit
  std::vector<double> peaks;   // each unit's peak P (how far its viseme shows), in [0,1]
  int units = 0;               // measured units (runs)
  int phonemesInRuns = 0;      // phonemes those units cover
  int merged = 0;              // phonemes merged into a run started by an earlier one
  int invisible = 0;           // units whose peak stayed under 0.05 (counted, error not taken)
  int dips = 0;                // units whose onset is the bottom of a dip, not a half-peak crossing
};

inline float lipChannelAt(const speech::VisemeCurves& curves, double t, int channel) {
  std::array<float, speech::kLipChannelCount> w{};
  curves.evaluate(t, w);
  return w[static_cast<std::size_t>(channel)];
}

inline std::vector<speech::Phoneme> sortedByStart(std::span<const speech::Phoneme> phonemes) {
  std::vector<speech::Phoneme> v(phonemes.begin(), phonemes.end());
  std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.start < b.start; });
  return v;
}

inline OnsetReport measureOnsets(std::span<const speech::Phoneme> phonemes, const speech::VisemeCurves& curves) {
  OnsetReport r;
  const std::vector<speech::Phoneme> ps = sortedByStart(phonemes);
  const auto shows = [](const speech::Phoneme& p) { return !p.cls.pause && p.cls.viseme != speech::Viseme::sil; };
  for (std::size_t i = 0; i < ps.size();) {
    if (!shows(ps[i])) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < ps.size() && shows(ps[j]) && ps[j].cls.viseme == ps[i].cls.viseme) ++j;
    const double s = ps[i].start;
    const double e = std::max(s, ps[j - 1].end);
    const int channel = static_cast<int>(ps[i].cls.viseme);
    ++r.units;
    r.phonemesInRuns += static_cast<int>(j - i);
    r.merged += static_cast<int>(j - i - 1);
    i = j;
    float peak = -1.0f;
    double tPeak = s;
    for (double t = s;; t += kLipMeasureStep) {
      const double at = std::min(t, e);
      const float v = lipChannelAt(curves, at, channel);
      if (v > peak) {
        peak = v;
        tPeak = at;
      }
      if (at >= e) break;
    }
    r.peaks.push_back(peak);
    if (peak < 0.05f) {
      ++r.invisible;
      continue;
    }
    const float half = 0.5f * peak;
    double after = tPeak;
    float vAfter = peak;
    double onset = tPeak;
    float lowest = peak;
    double tLowest = tPeak;
    for (double t = tPeak - kLipMeasureStep;; t -= kLipMeasureStep) {
      const float v = lipChannelAt(curves, t, channel);
      if (v < half) {
        onset = t + (after - t) * static_cast<double>((half - v) / (vAfter - v));
        break;
      }
      if (v < lowest) {
        lowest = v;
        tLowest = t;
      } else if (v > lowest + 0.1f * peak) {
        onset = tLowest;
        ++r.dips;
        break;
      }
      after = t;
      vAfter = v;
      if (t < -1.0) break;  // unreachable: before 0 the channel is at rest (0)
    }
    r.errors.push_back(onset - s);
  }
  return r;
}

struct ErrorStats {
  double meanAbs = 0.0, p95Abs = 0.0, maxAbs = 0.0, mean = 0.0;
  double shareUnder(double threshold, std::span<const double> errors) const {
    if (errors.empty()) return 1.0;
    const auto n = std::count_if(errors.begin(), errors.end(), [&](double e) { return std::fabs(e) <= threshold; });
    return static_cast<double>(n) / static_cast<double>(errors.size());
  }
};

// p95: the smallest |error| that at least 95 % of the units are within.
inline ErrorStats errorStats(std::span<const double> errors) {
  ErrorStats st;
  if (errors.empty()) return st;
  std::vector<double> a;
  for (const double e : errors) {
    a.push_back(std::fabs(e));
    st.mean += e;
  }
  std::sort(a.begin(), a.end());
  for (const double v : a) st.meanAbs += v;
  st.meanAbs /= static_cast<double>(a.size());
  st.mean /= static_cast<double>(a.size());
  const auto idx = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(a.size()))) - 1;
  st.p95Abs = a[std::min(idx, a.size() - 1)];
  st.maxAbs = a.back();
  return st;
}

// The phonemes repeated back to back until `seconds` (the last one cut there):
// a longer utterance of real timing, for the 10 s build benchmark.
inline std::vector<speech::Phoneme> tiledTo(std::span<const speech::Phoneme> phonemes, double seconds) {
  std::vector<speech::Phoneme> out;
  double length = 0.0;
  for (const auto& p : phonemes) length = std::max(length, p.end);
  if (!(length > 0.0)) return out;
  for (double offset = 0.0; offset < seconds; offset += length)
    for (speech::Phoneme p : phonemes) {
      p.start += offset;
      p.end = std::min(p.end + offset, seconds);
      if (p.start < seconds) out.push_back(std::move(p));
    }
  return out;
}

struct ClosureReport {
  int bilabials = 0;
  int missed = 0;
  double worstPP = 1.0, worstJaw = 0.0;  // of the missed ones' best instants
};

inline ClosureReport measureClosures(std::span<const speech::Phoneme> phonemes, const speech::VisemeCurves& curves) {
  ClosureReport r;
  std::array<float, speech::kLipChannelCount> w{};
  for (const speech::Phoneme& p : phonemes) {
    if (!p.cls.bilabial || !std::isfinite(p.start) || !std::isfinite(p.end)) continue;
    ++r.bilabials;
    bool closed = false;
    double bestPP = 0.0, bestJaw = 1.0;
    const double e = std::max(p.start, p.end);
    for (double t = std::min(p.start, p.end);; t += kLipMeasureStep) {
      const double at = std::min(t, e);
      curves.evaluate(at, w);
      const float pp = w[static_cast<std::size_t>(speech::Viseme::PP)];
      const float jaw = w[speech::kJawOpenChannel];
      if (pp >= 0.9f && jaw <= 0.1f) {
        closed = true;
        break;
      }
      if (pp > bestPP) {
        bestPP = pp;
        bestJaw = jaw;
      }
      if (at >= e) break;
    }
    if (!closed) {
      ++r.missed;
      r.worstPP = std::min(r.worstPP, bestPP);
      r.worstJaw = std::max(r.worstJaw, bestJaw);
    }
  }
  return r;
}

}  // namespace marionette::test
