#include "tracking/hand_held_path.hpp"

#include <limits>

#include "tracking/trajectory_metrics.hpp"

namespace marionette::ar::synthetic::handheld {

glm::dmat3 rotation(glm::dvec3 a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), k = 1 - c;
  return glm::dmat3(glm::dvec3(c + a.x * a.x * k, a.y * a.x * k + a.z * s, a.z * a.x * k - a.y * s),
                    glm::dvec3(a.x * a.y * k - a.z * s, c + a.y * a.y * k, a.z * a.y * k + a.x * s),
                    glm::dvec3(a.x * a.z * k + a.y * s, a.y * a.z * k - a.x * s, c + a.z * a.z * k));
}

glm::dmat3 rotationVector(glm::dvec3 v) {
  const double angle = glm::length(v);
  return angle > 0 ? rotation(v / angle, angle) : glm::dmat3(1.0);
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMaxSpeedDeg = 180;     // the camera's angular speed, everything included
constexpr double kPanAcceleration = 1500;  // deg/s^2 of a turn in pan and reentry
constexpr double kModerateAcceleration = 400;
constexpr double kModerateSpeedDeg = 80;   // hands and photometric: everything included

// The shortest time a turn of angleDeg takes at peak speed speedDeg and peak acceleration
// accelerationDeg (both per second).
double turnSeconds(double angleDeg, double speedDeg, double accelerationDeg) {
  const double a = std::abs(angleDeg);
  return std::max({kSmootherPeakSlope * a / speedDeg, std::sqrt(kSmootherPeakCurvature * a / accelerationDeg), 1e-3});
}

// The largest angular speed (deg/s) of a rotation over [0, seconds], from 2 ms steps.
template <typename F>
double peakSpeedDeg(const F& rotationAt, double seconds) {
  constexpr double dt = 0.002;
  double peak = 0;
  glm::dmat4 previous(rotationAt(0.0));
  for (double t = dt; t <= seconds + dt; t += dt) {
    const glm::dmat4 current(rotationAt(t));
    peak = std::max(peak, rotationErrorDeg(previous, current) / dt);
    previous = current;
  }
  return peak;
}

// What the turns may use of `limit` deg/s: the drift's and the tremor's peaks taken off (the
// speeds of a product of rotations add at most).
double turnSpeedBudget(const HandHeldPath& p, double seconds, double limit = kMaxSpeedDeg) {
  // Past the last frame by more than half an exposure.
  const double drift = peakSpeedDeg([&p](double t) { return p.look(t); }, seconds + 0.05);
  const double tremor = peakSpeedDeg([&p](double t) { return p.tremor(t); }, seconds + 0.05);
  return limit - drift - tremor - 1.0;  // 1 deg/s for what 2 ms steps miss
}

glm::dvec3 axisOf(int kind, Random& rng) {
  switch (kind) {
    case 0: return {0, rng.sign(), 0};  // yaw about the camera's vertical
    case 1: return {rng.sign(), 0, 0};  // pitch
    case 2: return {0, 0, rng.sign()};  // roll about the optical axis
    default: {                          // oblique: mostly yaw and pitch
      const double a = rng.uniform(0, kTwoPi);
      return glm::normalize(glm::dvec3(std::cos(a), std::sin(a), rng.uniform(-0.3, 0.3)));
    }
  }
}

// The smallest extra turn about `axis` at time t that leaves none of the target in view,
// degrees; NaN when 150 deg is not enough.
double leaveAngleDeg(const SequenceRenderer& r, const HandHeldPath& p, glm::dvec3 axis, double t) {
  auto gone = [&](double deg) { return r.visibleTargetFraction(p.at(t, axis, radians(deg))) == 0; };
  double lo = 0, hi = kNaN;
  for (double a = 3; a <= 150; a += 3) {
    if (gone(a)) {
      hi = a;
      break;
    }
    lo = a;
  }
  if (std::isnan(hi)) return kNaN;
  for (int i = 0; i < 10; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gone(mid) ? hi : lo) = mid;
  }
  return hi;
}

