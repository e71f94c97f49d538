// The markerless tracker against exact ground truth on the standard scenarios
// (tests/support/tracking/scenarios.hpp), 60 frames each, one thread: the goals of
// docs/tracking.md that the tracker meets, asserted so that a regression fails. The full
// 150-frame table is marionette_tracking_eval's (docs/tracking.md gives the command).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include <opencv2/core/utility.hpp>

#include "tracking/scenario_run.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace {

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

double shareWithin2cm(const TrajectoryReport& r) { return double(r.within2cm) / r.visibleFrames; }

// One test, not one per goal: ctest runs each GoogleTest test in a process of its own, and the
// scenarios take 40 s to render and track.
TEST(TrackingAccuracy, StandardScenariosMeetTheGoals) {
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  std::map<std::string, ScenarioRun> runs;
  std::map<std::string, double> within3Sigma;  // share of the drawn poses whose errors are within 3 sigma
  for (const RenderedScenario& s : renderScenarios(renderer, 60)) {
    ScenarioRun run = runMarkerless(s, renderer.camera(), MarkerlessSettings{});
    int drawn = 0, within = 0;
    for (std::size_t i = 0; i < run.poses.size(); ++i) {
      const TrackedPose& p = run.poses[i];
      if (p.state == TrackingState::Lost) continue;
      ++drawn;
      const double position = glm::length(p.position() - glm::dvec3(s.scenario.cameraToWorld[i][3]));
      const double rotation = rotationErrorDeg(p.cameraToWorld, s.scenario.cameraToWorld[i]);
      within += position <= 3 * p.positionSigmaM && rotation <= 3 * p.rotationSigmaDeg;
    }
    within3Sigma[s.scenario.name] = drawn > 0 ? double(within) / drawn : 0.0;
    runs.emplace(s.scenario.name, std::move(run));
  }
  ASSERT_EQ(runs.size(), 10u);

  // The confidence tells the truth: the errors of the drawn poses lie within three of their
  // standard deviations, poses measured against keyframes of the floor (fast_turn looks away
  // across it) included: their keyframe's own error counts (docs/tracking.md, "Confidence").
  for (const auto& [name, share] : within3Sigma) {
    std::printf("[ %s ] %.1f %% of the drawn poses within 3 sigma\n", name.c_str(), 100 * share);
    EXPECT_GE(share, 0.95) << name;
  }

  // No false pose anywhere.
  for (const auto& [name, run] : runs) {
    std::printf("%-14s %s\n", name.c_str(), formatReport(run.report).c_str());
    EXPECT_EQ(run.report.falsePoses, 0) << name;
  }
  // The orbit within half a centimetre (the stretch goal) and half a degree. Every frame but
  // the first TRACKING: a relocalization is given once the next frame confirms it.
  const TrajectoryReport& orbit = runs.at("orbit").report;
  EXPECT_EQ(orbit.verifiedFrames, orbit.frames - 1);
  EXPECT_LT(orbit.ateRmsM, 0.005);
  EXPECT_LT(orbit.rotationMeanDeg, 0.5);
  // regression: docs/tracking.md's table (150 frames) publishes orbit ATE rms 0.11 cm and rotation
  // mean 0.06 degrees (these 60 frames: the same); 1.5x.
  EXPECT_LT(orbit.ateRmsM, 0.00165);
  EXPECT_LT(orbit.rotationMeanDeg, 0.09);
  // A still camera does not jitter.
  const TrajectoryReport& still = runs.at("static").report;
  EXPECT_EQ(still.verifiedFrames, still.frames - 1);
  std::printf("static jitter %.4f mm (smoothed)\n", still.jitterMm);
  EXPECT_LT(still.jitterMm, 0.5);
  // regression: docs/tracking.md publishes 0.039 mm, smoothed as here (the default; 0.12 mm
  // unsmoothed), over 150 frames; 1.5x.
  EXPECT_LT(still.jitterMm, 0.06);
  // Motion blur of 9..25 px, noise and JPEG 30, +-1 EV gain, an occluder over 20..60 %, 50..80 %
  // of the target out of view, grazing views to 70 degrees, fast turns: at least 95 % of the
  // visible frames.
  for (const char* name : {"blur", "noise_jpeg", "gain", "occluder", "partial", "grazing"}) {
    const TrajectoryReport& r = runs.at(name).report;
    EXPECT_GE(shareWithin2cm(r), 0.95) << name << ": " << formatReport(r);
  }
  // Where the target comes back into view, a relocalized pose is given only once the next frame
  // confirms it (docs/tracking.md, "Gating"): on these 60-frame versions each return costs a
  // frame or two of the 38-40 visible ones (92 % and 90 % measured; issue 40 keeps 95 % as the
  // goal).
  for (const char* name : {"fast_turn", "lost_regained"}) {
    const TrajectoryReport& r = runs.at(name).report;
    EXPECT_GE(shareWithin2cm(r), 0.89) << name << ": " << formatReport(r);
  }
  // No drawn pose wildly wrong: within 5 cm and 2 degrees everywhere.
  for (const auto& [name, run] : runs) {
    EXPECT_LT(run.report.ateMaxM, 0.05) << name;
    EXPECT_LT(run.report.rotationMaxDeg, 2.0) << name;
    // regression: docs/tracking.md publishes 2.33 cm as the worst ATE max (fast_turn, 150
    // frames); 1.5x.
    EXPECT_LT(run.report.ateMaxM, 0.035) << name;
  }
  // Relocalized within ten frames of the target coming back.
  const TrajectoryReport& lost = runs.at("lost_regained").report;
  EXPECT_GE(lost.framesToRelocalize, 0) << formatReport(lost);
  EXPECT_LE(lost.framesToRelocalize, 10);
  // Under blur the template is smeared as the frame is, so the blurred frames keep a pose (a
  // third or more TRACKING: a smeared frame's pose is less certain, LIMITED when three standard
  // deviations pass TRACKING's bounds).
  const TrajectoryReport& blur = runs.at("blur").report;
  EXPECT_GE(blur.trackedFrames, blur.frames - 1) << formatReport(blur);
  EXPECT_GE(blur.verifiedFrames, blur.frames / 3) << formatReport(blur);
}

}  // namespace
