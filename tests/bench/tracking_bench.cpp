// marionette_bench: camera tracking per frame (examples/ar/tracking), one thread
// (cv::setNumThreads(1), as marionette-ar runs it). Time is milliseconds per update().
//   Tracking/MarkerlessFrame       the markerless tracker's per-frame update() over the
//                                  standard `orbit` sequence (60 frames, 640x480 RGB, rendered
//                                  once), the frames played forwards then backwards so the
//                                  motion has no jump, after one warm-up pass (the first frame
//                                  relocalizes). Counters: inliers (mean), relocalized and lost
//                                  (shares of the timed frames: 0 when tracking holds),
//                                  keyframes (the map's size at the end).
//   Tracking/MarkerlessRelocalize  reset() before every update() on the same frames: each
//                                  frame relocalizes from scratch (ORB + matching + RANSAC,
//                                  then the tracking check), the LOST path's cost. Counter
//                                  tracking = share of frames found TRACKING from nothing.
//   Tracking/AprilTagFrame         AprilTagTracker::update on ViSP's tag36_11_640x480.png
//                                  (fx = fy = 700, tag 0.2 m, decimate 2). Counters: tags, inliers.
//   Tracking/Memcpy640x480         a memcpy of one 640x480 RGB frame: the floor for a ratio.
#include <benchmark/benchmark.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
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
    } catch (const std::exception& e) {
      r.error = e.what();
    }
    return r;
  }();
  return o;
}

std::unique_ptr<MarkerlessTracker> markerless(const Orbit& o, std::string& error) {
  Diagnostics d;
  auto t = MarkerlessTracker::fromTarget(o.camera, synthetic::standardTargetImage(), synthetic::kStandardTargetWidth,
                                         MarkerlessSettings{}, d);
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

void aprilTagFrame(benchmark::State& state) {
  cv::setNumThreads(1);
  const std::string file =
      std::string(MARIONETTE_VISP_IMAGES) + "/AprilTag/benchmark/640x480/tag36_11_640x480.png";
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

}  // namespace

BENCHMARK(markerlessFrame)->Name("Tracking/MarkerlessFrame")->Unit(benchmark::kMillisecond);
BENCHMARK(markerlessRelocalize)->Name("Tracking/MarkerlessRelocalize")->Unit(benchmark::kMillisecond);
BENCHMARK(aprilTagFrame)->Name("Tracking/AprilTagFrame")->Unit(benchmark::kMillisecond);
BENCHMARK(memcpy640x480)->Name("Tracking/Memcpy640x480")->Unit(benchmark::kMicrosecond);