// The extra turn in [0, upTo] degrees at which the visible share falls to `share`.
double angleForShareDeg(const SequenceRenderer& r, const HandHeldPath& p, glm::dvec3 axis, double t, double share,
                        double upTo) {
  double lo = 0, hi = upTo;
  for (int i = 0; i < 24; ++i) {
    const double mid = 0.5 * (lo + hi);
    (r.visibleTargetFraction(p.at(t, axis, radians(mid))) > share ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

HandHeldPath basePath(Random& rng, double targetWidth) {
  const double w = targetWidth;
  HandHeldPath p;
  const double distance = w * rng.uniform(2.0, 3.0);
  const double azimuth = rng.uniform(0, kTwoPi), elevation = radians(rng.uniform(40, 65));
  p.aim = {w * rng.uniform(-0.1, 0.1), 0, w * rng.uniform(-0.08, 0.08)};
  p.eye = p.aim + distance * glm::dvec3(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                                        std::cos(elevation) * std::cos(azimuth));
  p.rollDeg = rng.uniform(-8, 8);
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 2; ++k) {
      p.eyeWaves[axis][k] = {w * rng.uniform(0.01, 0.03), rng.uniform(0.1, 0.4), rng.uniform(0, kTwoPi)};
      if (axis != 1) p.aimWaves[axis][k] = {w * rng.uniform(0.01, 0.05), rng.uniform(0.1, 0.4), rng.uniform(0, kTwoPi)};
      // A hand's tremor: a few hundredths of a degree at 6..11 Hz.
      p.tremorDegWaves[axis][k] = {rng.uniform(0.015, 0.05), rng.uniform(6, 11), rng.uniform(0, kTwoPi)};
    }
  p.rollDegWave = {rng.uniform(0, 3), rng.uniform(0.1, 0.3), rng.uniform(0, kTwoPi)};
  p.pivotBack = rng.uniform(0.1, 0.3);
  return p;
}

// pan: out-and-back turns at random speeds; the first takes the target out of view.
void planPan(const SequenceRenderer& r, HandHeldPath& p, Random& rng, double seconds) {
  const double budget = turnSpeedBudget(p, seconds);
  double t = rng.uniform(0.1, 0.3);
  bool lost = false;  // whether a turn has taken the target out of view yet
  for (int move = 0; move < 8; ++move) {
    const double left = seconds - 0.15 - t;  // the last 0.15 s settle
    if (left < 0.25) break;
    const bool first = !lost;
    const int kind = first ? std::array{0, 1, 3}[rng.below(3)] : rng.below(4);
    const glm::dvec3 axis = axisOf(kind, rng);
    const bool leaving = kind != 2 && (first || rng.chance(0.5));
    const double leave = leaving ? leaveAngleDeg(r, p, axis, t + 0.25) : kNaN;
    double angle = leaving ? leave + rng.uniform(5, 25) : kind == 2 ? rng.uniform(20, 100) : rng.uniform(8, 25);
    if (std::isnan(angle)) continue;  // a turn that cannot lose the target: another one
    double out = rng.speed(first ? 100 : 40, budget), back = rng.speed(60, budget), hold = rng.uniform(0, 0.25);
    const double returned = kind == 2 ? rng.uniform(0.7, 1.1) : rng.uniform(0.92, 1.08);
    auto total = [&] {
      return turnSeconds(angle, out, kPanAcceleration) + hold + turnSeconds(angle * returned, back, kPanAcceleration);
    };
    if (total() > left) {  // faster, and no pause, to fit
      out = back = budget;
      hold = 0;
    }
    if (total() > left && leaving) angle = leave + 3;
    if (total() > left && !first) break;
    const double outSeconds = turnSeconds(angle, out, kPanAcceleration);
    p.turns.push_back({axis, t, outSeconds, radians(angle)});
    const double backSeconds = turnSeconds(angle * returned, back, kPanAcceleration);
    p.turns.push_back({axis, t + outSeconds + hold, backSeconds, -radians(angle * returned)});
    t += outSeconds + hold + backSeconds + rng.uniform(0.05, 0.3);
    lost = lost || leaving;
  }
}

// reentry: away until the target is gone, back until `share` of it shows at the edge, a
// hesitation, then the rest of the way.
void planReentry(const SequenceRenderer& r, HandHeldPath& p, Random& rng, double seconds, ImageEdge edge) {
  const double budget = turnSpeedBudget(p, seconds);
  // Turning right moves the picture left: the target leaves, and comes back, by the left edge.
  const glm::dvec3 axis = edge == ImageEdge::Left    ? glm::dvec3(0, -1, 0)
                          : edge == ImageEdge::Right ? glm::dvec3(0, 1, 0)
                          : edge == ImageEdge::Top   ? glm::dvec3(-1, 0, 0)
                                                     : glm::dvec3(1, 0, 0);
  const double t0 = rng.uniform(0.2, 0.35);
  double leave = leaveAngleDeg(r, p, axis, t0 + 0.3);
  if (std::isnan(leave)) leave = 90;
  double margin = rng.uniform(5, 20), out = rng.speed(100, budget), away = rng.uniform(0.1, 0.3);
  double come = rng.speed(90, std::min(170.0, budget)), dwell = rng.uniform(0.15, 0.35);
  double finish = rng.speed(60, std::min(150.0, budget));
  const double share = rng.uniform(0.15, 0.45), residual = rng.uniform(-2, 2);
  double partial = 0.7 * leave;
  auto total = [&] {
    return turnSeconds(leave + margin, out, kPanAcceleration) + away +
           turnSeconds(leave + margin - partial, come, kPanAcceleration) + dwell +
           turnSeconds(partial - residual, finish, kPanAcceleration);
  };
  for (int pass = 0; pass < 2; ++pass) {
    if (t0 + total() + 0.1 > seconds) {  // squeeze: less margin, shorter pauses, faster
      margin = 3;
      away = std::min(away, 0.1);
      dwell = std::min(dwell, 0.15);
      out = budget;
      come = std::min(170.0, budget);
      finish = std::min(150.0, budget);
    }
    // The share at the hesitation's middle.
    const double dwellMiddle = t0 + turnSeconds(leave + margin, out, kPanAcceleration) + away +
                               turnSeconds(leave + margin - partial, come, kPanAcceleration) + 0.5 * dwell;
    partial = angleForShareDeg(r, p, axis, dwellMiddle, share, leave);
  }
  const double outSeconds = turnSeconds(leave + margin, out, kPanAcceleration);
  const double comeSeconds = turnSeconds(leave + margin - partial, come, kPanAcceleration);
  const double t1 = t0 + outSeconds + away, t2 = t1 + comeSeconds + dwell;
  p.turns.push_back({axis, t0, outSeconds, radians(leave + margin)});
  p.turns.push_back({axis, t1, comeSeconds, -radians(leave + margin - partial)});
  p.turns.push_back({axis, t2, turnSeconds(partial - residual, finish, kPanAcceleration), -radians(partial - residual)});
}

// hands and photometric: small turns back and forth, 80 deg/s at most in all.
void planModerate(HandHeldPath& p, Random& rng, double seconds) {
  const double speed = std::max(20.0, turnSpeedBudget(p, seconds, kModerateSpeedDeg));
  glm::dvec3 turned(0.0);  // about where the turns have taken the camera (a rotation vector)
  double t = rng.uniform(0.1, 0.4);
  while (t < seconds - 0.2) {
    const int kind = rng.below(4);
    glm::dvec3 axis = axisOf(kind, rng);
    const double angle = kind == 2 ? rng.uniform(4, 20) : rng.uniform(3, 12);
    if (glm::dot(turned, axis) > 0) axis = -axis;  // back toward where it began
    turned += angle * axis;
    const double duration = turnSeconds(angle, rng.speed(15, speed), kModerateAcceleration);
    p.turns.push_back({axis, t, duration, radians(angle)});
    t += duration + rng.uniform(0.05, 0.4);
  }
}

}  // namespace marionette::ar::synthetic::handheld
