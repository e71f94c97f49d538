// marionette_bench: camera tracking per frame (examples/ar/tracking), one thread
// (cv::setNumThreads(1), as marionette-ar runs it). Time is milliseconds per update().
//   Tracking/MarkerlessFrame       the markerless tracker's per-frame update() over the
//                                  standard `orbit` sequence (60 frames, 640x480 RGB, rendered
//                                  once), the frames played forwards then backwards so the
//                                  motion has no jump, after one warm-up pass (the first frame
//                                  relocalizes). Counters: inliers (mean), relocalized and lost
//                                  (shares of the timed frames: 0 when tracking holds),
//                                  keyframes (the map's size at the end).
//   Tracking/MarkerlessRelocalizeNoTarget/tiltedViewFeatures:N  a frame without the target: every
//                                  keyframe and tilted view matched in vain (N 0: no tilted views)
//   Tracking/MarkerlessRelocalize  reset() before every update() on the same frames: each
//                                  frame relocalizes from scratch (ORB + matching + RANSAC,
//                                  then the tracking check), the LOST path's cost. Counter
//                                  tracking = share of frames found TRACKING from nothing.
//   Tracking/AprilTagFrame         AprilTagTracker::update on ViSP's tag36_11_640x480.png
//                                  (fx = fy = 700, tag 0.2 m, decimate 2). Counters: tags, inliers.
//   Tracking/HammingMatch          relocalization's matcher (src/hamming_matcher): 600 random ORB
//                                  descriptors against 1200, the nearest two of each.
//   Tracking/Memcpy640x480         a memcpy of one 640x480 RGB frame: the floor for a ratio.
//   Tracking/TargetOcclusion[Smeared]  the occlusion mask over the target (1/4 resolution) at the
//                                  orbit's exact poses, sharp or every frame smeared 24 px along x;
//                                  Close / Near: 12 views from 0.32 / 0.55 m turned 45 deg (the
//                                  target's box larger than its area): it fills most of the frame
//                                  (worked at scale 8) / 25 % of it, just under maxTargetPixels (scale 4);
//                                  NearSmeared: those smeared 24 px along x.
//   Tracking/{Warp,Klt,Ransac,Pose}{Own,OpenCv}
//                                  the markerless tracker's per-frame primitives (src/
//                                  perspective_warp, lucas_kanade, homography_ransac,
//                                  planar_pose) against the OpenCV calls they replace, on the
//                                  same data in the same run: graf1 (level 1 of the reference)
//                                  warped into orbit frame 10 from frame 9's exact pose (the
//                                  target's box grown by 120 px); KLT of 200 of its corners from
//                                  that template into frame 10, window 15, 3 levels (Own builds
//                                  both pyramids in full, KltOwnRegion the template's over the
//                                  warped region only); RANSAC (2 px) on 200 pairs with 30 %
//                                  outliers and 0.5 px noise; the pose from 140 inliers
//                                  (IPPE + LM + projectPoints against ours). Time per call.
//   Tracking/MotionBlur{Apply,Search}  the template's motion blur (src/motion_blur): that template
//                                  blurred over the warped region by a pan's smear (18 px at
//                                  20 deg); the blur found from the sharp template and that
//                                  blurred frame at the 200 corners (estimateMotionBlur, then
//                                  refineMotionBlur from its estimate). Time per call.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <opencv2/calib3d.hpp>
#include <opencv2/video/tracking.hpp>

#include "dense_alignment.hpp"
#include "hamming_matcher.hpp"
#include "homography_ransac.hpp"
#include "image_shift.hpp"
#include "lucas_kanade.hpp"
#include "motion_blur.hpp"
#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "perspective_warp.hpp"
#include "planar_pose.hpp"
#include "tracking/scenario_run.hpp"
#include "tracking/visp_benchmark.hpp"

using namespace marionette;
using namespace marionette::ar;
using namespace marionette::ar::synthetic;

namespace {

constexpr int kOrbitFrames = 60;

ImageView view(const cv::Mat& m) { return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)}; }

struct Orbit {
  CameraModel camera;
  std::vector<cv::Mat> frames;  // RGB8
  std::vector<glm::dmat4> cameraToWorld;  // the truth
  double fps = 30;
  std::string error;
};

