#include "tracking/stress_scenarios.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <glm/mat3x3.hpp>
#include <opencv2/calib3d.hpp>

#include "tracking/hand_held_path.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace marionette::ar::synthetic {

namespace {

// The camera's path and the random streams (hand_held_path.hpp).
using handheld::basePath;
using handheld::HandHeldPath;
using handheld::kPi;
using handheld::kSmootherPeakSlope;
using handheld::kTwoPi;
using handheld::planModerate;
using handheld::planPan;
using handheld::planReentry;
using handheld::radians;
using handheld::Random;
using handheld::smoother;
using handheld::Wave;

constexpr double kFps = 30;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A hand reaching in over the target (fingers first), lingering, and going on across or back;
// its forearm rises from the wrist toward where it came from, out of the picture.
struct HandMove {
  cv::Mat hand, forearm;  // premultiplied
  cv::Point2d palmTexel, wristTexel;
  double texel = 0.001;
  double tilt = 0, armRise = 0;        // radians: the fingers down a little, the forearm up
  glm::dvec3 linger{0.0}, drift{0.0};  // the palm's centre while it lingers, and its drift then
  glm::dvec3 forward{1, 0, 0}, across{0, 0, 1}, approach{1, 0, 0};  // horizontal units
  double reachIn = 0.4, reachOut = 0.4;
  bool goesOn = true;
  double start = 0, inSeconds = 0.5, lingerSeconds = 0.3, outSeconds = 0.5;

