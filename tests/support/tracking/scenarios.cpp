#include "tracking/scenarios.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette/core/split_mix.hpp"

namespace marionette::ar::synthetic {

namespace {

constexpr double kFps = 30;
constexpr double kTwoPi = 6.283185307179586;

double radians(double deg) { return deg * 3.14159265358979323846 / 180.0; }

double smoothstep(double a, double b, double x) {
  const double s = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return s * s * (3 - 2 * s);
}

glm::dvec3 orbitEye(double azimuthDeg, double elevationDeg, double distance, glm::dvec3 lookAt) {
  const double az = radians(azimuthDeg), el = radians(elevationDeg);
  return lookAt + distance * glm::dvec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
}

glm::dmat4 withRoll(const glm::dmat4& m, double rollDeg) {
  return rollDeg == 0 ? m : m * glm::rotate(glm::dmat4(1.0), radians(rollDeg), glm::dvec3(0, 0, 1));
}

// The slow hand-held orbit `orbit`, `noise_jpeg`, `gain` and `occluder` share.
glm::dmat4 handHeldOrbit(double w, double t) {
  const double az = 20 * t;
  const double el = 47.5 + 11.5 * std::sin(kTwoPi * t / 7);
  const double distance = w * (2.5 + 0.5 * std::sin(kTwoPi * t / 5 + 0.7));
  const glm::dvec3 bob(0, 0.03 * w * std::sin(kTwoPi * 0.9 * t), 0);
  const glm::dvec3 eye = orbitEye(az, el, distance, glm::dvec3(0)) + bob;
  return withRoll(lookAtCameraToWorld(eye, glm::dvec3(0), glm::dvec3(0, 1, 0)), 3 * std::sin(kTwoPi * t / 6));
}

// Camera-own-axis turn for fast_turn: 90 deg out in 0.4 s (smoothstep: 225 deg/s mean,
// 337 deg/s peak), 0.3 s held, 0.4 s back, 0.5 s still; alternating left and right.
double turnDeg(double t, double start) {
  if (t < start) return 0;
  constexpr double period = 1.6;
  const double k = std::floor((t - start) / period), tau = t - start - k * period;
  const double sign = static_cast<long long>(k) % 2 == 0 ? 1.0 : -1.0;
  return sign * 90 * (smoothstep(0.0, 0.4, tau) - smoothstep(0.7, 1.1, tau));
}

std::uint32_t seedOf(int scenario, int frame) {
  return static_cast<std::uint32_t>(7919 * (scenario + 1) + frame + 1);
}

}  // namespace

glm::dmat4 orbitPose(double azimuthDeg, double elevationDeg, double distance, double rollDeg, glm::dvec3 lookAt) {
  return withRoll(lookAtCameraToWorld(orbitEye(azimuthDeg, elevationDeg, distance, lookAt), lookAt, glm::dvec3(0, 1, 0)),
                  rollDeg);
}

std::vector<std::string> standardScenarioNames() {
  return {"orbit", "static", "fast_turn", "blur", "noise_jpeg", "gain", "occluder", "partial", "grazing", "lost_regained"};
}

std::vector<Scenario> standardScenarios(const SequenceRenderer& renderer, int framesPerScenario) {
  if (framesPerScenario < 2) throw std::invalid_argument("standardScenarios: at least 2 frames per scenario");
  const int n = framesPerScenario;
  const double w = renderer.targetWidth();
  const double duration = n / kFps;
  const CameraModel& camera = renderer.camera();

  std::vector<Scenario> out;
  auto add = [&](std::string name, std::string description,
                 const std::function<void(int i, double t, double s, glm::dmat4& pose, FrameEffects& fx)>& frame) {
    Scenario sc;
    sc.name = std::move(name);
    sc.description = std::move(description);
    sc.fps = kFps;
    const int index = static_cast<int>(out.size());
    for (int i = 0; i < n; ++i) {
      glm::dmat4 pose(1.0);
      FrameEffects fx;
      fx.noiseSeed = seedOf(index, i);
      frame(i, i / kFps, static_cast<double>(i) / (n - 1), pose, fx);
      sc.cameraToWorld.push_back(pose);
      sc.effects.push_back(fx);
      sc.visibleFraction.push_back(renderer.visibleTargetFraction(pose));
    }
    out.push_back(std::move(sc));
  };

  add("orbit", "slow hand-held orbit, 2x..3x the target width away, elevation 35..60 deg",
      [&](int, double t, double, glm::dmat4& pose, FrameEffects&) { pose = handHeldOrbit(w, t); });

  const glm::dmat4 still = orbitPose(30, 50, 2.5 * w);
  add("static", "one pose for every frame, noise sigma 2",
      [&](int, double, double, glm::dmat4& pose, FrameEffects& fx) {
        pose = still;
        fx.noiseSigma = 2;
      });

  const double turnStart = std::min(1.0, 0.2 * duration);
  add("fast_turn", "fast orbit (90 deg/s) with 90 deg turns about the camera's own vertical at >= 180 deg/s",
      [&](int, double t, double, glm::dmat4& pose, FrameEffects&) {
        const glm::dmat4 base = orbitPose(90 * t, 45, 2.5 * w);
        pose = base * glm::rotate(glm::dmat4(1.0), radians(turnDeg(t, turnStart)), glm::dvec3(0, 1, 0));
      });

  auto blurPose = [&](double t) { return orbitPose(45 * t, 45 + 10 * std::sin(kTwoPi * t / 6), 2.5 * w); };
  // Sharp for the first 10 % (a tracker starts on a still camera), then blurred 9..25 px.
  add("blur", "orbit at 45 deg/s, sharp for the first 10 %, then motion blur 9..25 px along the image motion",
      [&](int i, double t, double s, glm::dmat4& pose, FrameEffects& fx) {
        pose = blurPose(t);
        fx.motionBlurPx = s < 0.1 ? 0.0 : 17 + 8 * std::sin(kTwoPi * t / 3);
        // Along the image motion of the target's centre, from the frame before to the next.
        const double t0 = std::max(0, i - 1) / kFps, t1 = std::min(n - 1, i + 1) / kFps;
        const glm::dvec2 d = projectWorldPoint(camera, blurPose(t1), glm::dvec3(0)) -
                             projectWorldPoint(camera, blurPose(t0), glm::dvec3(0));
        fx.motionBlurAngleDeg = glm::length(d) > 1e-9 ? std::atan2(d.y, d.x) * 180.0 / 3.14159265358979323846 : 0.0;
      });

  add("noise_jpeg", "slow orbit with noise sigma 6 and JPEG quality 30",
      [&](int, double t, double, glm::dmat4& pose, FrameEffects& fx) {
        pose = handHeldOrbit(w, t);
        fx.noiseSigma = 6;
        fx.jpegQuality = 30;
      });

  add("gain", "slow orbit with the gain swinging smoothly between -1 and +1 EV",
      [&](int, double t, double, glm::dmat4& pose, FrameEffects& fx) {
        pose = handHeldOrbit(w, t);
        fx.gainEv = std::sin(kTwoPi * t / 4);
      });

  add("occluder", "slow orbit with an occluder covering 20..60 % of the target sweeping across it",
      [&](int, double t, double, glm::dmat4& pose, FrameEffects& fx) {
        pose = handHeldOrbit(w, t);
        fx.occluderFraction = 0.4 + 0.2 * std::sin(kTwoPi * t / 3.3);
        const double p = t / 3 - std::floor(t / 3);
        fx.occluderPhase = p < 0.5 ? 2 * p : 2 - 2 * p;
      });

  // Starts with the whole target in view (the tracker must keep it as it slides out, not find
  // a sliver of it cold), slides to 20..50 % in view, and back for the last 15 %.
  add("partial", "the camera slides sideways until only 20..50 % of the target is in view, and back",
      [&](int, double t, double s, glm::dmat4& pose, FrameEffects&) {
        const glm::dmat4 base = orbitPose(10 * t, 55, 2.5 * w);
        const glm::dvec3 right(base[0]);
        const double band = 0.35 + 0.15 * std::sin(kTwoPi * t / 4);
        auto ramp = [](double x) { return x <= 0 ? 0.0 : x >= 1 ? 1.0 : x * x * (3 - 2 * x); };
        const double in = ramp((s - 0.1) / 0.15), back = ramp((s - 0.85) / 0.15);
        const double wanted = 1.0 + (band - 1.0) * in * (1 - back);
        if (wanted >= 0.999) {
          pose = base;
          return;
        }
        auto moved = [&](double offset) {
          glm::dmat4 m = base;
          m[3] += glm::dvec4(offset * right, 0);
          return m;
        };
        // The visible share falls as the camera moves right: bisect for the wanted share.
        double lo = 0, hi = 4 * w;
        for (int it = 0; it < 40; ++it) {
          const double mid = 0.5 * (lo + hi);
          (renderer.visibleTargetFraction(moved(mid)) > wanted ? lo : hi) = mid;
        }
        pose = moved(0.5 * (lo + hi));
      });

  add("grazing", "elevation from 50 deg down to 20 deg above the plane (70 deg from its normal) and back",
      [&](int, double t, double s, glm::dmat4& pose, FrameEffects&) {
        pose = orbitPose(15 * t, 35 + 15 * std::cos(kTwoPi * s), 2.5 * w);
      });

  add("lost_regained", "the camera pans 160 deg away (target out of view for about the middle third) and back",
      [&](int, double t, double s, glm::dmat4& pose, FrameEffects&) {
        const glm::dmat4 base = orbitPose(15 * t, 50, 2.5 * w);
        const double pan = 160 * (smoothstep(0.30, 0.38, s) - smoothstep(0.62, 0.70, s));
        // About the world's vertical through the camera: the view stays on the floor.
        const glm::dmat3 r = glm::dmat3(glm::rotate(glm::dmat4(1.0), radians(pan), glm::dvec3(0, 1, 0))) *
                             glm::dmat3(base);
        pose = glm::dmat4(r);
        pose[3] = base[3];
      });

  return out;
}

Scenario authoringSweep(const SequenceRenderer& renderer, int frames) {
  if (frames < 2) throw std::invalid_argument("authoringSweep: at least 2 frames");
  const glm::dvec3 look(0.15, 0.5, -0.4);
  Scenario sc;
  sc.name = "authoring_sweep";
  sc.description = "a user 3 m from a 2 m floor target and the open floor behind it, sweeping -15..15 deg around it";
  sc.fps = kFps;
  for (int i = 0; i < frames; ++i) {
    const double t = i / kFps, s = static_cast<double>(i) / (frames - 1);
    const double az = radians(-15 + 30 * s);
    const glm::dvec3 bob(0.01 * std::sin(kTwoPi * 0.8 * t), 0.012 * std::sin(kTwoPi * 1.1 * t + 0.5), 0);
    const glm::dvec3 eye = glm::dvec3(look.x + 3.4 * std::sin(az), 1.7, look.z + 3.4 * std::cos(az)) + bob;
    const glm::dmat4 pose = withRoll(lookAtCameraToWorld(eye, look, glm::dvec3(0, 1, 0)), 1.5 * std::sin(kTwoPi * t / 4));
    FrameEffects fx;
    fx.noiseSeed = seedOf(100, i);
    sc.cameraToWorld.push_back(pose);
    sc.effects.push_back(fx);
    sc.visibleFraction.push_back(renderer.visibleTargetFraction(pose));
  }
  return sc;
}

std::vector<RelaunchPose> relaunchPoses(const SequenceRenderer& renderer, const glm::dmat4& authored, int count) {
  const glm::dvec3 eye(authored[3]), forward = -glm::dvec3(authored[2]);
  std::vector<RelaunchPose> out;
  SplitMix64 random{0x5eed2026};
  auto uniform = [&random](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(random.next() >> 11) / 9007199254740992.0;
  };
  for (int tries = 0; static_cast<int>(out.size()) < count && tries < 100000; ++tries) {
    // Out to 1.2 m across the floor and up to 0.3 m up or down, then a point near the target to look at.
    const double heading = uniform(0, kTwoPi), reach = uniform(0.4, 1.2);
    const glm::dvec3 moved = eye + glm::dvec3(reach * std::sin(heading), uniform(-0.3, 0.3), reach * std::cos(heading));
    const glm::dvec3 look(uniform(-0.5, 0.5), uniform(0, 0.8), uniform(-0.8, 0.4));
    RelaunchPose p;
    p.cameraToWorld = withRoll(lookAtCameraToWorld(moved, look, glm::dvec3(0, 1, 0)), uniform(-5, 5));
    p.moved = glm::length(moved - eye);
    p.turnedDeg = glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(look - moved), forward), -1.0, 1.0)));
    // Within the ranges, spread over them (a turn from 0..10, 10..20, 20..30 deg in turn), and the
    // target at least half in view: a relaunch is pointed at the scene.
    const double band = 10.0 * static_cast<double>(out.size() % 3);
    if (p.moved < 0.4 || p.moved > 1.2 || p.turnedDeg < band || p.turnedDeg > band + 10.0) continue;
    if (renderer.visibleTargetFraction(p.cameraToWorld) < 0.5) continue;
    out.push_back(p);
  }
  return out;
}

}  // namespace marionette::ar::synthetic
