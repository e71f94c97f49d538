#include "marionette/behavior/head_motion.hpp"

#include "marionette/core/easing.hpp"
#include "marionette/core/text.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace marionette {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxCycles = 4;

// The peak of |sin(2 pi c u) sin(pi u)| over u in [0, 1]: what makes an oscillation's peak 1.
double oscillationPeak(int cycles) noexcept {
  static const std::array<double, kMaxCycles + 1> peaks = [] {
    std::array<double, kMaxCycles + 1> out{};
    for (int c = 1; c <= kMaxCycles; ++c)
      for (int i = 0; i <= 20000; ++i) {
        const double u = i / 20000.0;
        out[static_cast<std::size_t>(c)] =
            std::max(out[static_cast<std::size_t>(c)], std::abs(std::sin(2.0 * kPi * c * u) * std::sin(kPi * u)));
      }
    return out;
  }();
  return peaks[static_cast<std::size_t>(std::clamp(cycles, 1, kMaxCycles))];
}
}  // namespace

HeadMove headMove(const HeadParameters& p) noexcept {
  switch (p.lexeme) {
    case HeadLexeme::Nod: return {{25.0f, 0.0f, 0.0f}, HeadShape::RiseFall, 1};
    case HeadLexeme::Shake: return {{0.0f, 30.0f, 0.0f}, HeadShape::Oscillate, 1};
    case HeadLexeme::Tilt: return {{0.0f, 0.0f, 20.0f}, HeadShape::RiseFall, 1};
    case HeadLexeme::Toss: return {{0.0f, 0.0f, 15.0f}, HeadShape::RiseFall, 1};
    case HeadLexeme::Wiggle: return {{8.0f, 0.0f, 0.0f}, HeadShape::Oscillate, 2};
    case HeadLexeme::Waggle: return {{0.0f, 0.0f, 10.0f}, HeadShape::Oscillate, 2};
    case HeadLexeme::Orient: return {p.orientDegrees, HeadShape::Hold, 1};
  }
  return {};
}

float headPeakAngle(HeadLexeme lexeme) noexcept {
  return glm::radians(glm::length(headMove(HeadParameters{lexeme}).degrees));
}

glm::vec3 headAxis(HeadLexeme lexeme) noexcept {
  const glm::vec3 d = headMove(HeadParameters{lexeme}).degrees;
  return glm::length(d) > 0.0f ? glm::normalize(d) : glm::vec3(1, 0, 0);
}

float headShape(const HeadMove& move, std::span<const HeadStroke> strokes, const HeadPhases& phases, double t) noexcept {
  if (move.shape == HeadShape::Hold) {
    const HeadPhases& h = phases;
    if (!(t > h.start && t < h.end)) return 0.0f;
    if (t < h.ready) return static_cast<float>(smoothstep((t - h.start) / (h.ready - h.start)));
    if (t <= h.relax) return 1.0f;
    return static_cast<float>(h.end > h.relax ? smoothstep((h.end - t) / (h.end - h.relax)) : 0.0);
  }
  for (const HeadStroke& s : strokes) {
    if (!(t > s.start && t < s.end)) continue;
    if (move.shape == HeadShape::Oscillate) {
      const double u = (t - s.start) / (s.end - s.start);
      const int c = std::clamp(move.cycles, 1, kMaxCycles);
      return static_cast<float>(std::sin(2.0 * kPi * c * u) * std::sin(kPi * u) / oscillationPeak(c));  // peak |.| = 1
    }
    if (t <= s.peak) return static_cast<float>(s.peak > s.start ? smoothstep((t - s.start) / (s.peak - s.start)) : 1.0);
    return static_cast<float>(s.end > s.peak ? smoothstep((s.end - t) / (s.end - s.peak)) : 0.0);
  }
  return 0.0f;
}

float headShape(HeadLexeme lexeme, std::span<const HeadStroke> strokes, double t) noexcept {
  return headShape(headMove(HeadParameters{lexeme}), strokes, HeadPhases{}, t);
}

