// The markerless tracker against exact ground truth on the standard scenarios
// (tests/support/tracking/scenarios.hpp), 60 frames each, one thread: the goals of
// docs/tracking.md that the tracker meets, asserted so that a regression fails. The full
// 150-frame table is marionette_tracking_eval's (docs/tracking.md gives the command).
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <opencv2/core/utility.hpp>

#include "tracking/scenario_run.hpp"

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
  for (const RenderedScenario& s : renderScenarios(renderer, 60))
    runs.emplace(s.scenario.name, runMarkerless(s, renderer.camera(), MarkerlessSettings{}));
  ASSERT_EQ(runs.size(), 10u);

  // No false pose anywhere.
  for (const auto& [name, run] : runs) {
    std::printf("%-14s %s\n", name.c_str(), formatReport(run.report).c_str());
    EXPECT_EQ(run.report.falsePoses, 0) << name;
  }
  // The orbit within half a centimetre (the stretch goal) and half a degree.
  const TrajectoryReport& orbit = runs.at("orbit").report;
  EXPECT_EQ(orbit.verifiedFrames, orbit.frames);
  EXPECT_LT(orbit.ateRmsM, 0.005);
  EXPECT_LT(orbit.rotationMeanDeg, 0.5);
  // A still camera does not jitter.
  const TrajectoryReport& still = runs.at("static").report;
  EXPECT_EQ(still.verifiedFrames, still.frames);
  EXPECT_LT(still.jitterMm, 0.5);
  // Motion blur of 9..25 px, noise and JPEG 30, +-1 EV gain, an occluder over 20..60 %, 50..80 %
  // of the target out of view, grazing views to 70 degrees, fast turns: at least 95 % of the
  // visible frames.
  for (const char* name : {"blur", "noise_jpeg", "gain", "occluder", "partial", "grazing", "fast_turn", "lost_regained"}) {
    const TrajectoryReport& r = runs.at(name).report;
    EXPECT_GE(shareWithin2cm(r), 0.95) << name << ": " << formatReport(r);
  }
  // Relocalized within ten frames of the target coming back.
  const TrajectoryReport& lost = runs.at("lost_regained").report;
  EXPECT_GE(lost.framesToRelocalize, 0) << formatReport(lost);
  EXPECT_LE(lost.framesToRelocalize, 10);
  // Under blur the template is smeared as the frame is, so most blurred frames stay TRACKING.
  const TrajectoryReport& blur = runs.at("blur").report;
  EXPECT_GE(blur.verifiedFrames, blur.frames / 2) << formatReport(blur);
}

}  // namespace
