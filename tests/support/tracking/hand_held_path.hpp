// The stress sequences' hand-held camera (stress_scenarios.hpp): the seeded random streams, the
// path (a look that drifts, turns about camera axes at bounded speed and acceleration, a wrist's
// tremor) and each class's plan of turns. Internal to the stress generator (stress_scenarios.cpp
// makes the frames, hands and photometric effects from it).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "marionette/core/split_mix.hpp"
#include "tracking/stress_scenarios.hpp"
#include "tracking/synthetic_sequence.hpp"

namespace marionette::ar::synthetic::handheld {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2 * kPi;

inline double radians(double deg) { return deg * kPi / 180; }

// Draws from SplitMix64 with the distributions written out: std::uniform_real_distribution and
// its kin give other numbers with another standard library.
class Random {
 public:
  enum Purpose : std::uint64_t { kPath = 1, kMoves, kHands, kPhotometric, kNoise, kPicture };
  Random(std::uint64_t seed, StressClass kind, Purpose purpose)
      : mix_{seed * 0x9E3779B97F4A7C15ull ^ (static_cast<std::uint64_t>(kind) + 1) * 0xD1B54A32D192ED03ull ^
             static_cast<std::uint64_t>(purpose) * 0x8CB92BA72F3D8DD7ull} {
    mix_.next();
  }
  double uniform() { return static_cast<double>(mix_.next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  bool chance(double p) { return uniform() < p; }
  int below(int n) { return std::min(n - 1, static_cast<int>(uniform() * n)); }
  double sign() { return chance(0.5) ? 1.0 : -1.0; }
  // A peak speed from lo up to the budget (the budget alone when it is below lo).
  double speed(double lo, double budget) { return uniform(std::min(lo, budget), budget); }
  std::uint32_t bits32() { return static_cast<std::uint32_t>(mix_.next() >> 32); }

 private:
  SplitMix64 mix_;
};

// The quintic smoothstep: zero speed and acceleration at both ends; its largest slope and
// curvature bound a turn's speed and acceleration.
inline double smoother(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6 * x - 15) + 10);
}
inline constexpr double kSmootherPeakSlope = 1.875;
inline constexpr double kSmootherPeakCurvature = 5.773502691896258;  // 10 / sqrt(3), at x = 0.211

// Rodrigues: the rotation by `angle` radians about the unit `axis`.
[[nodiscard]] glm::dmat3 rotation(glm::dvec3 axis, double angle);
// The rotation by |v| radians about v.
[[nodiscard]] glm::dmat3 rotationVector(glm::dvec3 v);

struct Wave {
  double amplitude = 0, frequency = 0, phase = 0;
  [[nodiscard]] double at(double t) const { return amplitude * std::sin(kTwoPi * frequency * t + phase); }
};

template <std::size_t N>
double sumAt(const std::array<Wave, N>& waves, double t) {
  double s = 0;
  for (const Wave& w : waves) s += w.at(t);
  return s;
}

// A rotation about a camera axis (after the turns before it), its angle along `smoother`.
struct Turn {
  glm::dvec3 axis{0, 1, 0};
  double start = 0, duration = 1, angle = 0;  // seconds, seconds, radians
  [[nodiscard]] double at(double t) const { return angle * smoother((t - start) / duration); }
};

// The hand-held camera: R(t) = look(t) turns(t) tremor(t), about a wrist pivotBack behind it.
struct HandHeldPath {
  glm::dvec3 eye{0, 1, 1}, aim{0.0};
  double rollDeg = 0;
  std::array<std::array<Wave, 2>, 3> eyeWaves{}, aimWaves{}, tremorDegWaves{};  // per world / camera axis
  Wave rollDegWave;
  double pivotBack = 0.2;
  std::vector<Turn> turns;

  [[nodiscard]] glm::dvec3 eyeAt(double t) const {
    return eye + glm::dvec3(sumAt(eyeWaves[0], t), sumAt(eyeWaves[1], t), sumAt(eyeWaves[2], t));
  }
  [[nodiscard]] glm::dmat3 look(double t) const {
    const glm::dvec3 a = aim + glm::dvec3(sumAt(aimWaves[0], t), sumAt(aimWaves[1], t), sumAt(aimWaves[2], t));
    return glm::dmat3(lookAtCameraToWorld(eyeAt(t), a, glm::dvec3(0, 1, 0))) *
           rotation(glm::dvec3(0, 0, 1), radians(rollDeg + rollDegWave.at(t)));
  }
  [[nodiscard]] glm::dmat3 tremor(double t) const {
    return rotationVector(glm::dvec3(radians(sumAt(tremorDegWaves[0], t)), radians(sumAt(tremorDegWaves[1], t)),
                                     radians(sumAt(tremorDegWaves[2], t))));
  }
  [[nodiscard]] glm::dmat3 turned(double t) const {
    glm::dmat3 e(1.0);
    for (const Turn& turn : turns) e = e * rotation(turn.axis, turn.at(t));
    return e;
  }
  // Camera-to-world at t, with an extra rotation after the turns (the planner's trial turn).
  [[nodiscard]] glm::dmat4 at(double t, glm::dvec3 extraAxis = glm::dvec3(0, 0, 1), double extraAngle = 0) const {
    const glm::dmat3 l = look(t);
    const glm::dmat3 r = l * turned(t) * rotation(extraAxis, extraAngle) * tremor(t);
    const glm::dvec3 pivot = eyeAt(t) + l * glm::dvec3(0, 0, pivotBack);
    glm::dmat4 m(r);
    m[3] = glm::dvec4(pivot - r * glm::dvec3(0, 0, pivotBack), 1);
    return m;
  }
};

// A class's base path: where the camera stands and looks, its drift and tremor, no turns.
[[nodiscard]] HandHeldPath basePath(Random& rng, double targetWidth);
// The turns of each class over `seconds` (stress_scenarios.hpp says what each class promises).
void planPan(const SequenceRenderer& r, HandHeldPath& p, Random& rng, double seconds);
void planReentry(const SequenceRenderer& r, HandHeldPath& p, Random& rng, double seconds, ImageEdge edge);
void planModerate(HandHeldPath& p, Random& rng, double seconds);

}  // namespace marionette::ar::synthetic::handheld
