#include "tracking/scenario_run.hpp"
#include "test_paths.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace marionette::ar::synthetic {

namespace {

cv::Mat readRgb(const std::string& file) {
  cv::Mat bgr = cv::imread(file, cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error(file + ": test data missing (Debian opencv-doc)");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

}  // namespace

std::string standardTargetImage() { return ::marionette::test::opencvDataDir() + "/graf1.png"; }

TargetPyramid standardTargetPyramid() {
  TargetPyramid p;
  const cv::Mat g = cv::imread(standardTargetImage(), cv::IMREAD_GRAYSCALE);
  if (g.empty()) throw std::runtime_error(standardTargetImage() + ": test data missing (Debian opencv-doc)");
  p.levels.push_back(g);
  while (p.levels.size() < 8 && p.levels.back().cols >= 32 && p.levels.back().rows >= 32) {
    cv::Mat down;
    cv::pyrDown(p.levels.back(), down);
    p.levels.push_back(down);
  }
  const double s = kStandardTargetWidth / g.cols;
  p.planeToImage = cv::Matx33d(1 / s, 0, g.cols * 0.5 - 0.5, 0, 1 / s, g.rows * 0.5 - 0.5, 0, 0, 1);
  return p;
}

cv::Mat standardTargetGrey(cv::Size size) {
  const cv::Mat g = cv::imread(standardTargetImage(), cv::IMREAD_GRAYSCALE);
  if (g.empty()) throw std::runtime_error(standardTargetImage() + ": test data missing (Debian opencv-doc)");
  cv::Mat out;
  cv::resize(g, out, size, 0, 0, cv::INTER_AREA);
  return out;
}

SequenceRenderer standardRenderer() {
  PlanarScene scene;
  scene.target = readRgb(standardTargetImage());
  scene.targetWidth = kStandardTargetWidth;
  scene.floor = readRgb(::marionette::test::opencvDataDir() + "/baboon.jpg");
  scene.floorMetresPerPixel = 0.002;
  const CameraModel camera{.width = 640, .height = 480, .fx = 600, .fy = 600, .cx = 319.5, .cy = 239.5};
  return SequenceRenderer(scene, camera);
}

std::vector<RenderedScenario> renderScenarios(const SequenceRenderer& renderer, int framesPerScenario,
                                              const std::vector<std::string>& names) {
  std::vector<RenderedScenario> out;
  for (Scenario& s : standardScenarios(renderer, framesPerScenario)) {
    if (!names.empty() && std::find(names.begin(), names.end(), s.name) == names.end()) continue;
    RenderedScenario r;
    r.frames.resize(s.cameraToWorld.size());
    for (std::size_t i = 0; i < s.cameraToWorld.size(); ++i) renderer.render(s.cameraToWorld[i], s.effects[i], r.frames[i]);
    r.scenario = std::move(s);
    out.push_back(std::move(r));
  }
  return out;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}

ScenarioRun runMarkerless(const RenderedScenario& rendered, const CameraModel& camera,
                          const MarkerlessSettings& settings) {
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(camera, standardTargetImage(), kStandardTargetWidth, settings, d);
  if (!tracker) throw std::runtime_error(d.format());
  ScenarioRun run;
  for (std::size_t i = 0; i < rendered.frames.size(); ++i) {
    const cv::Mat& f = rendered.frames[i];
    const ImageView view{f.data, f.cols, f.rows, 3, static_cast<std::ptrdiff_t>(f.step)};
    const auto t0 = std::chrono::steady_clock::now();
    run.poses.push_back(tracker->update(view, static_cast<double>(i) / rendered.scenario.fps));
    run.ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    run.relocalizations += tracker->lastFrame().relocalized;
    if (std::getenv("MN_FRAMES")) {  // a line per frame, for calibrating the gates (docs/tracking.md)
      const TrackedPose& p = run.poses.back();
      const auto& st = tracker->lastFrame();
      const glm::dmat4& truth = rendered.scenario.cameraToWorld[i];
      const bool lost = p.state == TrackingState::Lost;
      std::fprintf(stderr,
                   "%s %zu: %s vis %.2f err %.1f mm %.2f deg sigma %.1f mm %.3f deg inl %d/%d rms %.2f spread %.2f "
                   "ncc %.2f motion %.1f/%.1f mm %.2f/%.2f deg rej %d reloc %d bg %d%s%s%s extra %d kf %d added %d judged %.1f mm %.2f deg ms %.2f pred %.1f mm %.2f deg blur %.1f smear %.1f share %.2f vis %.2f frame %.2f parts %d/%d span %.2f stages %.1f %.1f %.1f %.1f hidden %.2f carry %d given %.1f mm %.3f deg\n",
                   rendered.scenario.name.c_str(), i, std::string(trackingStateName(p.state)).c_str(),
                   rendered.scenario.visibleFraction[i], lost ? -1.0 : 1000 * glm::length(p.position() - glm::dvec3(truth[3])),
                   lost ? -1.0 : rotationErrorDeg(p.cameraToWorld, truth), 1000 * st.positionSigmaM, st.rotationSigmaDeg,
                   st.inliers, st.corners, st.rmsPx, st.spread, st.ncc, 1000 * st.motionPositionM,
                   1000 * st.motionPositionLimitM, st.motionRotationDeg, st.motionRotationLimitDeg,
                   static_cast<int>(st.rejection), st.relocalized, st.backgroundMotion, st.imageShift ? "s" : "", st.dense ? "d" : "", st.reentry ? "r" : "", st.extrapolated, st.keyframe,
                   st.keyframeAdded, st.inliers > 0 ? 1000 * glm::length(glm::dvec3(st.judgedCameraToWorld[3]) - glm::dvec3(truth[3])) : -1.0,
                   st.inliers > 0 ? rotationErrorDeg(st.judgedCameraToWorld, truth) : -1.0, run.ms.back(),
                   st.predicted ? 1000 * glm::length(glm::dvec3(st.predictedCameraToWorld[3]) - glm::dvec3(truth[3])) : -1.0,
                   st.predicted ? rotationErrorDeg(st.predictedCameraToWorld, truth) : -1.0, st.blurPx,
                   i < rendered.scenario.smearPx.size() ? rendered.scenario.smearPx[i] : 0.0, st.inlierShare, st.visibleShare, st.frameShare,
                   st.agreeingParts, st.parts, st.agreeingSpan, st.motionMs, st.kltMs, st.denseMs, st.relocalizationMs,
                   i < rendered.scenario.hiddenFraction.size() ? rendered.scenario.hiddenFraction[i] : 0.0, st.carried,
                   1000 * p.positionSigmaM, p.rotationSigmaDeg);
    }
  }
  run.keyframes = static_cast<int>(tracker->map().keyframes.size());
  run.medianMs = percentile(run.ms, 0.5);
  run.p95Ms = percentile(run.ms, 0.95);
  run.report = compareTrajectory(run.poses, rendered.scenario.cameraToWorld, rendered.scenario.visibleFraction, camera);
  return run;
}

}  // namespace marionette::ar::synthetic