float fitHeadToABody(const HeadMove& move, float amount, std::vector<HeadStroke>& strokes, HeadPhases& phases,
                     std::string& warning) {
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  char text[240];
  // Thinned: consecutive strokes merged so that each lasts at least the shortest a head can do.
  if (move.shape != HeadShape::Hold && strokes.size() > 1) {
    const double span = strokes.back().end - strokes.front().start;
    const std::size_t asked = strokes.size();
    const std::size_t fit = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(0.0, span / kMinHeadStrokeSeconds)), 1, asked);
    bool tooShort = false;
    for (const HeadStroke& s : strokes) tooShort |= s.end - s.start < kMinHeadStrokeSeconds;
    if (tooShort && fit < asked) {
      std::vector<HeadStroke> merged;
      merged.reserve(fit);
      for (std::size_t g = 0; g < fit; ++g) {
        const HeadStroke& first = strokes[g * asked / fit];
        const HeadStroke& last = strokes[(g + 1) * asked / fit - 1];
        const double share = first.end > first.start ? (first.peak - first.start) / (first.end - first.start) : 0.5;
        merged.push_back({first.start, first.start + share * (last.end - first.start), last.end});
      }
      std::snprintf(text, sizeof text, "%zu repetitions in %.3f s are more than a head can make (a stroke lasts at least %.2f s); thinned to %zu",
                    asked, span, kMinHeadStrokeSeconds, fit);
      note(text);
      strokes = std::move(merged);
    }
  }
  // Slowed: no part of the move turns the head faster than a head can. A smoothstep over d
  // seconds turns at most 1.5 A / d, so a rise or a return of A degrees takes at least
  // 1.5 A / kMaxHeadDegreesPerSecond: the stroke's peak (a hold's ready, relax) moves to make
  // room, and where a stroke is too short for both, or an oscillation too fast, the angle is made smaller.
  const double degrees = static_cast<double>(glm::length(move.degrees)) * std::abs(static_cast<double>(amount));
  if (!(degrees > 0.0)) return amount;
  const double shortest = 1.5 * degrees / kMaxHeadDegreesPerSecond;
  double scale = 1.0;
  int moved = 0;
  auto fit = [&](double from, double& middle, double to) {  // a rise from..middle and a fall middle..to
    const double span = to - from;
    if (!(span > 0.0)) return;
    if (span < 2.0 * shortest * (1.0 - 1e-9)) {
      scale = std::min(scale, span / (2.0 * shortest));
      if (std::abs(middle - (from + 0.5 * span)) > 1e-9) ++moved;
      middle = from + 0.5 * span;
      return;
    }
    const double before = middle;
    middle = std::clamp(middle, from + shortest, to - shortest);
    if (middle != before) ++moved;
  };
  if (move.shape == HeadShape::Hold) {
    HeadPhases& h = phases;
    double readyEnd = h.ready, relaxStart = h.relax;
    // To the direction within start..ready (at least `shortest`), back within relax..end.
    if (h.ready - h.start < shortest) readyEnd = std::min(h.start + shortest, h.relax), ++moved;
    if (h.end - h.relax < shortest) relaxStart = std::max(h.end - shortest, readyEnd), ++moved;
    const double tightest = std::min(readyEnd - h.start, h.end - relaxStart);
    if (tightest < shortest * (1.0 - 1e-9)) scale = std::min(scale, std::max(0.0, tightest) / shortest);
    h.ready = readyEnd;
    h.relax = relaxStart;
  } else if (move.shape == HeadShape::RiseFall) {
    for (HeadStroke& stroke : strokes) fit(stroke.start, stroke.peak, stroke.end);
  } else {  // an oscillation: its fastest turn per second of stroke, for `cycles`, sampled once
    const double perUnit = [&] {
      double fastest = 0.0;
      const HeadStroke unit[] = {{0.0, 0.5, 1.0}};
      float before = headShape(move, unit, phases, 0.0);
      for (int i = 1; i <= 512; ++i) {
        const float now = headShape(move, unit, phases, i / 512.0);
        fastest = std::max(fastest, std::abs(static_cast<double>(now - before)) * 512.0);
        before = now;
      }
      return fastest;
    }();
    for (const HeadStroke& stroke : strokes) {
      const double d = stroke.end - stroke.start;
      if (d > 0.0) scale = std::min(scale, kMaxHeadDegreesPerSecond * d / (perUnit * degrees));
    }
  }
  if (moved > 0) {
    std::snprintf(text, sizeof text, "slowed to what a head can do (%.0f degrees/s at most: %.0f degrees take %.3f s); %d stroke phase(s) moved",
                  kMaxHeadDegreesPerSecond, degrees, shortest, moved);
    note(text);
  }
  if (scale < 1.0) {
    std::snprintf(text, sizeof text, "too fast for a head (%.0f degrees/s at most); its angle made smaller (%.0f %%)",
                  kMaxHeadDegreesPerSecond, 100.0 * scale);
    note(text);
  }
  return static_cast<float>(amount * std::min(1.0, scale));
}

glm::quat headRotation(const glm::vec3& r) noexcept {
  return glm::angleAxis(r.y, glm::vec3(0, 1, 0)) * glm::angleAxis(r.x, glm::vec3(1, 0, 0)) *
         glm::angleAxis(r.z, glm::vec3(0, 0, 1));
}

void rotateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::quat& delta) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= pose.size()) return;
  // Parent model rotation: the root space's rotation, then the chain's local rotations.
  // The root space may scale (centimetre files): take its rotation only.
  glm::mat3 root(skeleton.rootTransform);
  for (int c = 0; c < 3; ++c) root[c] = glm::length(root[c]) > 0.0f ? glm::normalize(root[c]) : root[c];
  glm::quat parent = safeNormalize(glm::quat_cast(root));
  int chain[256];
  int n = 0;
  for (int p = skeleton.parents[static_cast<std::size_t>(joint)]; p >= 0 && n < 256; p = skeleton.parents[static_cast<std::size_t>(p)])
    chain[n++] = p;
  for (int i = n - 1; i >= 0; --i) parent = parent * pose[static_cast<std::size_t>(chain[i])].rotation;
  Transform& t = pose[static_cast<std::size_t>(joint)];
  t.rotation = safeNormalize(glm::inverse(parent) * delta * parent * t.rotation);
}

void translateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::vec3& delta) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= pose.size()) return;
  glm::mat3 parent(skeleton.rootTransform);
  int chain[256];
  int n = 0;
  for (int p = skeleton.parents[static_cast<std::size_t>(joint)]; p >= 0 && n < 256; p = skeleton.parents[static_cast<std::size_t>(p)])
    chain[n++] = p;
  for (int i = n - 1; i >= 0; --i) parent = parent * glm::mat3(pose[static_cast<std::size_t>(chain[i])].matrix());
  // A degenerate parent (a joint scaled to zero) cannot take the offset: left as it is.
  if (!(std::fabs(glm::determinant(parent)) > 1e-12f)) return;
  const glm::vec3 local = glm::inverse(parent) * delta;
  if (std::isfinite(local.x) && std::isfinite(local.y) && std::isfinite(local.z))
    pose[static_cast<std::size_t>(joint)].translation += local;
}

}  // namespace marionette