// Rendered on first use only (a few seconds): other benchmarks' runs do not pay for it.
const Orbit& orbit() {
  static const Orbit o = [] {
    Orbit r;
    try {
      const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
      r.camera = renderer.camera();
      auto rendered = synthetic::renderScenarios(renderer, kOrbitFrames, {"orbit"});
      if (rendered.size() != 1) throw std::runtime_error("no 'orbit' scenario");
      r.fps = rendered[0].scenario.fps;
      r.frames = std::move(rendered[0].frames);
      r.cameraToWorld = rendered[0].scenario.cameraToWorld;
    } catch (const std::exception& e) {
      r.error = e.what();
    }
    return r;
  }();
  return o;
}

std::unique_ptr<MarkerlessTracker> markerless(const Orbit& o, std::string& error,
                                              const MarkerlessSettings& settings = {}) {
  Diagnostics d;
  auto t = MarkerlessTracker::fromTarget(o.camera, synthetic::standardTargetImage(), synthetic::kStandardTargetWidth,
                                         settings, d);
  if (!t) error = d.format();
  return t;
}

// Frames 0, 1, .., 59, 58, .., 1, 0, 1, ..: a continuous path (the constant-velocity
// prediction sees one reversal per end), at monotonically increasing times.
struct PingPong {
  int count, step = 0;
  double fps, seconds = 0;
  int next() {
    const int period = 2 * (count - 1);
    const int s = step++ % period;
    seconds += 1.0 / fps;
    return s < count ? s : period - s;
  }
};

// A tracker for the orbit frames, or nullptr with the benchmark skipped with the reason.
std::unique_ptr<MarkerlessTracker> orbitTracker(benchmark::State& state, const Orbit& o) {
  cv::setNumThreads(1);
  std::string error = o.error;
  auto tracker = error.empty() ? markerless(o, error) : nullptr;
  if (!tracker) state.SkipWithError(error.c_str());
  return tracker;
}