  [[nodiscard]] glm::dvec3 palmAt(double t) const {
    const double t1 = start + inSeconds, t2 = t1 + lingerSeconds;
    if (t < t1) return linger - approach * (reachIn * (1 - smoother((t - start) / inSeconds)));
    if (t < t2) return linger + drift * smoother((t - t1) / lingerSeconds);
    return linger + drift + (goesOn ? approach : -approach) * (reachOut * smoother((t - t2) / outSeconds));
  }
  // The hand, then the forearm (its first texel column at the wrist).
  void addAt(double t, std::vector<Occluder>& out) const {
    Occluder h;
    h.texture = hand;
    h.axisU = texel * (std::cos(tilt) * forward + glm::dvec3(0, -std::sin(tilt), 0));
    h.axisV = texel * across;
    const glm::dvec3 palm = palmAt(t);
    h.centre = palm + (0.5 * (hand.cols - 1) - palmTexel.x) * h.axisU + (0.5 * (hand.rows - 1) - palmTexel.y) * h.axisV;
    const glm::dvec3 wrist = palm + (wristTexel.x - palmTexel.x) * h.axisU + (wristTexel.y - palmTexel.y) * h.axisV;
    Occluder a;
    a.texture = forearm;
    a.axisU = texel * (-std::cos(armRise) * forward + glm::dvec3(0, std::sin(armRise), 0));
    a.axisV = texel * across;
    a.centre = wrist + 0.5 * (forearm.cols - 1) * a.axisU;
    out.push_back(h);
    out.push_back(a);
  }
};

std::vector<HandMove> planHands(const SequenceRenderer& r, const HandHeldPath& path, Random& rng, std::uint64_t seed) {
  std::vector<HandMove> hands(rng.chance(0.5) ? 2 : 1);
  double approachAngle = rng.uniform(0, kTwoPi);
  for (std::size_t i = 0; i < hands.size(); ++i) {
    HandMove& h = hands[i];
    const HandPicture picture = handPicture(seed * 2 + i);
    h.hand = premultipliedTexture(picture.hand);
    h.forearm = premultipliedTexture(picture.forearm);
    h.palmTexel = picture.palmTexel;
    h.wristTexel = picture.wristTexel;
    h.texel = picture.texel;
    if (i > 0) approachAngle += rng.uniform(radians(70), radians(180)) * rng.sign();
    h.approach = {std::cos(approachAngle), 0, std::sin(approachAngle)};
    const double yaw = approachAngle + radians(rng.uniform(-25, 25));
    h.forward = {std::cos(yaw), 0, std::sin(yaw)};
    h.across = rng.sign() * glm::dvec3(-std::sin(yaw), 0, std::cos(yaw));  // the sign: a left or a right hand
    h.tilt = radians(rng.uniform(4, 10));
    h.armRise = radians(rng.uniform(20, 40));
    h.start = i == 0 ? rng.uniform(0, 0.2) : hands[0].start + rng.uniform(0.25, 0.6);
    h.reachIn = rng.uniform(0.35, 0.5);
    h.reachOut = rng.uniform(0.35, 0.5);
    h.inSeconds = kSmootherPeakSlope * h.reachIn / rng.uniform(0.8, 1.6);  // peak 0.8..1.6 m/s
    h.lingerSeconds = rng.uniform(0.15, 0.5);
    h.outSeconds = kSmootherPeakSlope * h.reachOut / rng.uniform(0.8, 1.6);
    h.goesOn = rng.chance(0.5);
    h.drift = {rng.uniform(-0.04, 0.04), 0, rng.uniform(-0.04, 0.04)};
    // Over a point of the target as the camera sees it: on the line of sight to that point,
    // 5..25 cm above the floor, and at most 45 % of the camera's height.
    const glm::dvec3 eye(path.at(h.start + h.inSeconds)[3]);
    const double height = rng.uniform(0.05, std::clamp(0.45 * eye.y, 0.06, 0.25));
    const glm::dvec3 onTarget(rng.uniform(-0.3, 0.3) * r.targetWidth(), 0, rng.uniform(-0.3, 0.3) * r.targetDepth());
    h.linger = eye + (onTarget - eye) * ((eye.y - height) / eye.y);
  }
  return hands;
}

std::vector<Occluder> handsAt(const std::vector<HandMove>& hands, double t) {
  std::vector<Occluder> out;
  for (const HandMove& h : hands) h.addAt(t, out);
  return out;
}

// Per frame: gain steps as auto-exposure makes them, white-balance steps and defocus bumps.
struct Photometric {
  std::vector<double> gainEv, defocusPx;
  std::vector<cv::Vec3d> channelGain;
};

Photometric planPhotometric(Random& rng, int frames) {
  Photometric ph;
  const double seconds = frames / kFps;
  double gain = 0, nextGain = rng.uniform(0.15, 0.5);
  cv::Vec3d balance(1, 1, 1);
  double nextBalance = rng.uniform(0.2, 0.7);
  struct Bump {
    double centre, halfWidth, peak;
  };
  std::vector<Bump> bumps(1 + rng.below(2));
  for (Bump& b : bumps) b = {rng.uniform(0.15, 0.85) * seconds, rng.uniform(0.15, 0.4), rng.uniform(1.5, 4)};
  for (int i = 0; i < frames; ++i) {
    const double t = i / kFps;
    while (t >= nextGain) {
      double step = rng.uniform(0.5, 1.5) * rng.sign();
      if (std::abs(gain + step) > 2) step = -step;  // auto-exposure stays within +-2 EV
      gain += step;
      nextGain += rng.uniform(0.25, 0.7);
    }
    while (t >= nextBalance) {
      balance = {std::exp2(rng.uniform(-0.4, 0.4)), 1, std::exp2(rng.uniform(-0.4, 0.4))};
      nextBalance += rng.uniform(0.3, 0.9);
    }
    double radius = 0;
    for (const Bump& b : bumps)
      if (std::abs(t - b.centre) < b.halfWidth)
        radius = std::max(radius, b.peak * 0.5 * (1 + std::cos(kPi * (t - b.centre) / b.halfWidth)));
    ph.gainEv.push_back(gain);
    ph.channelGain.push_back(balance);
    ph.defocusPx.push_back(std::min(radius, 4.0));
  }
  return ph;
}

// World points through a camera: pixels, and whether each is in front.
void projectAll(const CameraModel& camera, const glm::dmat4& cameraToWorld, const std::vector<glm::dvec3>& points,
                std::vector<glm::dvec2>& pixels, std::vector<bool>& inFront) {
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(cameraToWorld, r, t);
  std::vector<cv::Point3d> world;
  inFront.clear();
  for (const glm::dvec3& p : points) {
    world.emplace_back(p.x, p.y, p.z);
    inFront.push_back((r * p + t).z > 1e-6);
  }
  const cv::Matx33d rcv(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  cv::Vec3d rvec;
  cv::Rodrigues(rcv, rvec);
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::projectPoints(world, rvec, cv::Vec3d(t.x, t.y, t.z), k,
                    std::vector<double>(camera.distortion.begin(), camera.distortion.end()), out);
  pixels.clear();
  for (const cv::Point2d& q : out) pixels.emplace_back(q.x, q.y);
}

// The fastest image motion over [t0, t1], pixels: a 5 x 5 grid of the image (the floor it sees
// at the middle, or points 10 m away where it sees the sky) and the hands' palms in view.
double imageMotionPx(const CameraModel& camera, const HandHeldPath& path, const std::vector<HandMove>& hands,
                     double t0, double t1) {
  constexpr int kSteps = 8;
  const glm::dmat4 middle = path.at(0.5 * (t0 + t1));
  std::vector<cv::Point2d> grid, rays;
  for (int gy = 0; gy < 5; ++gy)
    for (int gx = 0; gx < 5; ++gx) grid.emplace_back(gx / 4.0 * (camera.width - 1), gy / 4.0 * (camera.height - 1));
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::undistortPoints(grid, rays, k, std::vector<double>(camera.distortion.begin(), camera.distortion.end()));
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(middle, r, t);
  const glm::dvec3 eye(middle[3]);
  std::vector<glm::dvec3> points;
  for (const cv::Point2d& ray : rays) {
    const glm::dvec3 d = glm::transpose(r) * glm::dvec3(ray.x, ray.y, 1.0);
    const double s = d.y < 0 ? -eye.y / d.y : kNaN;
    points.push_back(s > 0 && s * glm::length(d) < 20 ? eye + s * d : eye + 10.0 * glm::normalize(d));
  }
  // The hands' palms that are in view (with a margin) at the middle.
  std::vector<const HandMove*> seen;
  if (!hands.empty()) {
    std::vector<glm::dvec2> px;
    std::vector<bool> front;
    std::vector<glm::dvec3> palms;
    for (const HandMove& h : hands) palms.push_back(h.palmAt(0.5 * (t0 + t1)));
    projectAll(camera, middle, palms, px, front);
    for (std::size_t i = 0; i < hands.size(); ++i)
      if (front[i] && px[i].x > -100 && px[i].y > -100 && px[i].x < camera.width + 100 && px[i].y < camera.height + 100)
        seen.push_back(&hands[i]);
  }
  const std::size_t fixed = points.size();
  std::vector<double> length(fixed + seen.size(), 0.0);
  std::vector<bool> valid(length.size(), true);
  std::vector<glm::dvec2> previous, pixels;
  std::vector<bool> front;
  for (int step = 0; step <= kSteps; ++step) {
    const double ts = t0 + (t1 - t0) * step / kSteps;
    points.resize(fixed);
    for (const HandMove* h : seen) points.push_back(h->palmAt(ts));
    projectAll(camera, path.at(ts), points, pixels, front);
    for (std::size_t i = 0; i < points.size(); ++i) {
      valid[i] = valid[i] && front[i];
      if (step > 0) length[i] += glm::length(pixels[i] - previous[i]);
    }
    previous = pixels;
  }
  double fastest = 0;
  for (std::size_t i = 0; i < length.size(); ++i)
    if (valid[i]) fastest = std::max(fastest, length[i]);
  return fastest;
}

// The target centre's image path over [t0, t1], pixels; NaN when it is behind the camera.
double centreBlurPx(const CameraModel& camera, const HandHeldPath& path, double t0, double t1) {
  constexpr int kSteps = 16;
  double length = 0;
  std::vector<glm::dvec2> pixels;
  std::vector<bool> front;
  glm::dvec2 previous(0.0);
  for (int step = 0; step <= kSteps; ++step) {
    projectAll(camera, path.at(t0 + (t1 - t0) * step / kSteps), {glm::dvec3(0.0)}, pixels, front);
    if (!front[0]) return kNaN;
    if (step > 0) length += glm::length(pixels[0] - previous);
    previous = pixels[0];
  }
  return length;
}

// Frames, sub-frames, effects and facts of a planned sequence.
StressSequence assemble(const SequenceRenderer& r, StressClass kind, std::uint64_t seed, int frames,
                        const HandHeldPath& path, double exposure, const std::vector<HandMove>& hands,
                        const Photometric* photometric, const StressOptions& options, const std::string& description) {
  StressSequence s;
  s.kind = kind;
  s.seed = seed;
  s.exposure = exposure;
  s.scenario.name = std::string(stressClassName(kind)) + "/" + std::to_string(seed);
  s.scenario.fps = kFps;
  auto shared = std::make_shared<const HandHeldPath>(path);
  s.cameraAt = [shared](double t) { return shared->at(t); };
  Random noise(seed, kind, Random::kNoise);
  const double sigma = noise.uniform(1, 3);
  double peak = 0;
  for (int i = 0; i < frames; ++i) {
    const double t = i / kFps, t0 = t - 0.5 * exposure, t1 = t + 0.5 * exposure;
    StressFrame f;
    f.time = t;
    f.exposure = exposure;
    f.imageMotionPx = imageMotionPx(r.camera(), path, hands, t0, t1);
    const int n = std::clamp(static_cast<int>(std::ceil(f.imageMotionPx / options.pxPerSubFrame)), options.minSubFrames,
                             std::max(options.minSubFrames, options.maxSubFrames));
    for (int k = 0; k < n; ++k) {
      const double ts = t0 + exposure * (k + 0.5) / n;
      f.subFrames.push_back({path.at(ts), handsAt(hands, ts)});
    }
    f.blurPx = centreBlurPx(r.camera(), path, t0, t1);
    constexpr double h = 5e-4;
    f.angularSpeedDeg = rotationErrorDeg(path.at(t - h), path.at(t + h)) / (2 * h);
    peak = std::max(peak, f.angularSpeedDeg);
    const glm::dmat4 pose = path.at(t);
    f.handsCover = hands.empty() ? 0.0 : r.occludedTargetFraction(pose, handsAt(hands, t));
    FrameEffects fx;
    fx.noiseSigma = sigma;
    fx.noiseSeed = noise.bits32();
    if (photometric) {
      fx.gainEv = photometric->gainEv[static_cast<std::size_t>(i)];
      fx.channelGain = photometric->channelGain[static_cast<std::size_t>(i)];
      fx.defocusPx = photometric->defocusPx[static_cast<std::size_t>(i)];
    }
    s.scenario.cameraToWorld.push_back(pose);
    s.scenario.effects.push_back(fx);
    s.scenario.visibleFraction.push_back(r.visibleTargetFraction(pose));
    s.scenario.smearPx.push_back(f.blurPx);
    s.scenario.hiddenFraction.push_back(f.handsCover);
    s.frames.push_back(std::move(f));
  }
  char line[160];
  std::snprintf(line, sizeof line, "%s; %zu turns, up to %.0f deg/s at the frames; exposure 1/%.0f s; noise sigma %.1f",
                description.c_str(), path.turns.size(), peak, 1 / exposure, sigma);
  s.scenario.description = line;
  return s;
}

void checkFrames(int frames) {
  if (frames < 30) throw std::invalid_argument("a stress sequence needs at least 30 frames");
}

}  // namespace

std::string_view stressClassName(StressClass kind) noexcept {
  switch (kind) {
    case StressClass::Pan: return "pan";
    case StressClass::Reentry: return "reentry";
    case StressClass::Hands: return "hands";
    case StressClass::Photometric: return "photometric";
  }
  return "?";
}

std::optional<StressClass> stressClassNamed(std::string_view name) noexcept {
  for (StressClass k : kStressClasses)
    if (stressClassName(k) == name) return k;
  return std::nullopt;
}

std::string_view imageEdgeName(ImageEdge edge) noexcept {
  switch (edge) {
    case ImageEdge::Left: return "left";
    case ImageEdge::Right: return "right";
    case ImageEdge::Top: return "top";
    case ImageEdge::Bottom: return "bottom";
  }
  return "?";
}

int defaultStressFrames(StressClass kind) noexcept {
  switch (kind) {
    case StressClass::Pan: return 50;
    case StressClass::Reentry: return 60;
    default: return 40;
  }
}

namespace {

// What every class starts with: the frame count checked, the hand-held base path and the
// exposure from the class's path stream, and the stream its moves are planned from.
struct Start {
  HandHeldPath path;
  double exposure = 0;
  Random moves;
};

Start start(const SequenceRenderer& renderer, std::uint64_t seed, StressClass kind, int frames) {
  checkFrames(frames);
  Random rng(seed, kind, Random::kPath);
  HandHeldPath path = basePath(rng, renderer.targetWidth());
  const double exposure = 1 / rng.uniform(30, 60);
  return {std::move(path), exposure, Random(seed, kind, Random::kMoves)};
}

}  // namespace

StressSequence panSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames, const StressOptions& options) {
  auto [path, exposure, moves] = start(renderer, seed, StressClass::Pan, frames);
  planPan(renderer, path, moves, frames / kFps);
  return assemble(renderer, StressClass::Pan, seed, frames, path, exposure, {}, nullptr, options,
                  "hand-held pans and turns, the target out of view and back");
}

