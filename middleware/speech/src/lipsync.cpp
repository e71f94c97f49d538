// Lip-sync curves (lipsync.hpp). Command time builds; evaluate() interpolates.
//
// Co-articulation after Cohen & Massaro (1993), "Modeling coarticulation in
// synthetic visual speech": a phoneme's dominance is flat over the central part of
// its interval and falls off exponentially on both sides (its own rates before and
// after); every channel is the dominance-weighted average of the targets of all
// phonemes near that time. Each phoneme only scatters into the samples its
// dominance reaches (until it is a thousandth of the rest dominance), so the build
// is linear in the number of phonemes plus samples, whatever their order.
#include "marionette/speech/lipsync.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace marionette::speech {

namespace {

constexpr std::array<std::string_view, kLipChannelCount> kChannelNames = {
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou",
    "vrm_aa", "vrm_ih", "vrm_ou", "vrm_ee", "vrm_oh", "jawOpen"};
constexpr int kPP = static_cast<int>(Viseme::PP);
constexpr std::size_t kC = kLipChannelCount;

double inRange(double v, double lo, double hi, double fallback) {
  return std::isfinite(v) && v >= lo && v <= hi ? v : fallback;
}

LipSyncSettings sanitized(const LipSyncSettings& in) {
  const LipSyncSettings d;
  LipSyncSettings s;
  s.sampleRate = inRange(in.sampleRate, 1.0, 1e4, d.sampleRate);
  s.maxFrames = in.maxFrames >= 2 && in.maxFrames <= (1 << 24) ? in.maxFrames : d.maxFrames;
  s.anticipationRate = inRange(in.anticipationRate, 1.0, 1e4, d.anticipationRate);
  s.carryOverRate = inRange(in.carryOverRate, 1.0, 1e4, d.carryOverRate);
  s.dominanceWidth = inRange(in.dominanceWidth, 0.0, 1.0, d.dominanceWidth);
  s.pauseDominance = inRange(in.pauseDominance, 1e-4, 1e2, d.pauseDominance);
  s.restDominance = inRange(in.restDominance, 1e-6, 1e2, d.restDominance);
  s.minVisible = inRange(in.minVisible, 0.0, 1.0, d.minVisible);
  s.maxSpeed = std::isnan(in.maxSpeed) ? d.maxSpeed : in.maxSpeed;  // <= 0 or +inf: no limit
  s.closureHold = inRange(in.closureHold, 0.0, 1.0, d.closureHold);
  return s;
}

// A phoneme ready to scatter: where its dominance is flat, how fast it falls off,
// and its target for the (at most three) channels it drives.
struct Source {
  double flatLo = 0.0, flatHi = 0.0;
  double before = 0.0, after = 0.0;  // rates, 1/s
  float alpha = 1.0f;
  int channel[3] = {-1, -1, -1};
  float target[3] = {0.0f, 0.0f, 0.0f};
};

// Slew limit to `step` per sample: the mean of a forward and a backward pass.
// Each pass keeps every difference within `step`, so does their mean; the forward
// pass delays a change and the backward pass advances it, so the mean stays
// centred on the original change. Samples already within `step` of a pinned value
// on a cone (see buildVisemeCurves) are never moved. Eight channels at a time:
// the inner loop vectorises across channels (one channel alone is a chain of
// dependent clamps), and the scratch stays small (fresh pages cost more than the
// arithmetic here).
constexpr std::size_t kGroup = 8;
void limitSpeed(float* values, int frames, float step, std::vector<float>& fwd) {
  const auto n = static_cast<std::size_t>(frames);
  fwd.resize(n * kGroup);
  for (std::size_t c0 = 0; c0 < kC; c0 += kGroup) {
    const std::size_t g = std::min(kGroup, kC - c0);
    std::copy_n(values + c0, g, fwd.data());
    for (std::size_t k = 1; k < n; ++k) {
      const float* prev = fwd.data() + (k - 1) * kGroup;
      const float* v = values + k * kC + c0;
      float* cur = fwd.data() + k * kGroup;
      for (std::size_t c = 0; c < g; ++c) cur[c] = std::clamp(v[c], prev[c] - step, prev[c] + step);
    }
    std::array<float, kGroup> next{};
    std::copy_n(values + (n - 1) * kC + c0, g, next.begin());
    for (std::size_t k = n; k-- > 0;) {
      float* v = values + k * kC + c0;
      const float* f = fwd.data() + k * kGroup;
      for (std::size_t c = 0; c < g; ++c) {
        next[c] = std::clamp(v[c], next[c] - step, next[c] + step);
        v[c] = 0.5f * (next[c] + f[c]);
      }
    }
  }
}

}  // namespace