void markerlessFrame(benchmark::State& state) {
  const Orbit& o = orbit();
  auto tracker = orbitTracker(state, o);
  if (!tracker) return;
  PingPong frames{kOrbitFrames, 0, o.fps};
  TrackedPose last;
  for (int i = 0; i < 2 * (kOrbitFrames - 1); ++i)  // warm-up: one pass there and back
    last = tracker->update(view(o.frames[static_cast<std::size_t>(frames.next())]), frames.seconds);
  if (last.state != TrackingState::Tracking) {  // the figure would be the LOST path's, not tracking's
    state.SkipWithError("the markerless tracker does not hold the orbit sequence (not TRACKING after warm-up)");
    return;
  }
  long inliers = 0, relocalized = 0, lost = 0;
  for (auto _ : state) {
    const int f = frames.next();
    const TrackedPose p = tracker->update(view(o.frames[static_cast<std::size_t>(f)]), frames.seconds);
    benchmark::DoNotOptimize(p);
    inliers += p.inliers;
    relocalized += tracker->lastFrame().relocalized;
    lost += p.state == TrackingState::Lost;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["inliers"] = static_cast<double>(inliers) / n;
  state.counters["relocalized"] = static_cast<double>(relocalized) / n;
  state.counters["lost"] = static_cast<double>(lost) / n;
  state.counters["keyframes"] = static_cast<double>(tracker->map().keyframes.size());
}

void markerlessRelocalize(benchmark::State& state) {
  const Orbit& o = orbit();
  auto tracker = orbitTracker(state, o);
  if (!tracker) return;
  PingPong frames{kOrbitFrames, 0, o.fps};
  for (int i = 0; i < kOrbitFrames; ++i) {  // warm-up: OpenCV's first calls, the map's keyframes if any
    tracker->reset();
    benchmark::DoNotOptimize(tracker->update(view(o.frames[static_cast<std::size_t>(frames.next())]), frames.seconds));
  }
  long inliers = 0, tracking = 0, relocalized = 0;
  for (auto _ : state) {
    const int f = frames.next();
    tracker->reset();
    const TrackedPose p = tracker->update(view(o.frames[static_cast<std::size_t>(f)]), frames.seconds);
    benchmark::DoNotOptimize(p);
    inliers += p.inliers;
    tracking += p.state == TrackingState::Tracking;
    relocalized += tracker->lastFrame().relocalized;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["inliers"] = static_cast<double>(inliers) / n;
  state.counters["tracking"] = static_cast<double>(tracking) / n;
  state.counters["relocalized"] = static_cast<double>(relocalized) / n;  // 1: every frame took the LOST path
}

// The LOST path's worst case: a frame without the target (blurred noise), so that the keyframes
// and then the five tilted views are all matched and fail. range(0): the tilted views' features
// (0: none), so that their cost is read as a ratio in one run.
void markerlessRelocalizeNoTarget(benchmark::State& state) {
  const Orbit& o = orbit();
  cv::setNumThreads(1);
  MarkerlessSettings settings;
  settings.tiltedViewFeatures = static_cast<int>(state.range(0));
  std::string error = o.error;
  auto tracker = error.empty() ? markerless(o, error, settings) : nullptr;
  if (!tracker) {
    state.SkipWithError(error.c_str());
    return;
  }
  cv::Mat noise(o.camera.height, o.camera.width, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  const ImageView frame{noise.data, noise.cols, noise.rows, 3, static_cast<std::ptrdiff_t>(noise.step)};
  double seconds = 0;
  for (int i = 0; i < 3; ++i) benchmark::DoNotOptimize(tracker->update(frame, seconds += 1.0 / 30));
  long posed = 0;
  for (auto _ : state) {
    const TrackedPose p = tracker->update(frame, seconds += 1.0 / 30);
    benchmark::DoNotOptimize(p);
    posed += p.state != TrackingState::Lost;
  }
  state.counters["posed"] = static_cast<double>(posed) / static_cast<double>(state.iterations());  // 0: no false pose
}

void aprilTagFrame(benchmark::State& state) {
  cv::setNumThreads(1);
  const std::string file =
      ::marionette::test::vispImagesDir() + "/AprilTag/benchmark/640x480/tag36_11_640x480.png";
  cv::Mat bgr = cv::imread(file, cv::IMREAD_COLOR), rgb;
  if (bgr.empty()) {
    state.SkipWithError((file + ": missing (Debian visp-images-data)").c_str());
    return;
  }
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  Diagnostics d;
  auto tracker = AprilTagTracker::create(vispBenchmarkCamera(), vispBenchmarkTagSettings(), d);
  if (!tracker) {
    state.SkipWithError(d.format().c_str());
    return;
  }
  const ImageView frame = view(rgb);
  double seconds = 0;
  for (int i = 0; i < 5; ++i) benchmark::DoNotOptimize(tracker->update(frame, seconds += 1.0 / 30));
  long inliers = 0, tags = 0, lost = 0;
  for (auto _ : state) {
    const TrackedPose p = tracker->update(frame, seconds += 1.0 / 30);
    benchmark::DoNotOptimize(p);
    inliers += p.inliers;
    tags += static_cast<long>(tracker->detections().size());
    lost += p.state == TrackingState::Lost;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["tags"] = static_cast<double>(tags) / n;
  state.counters["inliers"] = static_cast<double>(inliers) / n;
  state.counters["lost"] = static_cast<double>(lost) / n;
}

void memcpy640x480(benchmark::State& state) {
  constexpr std::size_t kBytes = 640u * 480u * 3u;
  std::vector<unsigned char> src(kBytes), dst(kBytes);
  for (std::size_t i = 0; i < kBytes; ++i) src[i] = static_cast<unsigned char>(i * 31u);
  for (auto _ : state) {
    std::memcpy(dst.data(), src.data(), kBytes);
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(kBytes));
}

// The primitives' data (see the header comment), made once.
struct PrimitivesData {
  cv::Mat source, frame, templ;  // reference level 1, frame 10 (grey), the template
  cv::Matx33d warp;               // source pixel -> frame pixel
  cv::Rect region;
  std::uint8_t background = 128;
  std::vector<cv::Point2f> from;  // 200 template points (the guesses too)
  std::vector<cv::Point2f> plane, image;  // RANSAC pairs
  std::vector<cv::Point2f> inlierPlane, inlierImage;
  cv::Matx33d k{600, 0, 319.5, 0, 600, 239.5, 0, 0, 1};
  std::string error;
};

const PrimitivesData& primitives() {
  static const PrimitivesData d = [] {
    PrimitivesData r;
    const Orbit& o = orbit();
    if (!o.error.empty()) {
      r.error = o.error;
      return r;
    }
    const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
    const auto scenarios = synthetic::standardScenarios(renderer, kOrbitFrames);
    const auto poseOf = [&](std::size_t i) {
      glm::dmat3 m;
      glm::dvec3 t;
      synthetic::worldToOpenCvCamera(scenarios[0].cameraToWorld[i], m, t);
      const cv::Matx33d rm(m[0][0], m[1][0], m[2][0], m[0][1], m[1][1], m[2][1], m[0][2], m[1][2], m[2][2]);
      return PlanarPose{rodriguesFromRotation(rm), cv::Vec3d(t.x, t.y, t.z)};
    };
    const cv::Mat reference = cv::imread(synthetic::standardTargetImage(), cv::IMREAD_GRAYSCALE);
    cv::pyrDown(reference, r.source);
    r.background = static_cast<std::uint8_t>(cv::mean(reference)[0]);
    cv::cvtColor(o.frames[10], r.frame, cv::COLOR_RGB2GRAY);
    const double mpp = synthetic::kStandardTargetWidth / reference.cols;
    const cv::Matx33d planeToRef(1 / mpp, 0, reference.cols * 0.5 - 0.5, 0, 1 / mpp, reference.rows * 0.5 - 0.5, 0, 0, 1);
    const cv::Matx33d levelToBase(2, 0, 0.5, 0, 2, 0.5, 0, 0, 1);
    const cv::Matx33d w0 = planeToImage(r.k, poseOf(9)) * planeToRef.inv();
    r.warp = w0 * levelToBase;
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(reference, corners, 500, 0.01, 8, cv::noArray(), 5);
    for (const cv::Point2f& c : corners) {
      const cv::Point2f p = applyHomography(w0, c);
      if (p.x >= 15 && p.y >= 15 && p.x < 625 && p.y < 465 && r.from.size() < 200) r.from.push_back(p);
    }
    r.region = (cv::boundingRect(r.from) + cv::Size(240, 240) - cv::Point(120, 120)) & cv::Rect(0, 0, 640, 480);
    r.templ = cv::Mat(480, 640, CV_8UC1, cv::Scalar(r.background));
    warpPerspectiveRegion(r.source, r.warp, r.templ, r.region, r.background);
    cv::RNG rng(1);
    const PlanarPose truth = poseOf(10);
    for (int i = 0; i < 200; ++i) r.plane.emplace_back(rng.uniform(-0.15f, 0.15f), rng.uniform(-0.12f, 0.12f));
    r.image.resize(r.plane.size());
    projectPlanePoints(r.k, truth, r.plane, r.image);
    for (std::size_t i = 0; i < r.image.size(); ++i) {
      const cv::Point2f noise(static_cast<float>(rng.gaussian(0.5)), static_cast<float>(rng.gaussian(0.5)));
      if (i < 60) r.image[i] += cv::Point2f(rng.uniform(-100.f, 100.f), rng.uniform(-100.f, 100.f));
      else r.image[i] += noise, r.inlierPlane.push_back(r.plane[i]), r.inlierImage.push_back(r.image[i]);
    }
    return r;
  }();
  return d;
}

#define MN_PRIMITIVES_DATA(d)                 \
  cv::setNumThreads(1);                       \
  const PrimitivesData& d = primitives();     \
  if (!d.error.empty()) {                     \
    state.SkipWithError(d.error.c_str());     \
    return;                                   \
  }

// range(0): 1 for the widest build the CPU runs (AVX2), 0 for the scalar loop.
void warpOwn(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  cv::Mat out(480, 640, CV_8UC1, cv::Scalar(d.background));
  for (auto _ : state) {
    warpPerspectiveRegion(d.source, d.warp, out, d.region, d.background, state.range(0) != 0);
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["pixels"] = d.region.area();
}

void warpOpenCv(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  cv::Mat out(480, 640, CV_8UC1, cv::Scalar(d.background));
  const cv::Matx33d shift(1, 0, -d.region.x, 0, 1, -d.region.y, 0, 0, 1);
  for (auto _ : state) {
    cv::Mat target = out(d.region);
    cv::warpPerspective(d.source, target, shift * d.warp, d.region.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                        cv::Scalar(d.background));
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["pixels"] = d.region.area();
}

// wide: AVX2 where the CPU has it (else SSE2); window: the level-0 side (a smear widens it to 25).
void kltOwn(benchmark::State& state, bool regionOnly, bool wide = true, int window = 15) {
  MN_PRIMITIVES_DATA(d)
  ImagePyramid t, f;
  t.configure(640, 480, 3);
  f.configure(640, 480, 3);
  LucasKanade lk;
  std::vector<cv::Point2f> to(d.from.size());
  std::vector<std::uint8_t> status(d.from.size());
  int found = 0;
  for (auto _ : state) {
    if (regionOnly) t.buildRegion(d.templ, d.region, d.background);
    else t.build(d.templ);
    f.build(d.frame);
    std::copy(d.from.begin(), d.from.end(), to.begin());
    LucasKanadeOptions params;
    params.wide = wide;
    params.window = window;
    params.coarseWindow = 15;
    found = lk.track(t, f, d.from, to, status, params);
    benchmark::DoNotOptimize(to.data());
  }
  state.counters["points"] = static_cast<double>(d.from.size());
  state.counters["found"] = found;
}

// range(0): 1 for AVX2 where the CPU has it, 0 for the scalar loop; range(1): the smear's angle, degrees.
void motionBlurApply(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  MotionBlurScratch scratch;
  scratch.reserve(640, 480);
  cv::Mat out = d.templ.clone();
  const double angle = static_cast<double>(state.range(1)) * 3.14159265358979 / 180;
  for (auto _ : state) {
    applyMotionBlur(d.templ, {18.0, angle}, d.region, out, scratch, state.range(0) != 0);
    benchmark::DoNotOptimize(out.data);
  }
}

void motionBlurSearch(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  MotionBlurScratch scratch;
  scratch.reserve(640, 480);
  cv::Mat frame = d.templ.clone();
  applyMotionBlur(d.templ, {18.0, 20.0 * 3.14159265358979 / 180}, d.region, frame, scratch);
  MotionBlur found;
  for (auto _ : state) {
    const MotionBlur start = estimateMotionBlur(d.templ, frame, d.from, 128, scratch);
    found = refineMotionBlur(d.templ, frame, d.from, d.from, start, 128, scratch);
    benchmark::DoNotOptimize(found);
  }
  state.counters["length"] = found.lengthPx;
}

// The whole image's shift between two frames of the orbit (image_shift.hpp): what the markerless
// tracker falls back on when a smear defeats KLT on its grid. Smeared: both frames blurred along
// x by 41 px, as a pan smears them. The pyramids are the tracker's, built anyway: not timed.
void imageShift(benchmark::State& state, int smear) {
  cv::setNumThreads(1);
  const Orbit& o = orbit();
  if (!o.error.empty()) {
    state.SkipWithError(o.error.c_str());
    return;
  }
  cv::Mat a, b;
  cv::cvtColor(o.frames[9], a, cv::COLOR_RGB2GRAY);
  cv::cvtColor(o.frames[10], b, cv::COLOR_RGB2GRAY);
  if (smear > 1) {
    cv::blur(a, a, cv::Size(smear, 1));
    cv::blur(b, b, cv::Size(smear, 1));
  }
  ImagePyramid pa, pb;
  pa.configure(640, 480, 3);
  pb.configure(640, 480, 3);
  pa.build(a);
  pb.build(b);
  ImageShift shift;
  bool found = false;
  for (auto _ : state) {
    found = estimateImageShift(pa, pb, {0, 0}, ImageShiftOptions{}, shift);
    benchmark::DoNotOptimize(shift);
  }
  state.counters["found"] = found;
  state.counters["shift_px"] = std::hypot(shift.shift.x, shift.shift.y);
  state.counters["score"] = shift.score;
}

// The dense alignment (dense_alignment.hpp) on orbit frame 10 smeared along x by `smear` px (0:
// sharp), from its true pose turned 1 deg, the smear's turn started at half of the truth's: what
// the tracker runs where KLT on corners fails. The pyramids are built anyway: not timed.
void denseAlignment(benchmark::State& state, int smear, bool verifyOnly = false) {
  cv::setNumThreads(1);
  const Orbit& o = orbit();
  if (!o.error.empty()) {
    state.SkipWithError(o.error.c_str());
    return;
  }
  cv::Mat frame;
  cv::cvtColor(o.frames[10], frame, cv::COLOR_RGB2GRAY);
  if (smear > 1) cv::blur(frame, frame, cv::Size(smear, 1));
  ImagePyramid pyramid;
  pyramid.configure(frame.cols, frame.rows, 3);
  pyramid.build(frame);
  const synthetic::TargetPyramid reference = synthetic::standardTargetPyramid();
  const DenseTarget target{reference.levels, reference.planeToImage};
  const cv::Matx33d k(o.camera.fx, 0, o.camera.cx, 0, o.camera.fy, o.camera.cy, 0, 0, 1);
  glm::dmat3 r;
  glm::dvec3 t;
  synthetic::worldToOpenCvCamera(o.cameraToWorld[10], r, t);
  const cv::Matx33d m(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  const PlanarPose start{rodriguesFromRotation(rotationFromRodrigues(cv::Vec3d(0.0, 0.0175, 0.0)) * m),
                         cv::Vec3d(t.x, t.y, t.z)};
  // A smear of `smear` px along x is a turn of smear / fx about the camera's y axis.
  const cv::Vec3d turn(0.0, 0.5 * smear / o.camera.fx, 0.0);
  DenseAligner aligner;
  DenseAlignmentOptions params;
  aligner.reserve(params);
  DenseAlignment result;
  bool aligned = false;
  for (auto _ : state) {
    aligned = verifyOnly ? aligner.verify(k, target, pyramid, turn, start, params, result)
                         : aligner.align(k, target, pyramid, turn, start, params, result);
    benchmark::DoNotOptimize(result);
  }
  state.counters["aligned"] = aligned;
  if (verifyOnly) state.counters["agreeing_parts"] = result.agreeingParts;
  state.counters["zncc"] = result.zncc;
  state.counters["samples"] = result.samples;
  state.counters["smear_px"] = result.smearPx;
  state.counters["renders"] = result.renders;
}

// The occlusion mask over the target (target_occlusion.hpp) at the orbit's exact poses, the 60
// RGB frames in turn, each smeared along x by `smear` px first (0: sharp; made before timing).
// Counters: the target's mask pixels and the share said hidden (none is: nothing covers it),
// the blur given to the reference (mask pixels), the share of frames computed at twice the scale.
void targetOcclusion(benchmark::State& state, int smear, double closeDistance = 0) {
  cv::setNumThreads(1);
  const Orbit& o = orbit();
  if (!o.error.empty()) {
    state.SkipWithError(o.error.c_str());
    return;
  }
  std::vector<cv::Mat> frames;
  std::vector<glm::dmat4> poses = o.cameraToWorld;
  if (closeDistance > 0) {  // 12 views from closeDistance, 60 deg above the target, turned 45 deg
    const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
    poses.clear();
    for (int k = 0; k < 12; ++k) {
      poses.push_back(synthetic::orbitPose(30.0 * k, 60, closeDistance, 45));
      frames.emplace_back();
      renderer.render(poses.back(), {}, frames.back());
      if (smear > 1) cv::blur(frames.back(), frames.back(), cv::Size(smear, 1));
    }
  } else {
    for (const cv::Mat& f : o.frames) {
      cv::Mat g = f.clone();
      if (smear > 1) cv::blur(f, g, cv::Size(smear, 1));
      frames.push_back(g);
    }
  }
  const synthetic::TargetPyramid reference = synthetic::standardTargetPyramid();
  std::array<double, 9> planeToImage{};
  for (std::size_t k = 0; k < 9; ++k) planeToImage[k] = reference.planeToImage.val[k];
  const cv::Mat& ref = reference.levels[0];
  Diagnostics d;
  auto occlusion = TargetOcclusion::create(o.camera, view(ref), planeToImage, {}, d);
  if (!occlusion) {
    state.SkipWithError(d.format().c_str());
    return;
  }
  std::size_t i = 0;
  double pixels = 0, hidden = 0, blur = 0, coarse = 0;
  for (auto _ : state) {
    occlusion->update(view(frames[i]), poses[i]);
    benchmark::DoNotOptimize(occlusion->mask().pixels);
    pixels += occlusion->mask().targetPixels, hidden += occlusion->mask().hiddenShare, blur += occlusion->mask().blurLength;
    coarse += occlusion->mask().computedScale != occlusion->mask().scale;
    i = (i + 1) % frames.size();
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["target_px"] = pixels / n;
  state.counters["hidden"] = hidden / n;
  state.counters["blur"] = blur / n;
  state.counters["coarse"] = coarse / n;  // share of the frames computed at twice the scale
}

void kltOpenCv(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  std::vector<cv::Point2f> to;
  std::vector<unsigned char> status;
  std::vector<float> error;
  for (auto _ : state) {
    to = d.from;
    cv::calcOpticalFlowPyrLK(d.templ, d.frame, d.from, to, status, error, cv::Size(15, 15), 3,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01),
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    benchmark::DoNotOptimize(to.data());
  }
  state.counters["points"] = static_cast<double>(d.from.size());
  state.counters["found"] = static_cast<double>(std::count(status.begin(), status.end(), 1));
}

// Relocalization's matching of a frame's ORB descriptors (600) against a keyframe's (1200):
// random descriptors, the nearest two of each by Hamming distance.
void hammingMatch(benchmark::State& state) {
  cv::RNG rng(3);
  cv::Mat query(600, 32, CV_8UC1), train(1200, 32, CV_8UC1);
  rng.fill(query, cv::RNG::UNIFORM, 0, 256);
  rng.fill(train, cv::RNG::UNIFORM, 0, 256);
  std::vector<HammingMatch> matches;
  matches.reserve(600);
  for (auto _ : state) {
    matchNearestTwo(query, train, matches);
    benchmark::DoNotOptimize(matches.data());
  }
  state.counters["pairs"] = 600.0 * 1200.0;
}

void ransacOwn(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  HomographyRansac ransac;
  ransac.reserve(d.plane.size());
  std::vector<std::uint8_t> mask(d.plane.size());
  cv::Matx33d h;
  int inliers = 0;
  HomographyRansacOptions params;
  params.thresholdPx = 2.0;
  for (auto _ : state) {
    ransac.estimate(d.plane, d.image, params, h, mask, inliers);
    benchmark::DoNotOptimize(h.val);
  }
  state.counters["inliers"] = inliers;
}

void ransacOpenCv(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  std::vector<unsigned char> mask;
  cv::Mat h;
  for (auto _ : state) {
    h = cv::findHomography(d.plane, d.image, cv::RANSAC, 2.0, mask, 500, 0.995);
    benchmark::DoNotOptimize(h.data);
  }
  state.counters["inliers"] = cv::countNonZero(mask);
}

void poseOwn(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  HomographyRansac fit;
  fit.reserve(d.inlierPlane.size());
  cv::Matx33d h;
  if (!fit.fit(d.inlierPlane, d.inlierImage, {}, 10, h)) {
    state.SkipWithError("no homography");
    return;
  }
  PlanarPose pose;
  double rms = 0;
  for (auto _ : state) {
    planarPoseFromHomography(d.k, h, d.inlierPlane, d.inlierImage, {}, PoseRefineOptions{}, pose, rms);
    rms = reprojectionRms(d.k, pose, d.inlierPlane, d.inlierImage, {});
    benchmark::DoNotOptimize(rms);
  }
  state.counters["rms"] = rms;
}

void poseOpenCv(benchmark::State& state) {
  MN_PRIMITIVES_DATA(d)
  std::vector<cv::Point3f> object;
  for (const cv::Point2f& p : d.inlierPlane) object.emplace_back(p.x, 0.f, p.y);
  std::vector<cv::Point2f> projected;
  double rms = 0;
  for (auto _ : state) {
    cv::Vec3d rvec, tvec;
    cv::solvePnP(object, d.inlierImage, d.k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE);
    cv::solvePnPRefineLM(object, d.inlierImage, d.k, cv::noArray(), rvec, tvec,
                         cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 1e-9));
    cv::projectPoints(object, rvec, tvec, d.k, cv::noArray(), projected);
    double sum = 0;
    for (std::size_t i = 0; i < projected.size(); ++i) {
      const cv::Point2f e = projected[i] - d.inlierImage[i];
      sum += e.dot(e);
    }
    rms = std::sqrt(sum / static_cast<double>(projected.size()));
    benchmark::DoNotOptimize(rms);
  }
  state.counters["rms"] = rms;
}

}  // namespace


// A tracker's first frame: nothing predicts it, so it relocalizes (ORB over the whole frame).
// The tracker is made outside the timing, as an application makes it before its first frame;
// ORB's first frame-sized call is made there since session 40 (warmUpRelocalization).
void markerlessFirstFrame(benchmark::State& state) {
  const Orbit& o = orbit();
  if (!orbitTracker(state, o)) return;
  long relocalized = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::string error;
    auto tracker = markerless(o, error);
    state.ResumeTiming();
    const TrackedPose p = tracker->update(view(o.frames[0]), 0.0);
    benchmark::DoNotOptimize(p);
    relocalized += tracker->lastFrame().relocalized;
    state.PauseTiming();
    tracker.reset();
    state.ResumeTiming();
  }
  state.counters["relocalized"] = static_cast<double>(relocalized) / static_cast<double>(state.iterations());
}

// The tests' synthetic renderer (not the middleware): one stress-like exposure of 8 sub-frames
// (a pan's smear across the target and the floor), its scene samples four at a time with AVX2
// (arg 1) or one at a time (arg 0): the same bits (SyntheticSequenceRender.WideScene...), the
// time that most of the tracking tests spend (docs/testing.md).
void syntheticExposure(benchmark::State& state) {
  cv::setNumThreads(1);
  synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  renderer.useWideSamples(state.range(0) != 0);
  if (state.range(0) != 0 && !renderer.wideSamples()) {
    state.SkipWithError("AVX2 absent");
    return;
  }
  std::vector<synthetic::SubFrame> subFrames;
  for (int k = 0; k < 8; ++k) {
    const double a = 0.02 * k;  // radians of pan across the exposure
    const glm::dvec3 eye(0.0, 0.55, 0.45);
    subFrames.push_back({synthetic::lookAtCameraToWorld(eye, glm::dvec3(0.3 * std::sin(a), 0.0, -0.3 * std::cos(a) + 0.3),
                                                        glm::dvec3(0, 1, 0)),
                         {}});
  }
  cv::Mat linear;
  for (auto _ : state) {
    renderer.renderLinear(subFrames, synthetic::FrameEffects{}, linear);
    benchmark::DoNotOptimize(linear.data);
  }
  state.counters["subframes"] = 8;
}

BENCHMARK(markerlessFrame)->Name("Tracking/MarkerlessFrame")->Unit(benchmark::kMillisecond);
BENCHMARK(markerlessFirstFrame)->Name("Tracking/MarkerlessFirstFrame")->Unit(benchmark::kMillisecond);
BENCHMARK(syntheticExposure)->Name("TrackingTestData/SyntheticExposure8")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(markerlessRelocalize)->Name("Tracking/MarkerlessRelocalize")->Unit(benchmark::kMillisecond);
BENCHMARK(markerlessRelocalizeNoTarget)
    ->Name("Tracking/MarkerlessRelocalizeNoTarget")
    ->ArgName("tiltedViewFeatures")
    ->Arg(400)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(aprilTagFrame)->Name("Tracking/AprilTagFrame")->Unit(benchmark::kMillisecond);
BENCHMARK(memcpy640x480)->Name("Tracking/Memcpy640x480")->Unit(benchmark::kMicrosecond);
BENCHMARK(hammingMatch)->Name("Tracking/HammingMatch")->Unit(benchmark::kMicrosecond);
BENCHMARK(warpOwn)->Name("Tracking/WarpOwn")->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(warpOwn)->Name("Tracking/WarpOwnScalar")->Arg(0)->Unit(benchmark::kMicrosecond);
BENCHMARK(warpOpenCv)->Name("Tracking/WarpOpenCv")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kltOwn, full, false)->Name("Tracking/KltOwn")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kltOwn, region, true)->Name("Tracking/KltOwnRegion")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kltOwn, region, true, false)->Name("Tracking/KltOwnRegionSse2")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kltOwn, region, true, true, 25)->Name("Tracking/KltOwnRegionWindow25")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(kltOwn, region, true, false, 25)->Name("Tracking/KltOwnRegionWindow25Sse2")->Unit(benchmark::kMicrosecond);
BENCHMARK(kltOpenCv)->Name("Tracking/KltOpenCv")->Unit(benchmark::kMicrosecond);
BENCHMARK(motionBlurApply)->Name("Tracking/MotionBlurApply")->Args({1, 20})->Args({0, 20})->Args({1, 75})->Args({0, 75})->Unit(benchmark::kMicrosecond);
BENCHMARK(motionBlurSearch)->Name("Tracking/MotionBlurSearch")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(imageShift, sharp, 0)->Name("Tracking/ImageShift")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(imageShift, smeared, 41)->Name("Tracking/ImageShiftSmeared")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(denseAlignment, sharp, 0)->Name("Tracking/DenseAlignment")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(denseAlignment, smeared, 41)->Name("Tracking/DenseAlignmentSmeared")->Unit(benchmark::kMicrosecond);
// The check of a carried pose: one render at the fine level, nothing fitted (at the alignment
// benchmark's start, 1 deg about the target's origin: its parts all agree there).
BENCHMARK_CAPTURE(denseAlignment, verify, 0, true)->Name("Tracking/DenseVerify")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(targetOcclusion, sharp, 0)->Name("Tracking/TargetOcclusion")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(targetOcclusion, smeared, 24)->Name("Tracking/TargetOcclusionSmeared")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(targetOcclusion, close, 0, 0.32)->Name("Tracking/TargetOcclusionClose")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(targetOcclusion, near, 0, 0.55)->Name("Tracking/TargetOcclusionNear")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(targetOcclusion, nearSmeared, 24, 0.55)->Name("Tracking/TargetOcclusionNearSmeared")->Unit(benchmark::kMicrosecond);
BENCHMARK(ransacOwn)->Name("Tracking/RansacOwn")->Unit(benchmark::kMicrosecond);
BENCHMARK(ransacOpenCv)->Name("Tracking/RansacOpenCv")->Unit(benchmark::kMicrosecond);
BENCHMARK(poseOwn)->Name("Tracking/PoseOwn")->Unit(benchmark::kMicrosecond);
BENCHMARK(poseOpenCv)->Name("Tracking/PoseOpenCv")->Unit(benchmark::kMicrosecond);