StressSequence reentrySequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames, const StressOptions& options) {
  constexpr ImageEdge kEdges[4] = {ImageEdge::Left, ImageEdge::Right, ImageEdge::Top, ImageEdge::Bottom};
  return reentrySequence(renderer, seed, frames, kEdges[seed == 0 ? 0 : (seed - 1) / 4 % 4], options);
}

StressSequence reentrySequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames, ImageEdge edge,
                               const StressOptions& options) {
  auto [path, exposure, moves] = start(renderer, seed, StressClass::Reentry, frames);
  planReentry(renderer, path, moves, frames / kFps, edge);
  StressSequence s = assemble(renderer, StressClass::Reentry, seed, frames, path, exposure, {}, nullptr, options,
                              "away and back, the target re-entering partly by the " + std::string(imageEdgeName(edge)) +
                                  " edge");
  s.edge = edge;
  return s;
}

StressSequence handsSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames, const StressOptions& options) {
  auto [path, exposure, moves] = start(renderer, seed, StressClass::Hands, frames);
  planModerate(path, moves, frames / kFps);
  Random handRng(seed, StressClass::Hands, Random::kHands);
  const std::vector<HandMove> hands = planHands(renderer, path, handRng, seed);
  return assemble(renderer, StressClass::Hands, seed, frames, path, exposure, hands, nullptr, options,
                  std::to_string(hands.size()) + " hand(s) reaching over the target, moderate motion");
}