std::string_view lipChannelName(int channel) noexcept {
  return channel >= 0 && channel < kLipChannelCount ? kChannelNames[static_cast<std::size_t>(channel)]
                                                    : std::string_view();
}

std::optional<int> lipChannelFromName(std::string_view name) noexcept {
  for (int c = 0; c < kLipChannelCount; ++c)
    if (lipChannelName(c) == name) return c;
  return std::nullopt;
}

void VisemeCurves::evaluate(double t, std::span<float> out) const noexcept {
  const std::size_t n = std::min(out.size(), kC);
  const bool have = frames > 0 && values.size() >= static_cast<std::size_t>(frames) * kC;
  if (!have || !(t >= 0.0) || !(t <= duration) || !(sampleRate > 0.0)) {
    for (std::size_t c = 0; c < n; ++c) out[c] = c == 0 ? 1.0f : 0.0f;
    return;
  }
  const double x = t * sampleRate;
  if (!(x < static_cast<double>(frames - 1))) {
    const float* last = values.data() + static_cast<std::size_t>(frames - 1) * kC;
    for (std::size_t c = 0; c < n; ++c) out[c] = last[c];
    return;
  }
  const auto k = static_cast<std::size_t>(x);
  const float f = static_cast<float>(x - static_cast<double>(k));
  const float* a = values.data() + k * kC;
  const float* b = a + kC;
  for (std::size_t c = 0; c < n; ++c) out[c] = a[c] + f * (b[c] - a[c]);
}