StressSequence photometricSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                   const StressOptions& options) {
  auto [path, exposure, moves] = start(renderer, seed, StressClass::Photometric, frames);
  planModerate(path, moves, frames / kFps);
  Random photo(seed, StressClass::Photometric, Random::kPhotometric);
  const Photometric ph = planPhotometric(photo, frames);
  return assemble(renderer, StressClass::Photometric, seed, frames, path, exposure, {}, &ph, options,
                  "gain and white-balance steps, defocus coming and going, moderate motion");
}

StressSequence stressSequence(const SequenceRenderer& renderer, StressClass kind, std::uint64_t seed, int frames,
                              const StressOptions& options) {
  switch (kind) {
    case StressClass::Pan: return panSequence(renderer, seed, frames, options);
    case StressClass::Reentry: return reentrySequence(renderer, seed, frames, options);
    case StressClass::Hands: return handsSequence(renderer, seed, frames, options);
    case StressClass::Photometric: return photometricSequence(renderer, seed, frames, options);
  }
  throw std::invalid_argument("unknown stress class");
}

void renderStressFrame(const SequenceRenderer& renderer, const StressSequence& sequence, int frame, cv::Mat& outRgb) {
  const auto i = static_cast<std::size_t>(frame);
  renderer.renderExposure(sequence.frames.at(i).subFrames, sequence.scenario.effects.at(i), outRgb);
}

RenderedScenario renderStress(const SequenceRenderer& renderer, const StressSequence& sequence, int threads,
                              std::vector<double>* msPerFrame) {
  const int n = static_cast<int>(sequence.frames.size());
  RenderedScenario out;
  out.scenario = sequence.scenario;
  out.frames.resize(sequence.frames.size());
  std::vector<double> ms(sequence.frames.size());
  std::atomic<int> next{0};
  std::mutex failed;
  std::exception_ptr error;
  auto work = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        const auto start = std::chrono::steady_clock::now();
        renderStressFrame(renderer, sequence, i, out.frames[static_cast<std::size_t>(i)]);
        ms[static_cast<std::size_t>(i)] =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failed);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < std::max(1, threads); ++k) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (msPerFrame) *msPerFrame = std::move(ms);
  return out;
}

HandPicture handPicture(std::uint64_t seed) {
  Random rng(seed, StressClass::Hands, Random::kPicture);
  constexpr double kTexel = 0.001;
  const double s = rng.uniform(0.9, 1.1);  // the hand's size
  // Shapes in metres: the palm's centre at the origin, the fingers along +u, the thumb on +v.
  struct Capsule {
    glm::dvec2 a, b;
    double ra, rb;
  };
  auto capsule = [](const Capsule& c, glm::dvec2 p, double& along) {
    const glm::dvec2 ab = c.b - c.a;
    along = std::clamp(glm::dot(p - c.a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - c.a - along * ab) - (c.ra + (c.rb - c.ra) * along);
  };
  auto smoothMin = [](double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k / 4;
  };
  std::vector<Capsule> fingers;
  const double spread = rng.uniform(0, 8);
  const double lengths[4] = {0.062, 0.077, 0.082, 0.075}, radii[4] = {0.0075, 0.0085, 0.0088, 0.0085};
  for (int i = 0; i < 4; ++i) {
    const double angle = radians(spread * (i - 1.5) + rng.uniform(-3, 3));
    const glm::dvec2 base(0.036 * s, (-0.03 + 0.02 * i) * s);
    const double length = lengths[i] * s * rng.uniform(0.95, 1.05);
    fingers.push_back({base, base + length * glm::dvec2(std::cos(angle), std::sin(angle)), radii[i] * s, 0.9 * radii[i] * s});
  }
  const double thumbAngle = radians(rng.uniform(35, 60));
  const glm::dvec2 thumbBase(-0.01 * s, 0.035 * s);
  const Capsule thumb{thumbBase, thumbBase + 0.06 * s * glm::dvec2(std::cos(thumbAngle), std::sin(thumbAngle)),
                      0.0115 * s, 0.0095 * s};
  const double wristU = -0.07 * s;
  const Capsule wrist{{-0.035 * s, 0}, {wristU, 0}, 0.03 * s, 0.027 * s};
  auto palm = [s](glm::dvec2 p) {  // a rounded box
    const glm::dvec2 q = glm::abs(p) - glm::dvec2(0.045 * s - 0.02 * s, 0.041 * s - 0.02 * s);
    return glm::length(glm::max(q, glm::dvec2(0.0))) + std::min(std::max(q.x, q.y), 0.0) - 0.02 * s;
  };

  // One skin for both pictures: a tone between two neighbours of a light-to-dark palette, one
  // side lit more than the other, mottled by plane waves 1.5..4 cm long in three directions.
  const cv::Vec3d palette[6] = {{241, 204, 177}, {226, 180, 148}, {205, 152, 115}, {176, 122, 86}, {134, 88, 60}, {96, 62, 44}};
  const int tone = rng.below(5);
  const double mix = rng.uniform(0, 1);
  const cv::Vec3d skin = palette[tone] * (1 - mix) + palette[tone + 1] * mix;
  const double light = rng.uniform(-0.12, 0.12);
  Wave mottle[3];
  glm::dvec2 mottleDirection[3];
  for (int k = 0; k < 3; ++k) {
    mottle[k] = {rng.uniform(0.01, 0.025), 1 / rng.uniform(0.015, 0.04), rng.uniform(0, kTwoPi)};
    const double a = rng.uniform(0, kPi);
    mottleDirection[k] = {std::cos(a), std::sin(a)};
  }
  // Paints texels (u, v) = (uMin + (x + 0.5) texel, vMin + (y + 0.5) texel) from a signed
  // distance (< 0 inside, metres) with creases (a factor) and nails (a share of nail colour).
  struct Look {
    double distance, crease = 1, nail = 0;
  };
  auto paint = [&](int cols, int rows, double uMin, double vMin, const auto& lookAt) {
    cv::Mat rgba(rows, cols, CV_8UC4);
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < cols; ++x) {
        const glm::dvec2 p(uMin + (x + 0.5) * kTexel, vMin + (y + 0.5) * kTexel);
        const Look look = lookAt(p);
        const double alpha = std::clamp(0.5 - look.distance / kTexel, 0.0, 1.0);
        // Darker toward the rim of a rounded section.
        const double in = std::clamp(-look.distance / 0.01, 0.0, 1.0);
        double shade = (0.62 + 0.38 * std::sqrt(in * (2 - in))) * (1 + light * p.y / 0.06) * look.crease;
        for (int k = 0; k < 3; ++k) shade *= 1 + mottle[k].at(glm::dot(p, mottleDirection[k]));
        cv::Vec3d c = skin * shade * (1 + 0.04 * (rng.uniform() - 0.5));
        c = c * (1 - look.nail) + cv::Vec3d(236, 206, 200) * look.nail * shade;
        auto level = [](double v) { return static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 255.0))); };
        rgba.at<cv::Vec4b>(y, x) = {level(c[0]), level(c[1]), level(c[2]), level(255 * alpha)};
      }
    return rgba;
  };

  HandPicture out;
  out.texel = kTexel;
  const double uMin = -0.1, uMax = 0.14, vMin = -0.065, vMax = 0.11;
  out.hand = paint(static_cast<int>(std::lround((uMax - uMin) / kTexel)), static_cast<int>(std::lround((vMax - vMin) / kTexel)),
                   uMin, vMin, [&](glm::dvec2 p) {
                     double along = 0;
                     Look look{smoothMin(palm(p), capsule(wrist, p, along), 0.015)};
                     for (const Capsule& f : fingers) {
                       const double df = capsule(f, p, along);
                       look.distance = smoothMin(look.distance, df, 0.006);
                       if (df < 0) {
                         const double length = glm::length(f.b - f.a);
                         // Knuckle creases across the finger, and the nail over its last 11 mm.
                         for (double at : {0.36, 0.68})
                           if (std::abs(along - at) * length < 0.0007) look.crease = 0.82;
                         if ((1 - along) * length < 0.011 && df < -0.35 * f.ra) look.nail = 0.35;
                       }
                     }
                     look.distance = smoothMin(look.distance, capsule(thumb, p, along), 0.008);
                     return look;
                   });
  out.palmTexel = {-uMin / kTexel - 0.5, -vMin / kTexel - 0.5};
  out.wristTexel = {(wristU - uMin) / kTexel - 0.5, out.palmTexel.y};
  // The forearm from the wrist (u = 0) to past the elbow, widening; cut square at its far end,
  // which is out of the picture.
  const Capsule arm{{0.01, 0}, {0.75, 0}, 0.027 * s, 0.037 * s};
  out.forearm = paint(700, 84, 0.0, -0.042, [&](glm::dvec2 p) {
    double along = 0;
    return Look{capsule(arm, p, along)};
  });
  return out;
}

}  // namespace marionette::ar::synthetic