VisemeCurves buildVisemeCurves(std::span<const Phoneme> phonemes, double duration, const LipSyncSettings& settingsIn) {
  const LipSyncSettings s = sanitized(settingsIn);
  VisemeCurves curves;
  curves.sampleRate = s.sampleRate;

  // A duration that is not a number: the last finite phoneme end.
  if (!std::isfinite(duration) || duration < 0.0) {
    duration = 0.0;
    for (const Phoneme& p : phonemes)
      if (std::isfinite(p.start) && std::isfinite(p.end)) duration = std::max({duration, p.start, p.end});
  }
  curves.duration = duration;
  if (!(duration > 0.0)) return curves;  // no time: always at rest
  if (duration * s.sampleRate + 1.0 > static_cast<double>(s.maxFrames))
    curves.sampleRate = static_cast<double>(s.maxFrames - 1) / duration;
  const double rate = curves.sampleRate;
  const int frames = static_cast<int>(
      std::min(static_cast<double>(s.maxFrames), std::ceil(duration * rate) + 1.0));
  curves.frames = frames;

  // Sources. Non-finite times are skipped; a reversed interval is turned round;
  // times are clamped into [0, duration].
  std::vector<Source> sources;
  sources.reserve(phonemes.size());
  std::vector<double> closures;  // bilabial centres
  for (const Phoneme& p : phonemes) {
    if (!std::isfinite(p.start) || !std::isfinite(p.end)) continue;
    const double a = std::clamp(std::min(p.start, p.end), 0.0, duration);
    const double b = std::clamp(std::max(p.start, p.end), 0.0, duration);
    const PhonemeClass& cls = p.cls;
    Source src;
    const double centre = 0.5 * (a + b);
    const double half = 0.5 * s.dominanceWidth * (b - a);
    src.flatLo = centre - half;
    src.flatHi = centre + half;
    src.before = s.anticipationRate;
    src.after = s.carryOverRate;
    if (cls.pause) {
      // A pause pulls toward rest with a weaker dominance over all of its length:
      // the last phoneme's carry-over fades into it instead of snapping shut.
      src.flatLo = a;
      src.flatHi = b;
      src.alpha = static_cast<float>(s.pauseDominance);
      src.channel[0] = 0;
      src.target[0] = 1.0f;
    } else {
      if (src.flatHi - src.flatLo < s.minVisible) {
        // Held long enough to be seen: inside the interval if it is long enough,
        // else from the phoneme's start on (onsets stay where the sound starts).
        if (b - a >= s.minVisible) {
          src.flatLo = centre - 0.5 * s.minVisible;
          src.flatHi = centre + 0.5 * s.minVisible;
        } else {
          src.flatLo = a;
          src.flatHi = a + s.minVisible;
        }
      }
      const auto vis = static_cast<int>(cls.viseme);
      src.channel[0] = vis >= 0 && vis < kVisemeCount ? vis : 0;
      src.target[0] = 1.0f;
      const auto vrm = static_cast<int>(cls.vrm);
      if (vrm >= 0 && vrm < kVrmVisemeCount) {
        src.channel[1] = kVrmChannelBase + vrm;
        src.target[1] = std::isfinite(cls.vrmAmount) ? std::clamp(cls.vrmAmount, 0.0f, 1.0f) : 0.0f;
      }
      src.channel[2] = kJawOpenChannel;
      src.target[2] = std::isfinite(cls.jawOpen) ? std::clamp(cls.jawOpen, 0.0f, 1.0f) : 0.0f;
      if (cls.bilabial) closures.push_back(centre);
    }
    sources.push_back(src);
  }

  // Time no phoneme covers (before the first, after the last, gaps) is silence:
  // without a source there, the weak rest dominance would let the nearest
  // phoneme's tail show its shape long before it starts.
  {
    std::vector<std::pair<double, double>> spans;
    spans.reserve(phonemes.size());
    for (const Phoneme& p : phonemes)
      if (std::isfinite(p.start) && std::isfinite(p.end))
        spans.emplace_back(std::clamp(std::min(p.start, p.end), 0.0, duration),
                           std::clamp(std::max(p.start, p.end), 0.0, duration));
    std::sort(spans.begin(), spans.end());
    double covered = 0.0;
    const auto silence = [&](double a, double b) {
      if (b - a <= 1e-6) return;
      Source src;
      src.flatLo = a;
      src.flatHi = b;
      src.before = s.anticipationRate;
      src.after = s.carryOverRate;
      src.alpha = static_cast<float>(s.pauseDominance);
      src.channel[0] = 0;
      src.target[0] = 1.0f;
      sources.push_back(src);
    };
    for (const auto& [a, b] : spans) {
      silence(covered, a);
      covered = std::max(covered, b);
    }
    silence(covered, duration);
  }

  // Scatter: numerators into `values`, denominators into `weight`; the rest
  // target (sil = 1) everywhere with its constant dominance.
  curves.values.assign(static_cast<std::size_t>(frames) * kC, 0.0f);
  std::vector<float> weight(static_cast<std::size_t>(frames), static_cast<float>(s.restDominance));
  float* values = curves.values.data();
  for (int k = 0; k < frames; ++k) values[static_cast<std::size_t>(k) * kC] = static_cast<float>(s.restDominance);
  const double cutoff = 1e-3 * s.restDominance;  // smaller dominance moves no value by more than 0.1 %
  const double last = static_cast<double>(frames - 1);
  for (const Source& src : sources) {
    const double reach = std::log(std::max(1.0, src.alpha / cutoff));
    const double lo = std::clamp(std::ceil((src.flatLo - reach / src.before) * rate), 0.0, last);
    const double hi = std::clamp(std::floor((src.flatHi + reach / src.after) * rate), 0.0, last);
    for (auto k = static_cast<int>(lo); k <= static_cast<int>(hi); ++k) {
      const double t = k / rate;
      double d = src.alpha;
      if (t < src.flatLo)
        d *= std::exp(-src.before * (src.flatLo - t));
      else if (t > src.flatHi)
        d *= std::exp(-src.after * (t - src.flatHi));
      const auto df = static_cast<float>(d);
      weight[static_cast<std::size_t>(k)] += df;
      float* row = values + static_cast<std::size_t>(k) * kC;
      for (int j = 0; j < 3; ++j)
        if (src.channel[j] >= 0) row[src.channel[j]] += df * src.target[j];
    }
  }
  for (int k = 0; k < frames; ++k) {
    const float inv = 1.0f / weight[static_cast<std::size_t>(k)];
    float* row = values + static_cast<std::size_t>(k) * kC;
    for (std::size_t c = 0; c < kC; ++c) row[c] *= inv;
  }

  // Closure: every P / B / M holds PP = 1 and everything else (jaw included) at 0
  // on the two samples around its centre (so that the interpolated curve is closed
  // at the centre, even for a zero-length phoneme between samples) and on every
  // sample within closureHold / 2 of the centre.
  std::vector<std::uint8_t> pinned(static_cast<std::size_t>(frames), 0);
  for (const double c : closures) {
    const double x = c * rate;
    const double h = 0.5 * s.closureHold * rate;
    const auto from = static_cast<int>(std::clamp(std::min(std::floor(x), std::ceil(x - h)), 0.0, last));
    const auto to = static_cast<int>(std::clamp(std::max(std::ceil(x), std::floor(x + h)), 0.0, last));
    for (int k = from; k <= to; ++k) pinned[static_cast<std::size_t>(k)] = 1;
  }
  for (int k = 0; k < frames; ++k)
    if (pinned[static_cast<std::size_t>(k)]) curves.closureFrames.push_back(k);

  const bool limited = s.maxSpeed > 0.0 && std::isfinite(s.maxSpeed);
  const auto step = static_cast<float>(limited ? s.maxSpeed / rate : 2.0);
  if (!curves.closureFrames.empty()) {
    // Closure wins over the speed limit by starting early: each channel is first
    // kept inside the cone that the limit allows around the pinned values (PP at
    // least 1 - step * distance, the others at most step * distance). A curve that
    // respects the cones keeps the pins through the limiter, whose passes never
    // leave a cone that is itself within the limit.
    std::vector<int> dist(static_cast<std::size_t>(frames));
    int run = std::numeric_limits<int>::max() / 2;
    for (int k = 0; k < frames; ++k) {
      run = pinned[static_cast<std::size_t>(k)] ? 0 : run + 1;
      dist[static_cast<std::size_t>(k)] = run;
    }
    run = std::numeric_limits<int>::max() / 2;
    for (int k = frames - 1; k >= 0; --k) {
      run = pinned[static_cast<std::size_t>(k)] ? 0 : run + 1;
      dist[static_cast<std::size_t>(k)] = std::min(dist[static_cast<std::size_t>(k)], run);
    }
    for (int k = 0; k < frames; ++k) {
      const double reachOfPin = static_cast<double>(step) * dist[static_cast<std::size_t>(k)];
      if (reachOfPin >= 1.0) continue;
      const auto r = static_cast<float>(reachOfPin);
      float* row = values + static_cast<std::size_t>(k) * kC;
      for (std::size_t c = 0; c < kC; ++c)
        row[c] = static_cast<int>(c) == kPP ? std::max(row[c], 1.0f - r) : std::min(row[c], r);
    }
  }
  if (limited && frames > 1) {
    std::vector<float> scratch;
    limitSpeed(values, frames, step, scratch);
  }
  for (float& v : curves.values) v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
  return curves;
}

}  // namespace marionette::speech
