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

const std::map<std::string, ScenarioRun>& runs() {
  static const std::map<std::string, ScenarioRun> all = [] {
    cv::setNumThreads(1);
    const SequenceRenderer renderer = standardRenderer();
    std::map<std::string, ScenarioRun> out;
    for (const RenderedScenario& s : renderScenarios(renderer, 60))
      out.emplace(s.scenario.name, runMarkerless(s, renderer.camera(), MarkerlessSettings{}));
    return out;
  }();
  return all;
}

double shareWithin2cm(const TrajectoryReport& r) { return double(r.within2cm) / r.visibleFrames; }

TEST(TrackingAccuracy, NoFalsePoseInAnyScenario) {
  for (const auto& [name, run] : runs()) {
    std::printf("%-14s %s\n", name.c_str(), formatReport(run.report).c_str());
    EXPECT_EQ(run.report.falsePoses, 0) << name;
  }
}

TEST(TrackingAccuracy, OrbitWithinAMillimetresAndATenthOfADegree) {
  const TrajectoryReport& r = runs().at("orbit").report;
  EXPECT_EQ(r.verifiedFrames, r.frames);
  EXPECT_LT(r.ateRmsM, 0.005);  // goal 0.5 cm
  EXPECT_LT(r.rotationMeanDeg, 0.5);
}

TEST(TrackingAccuracy, StaticCameraDoesNotJitter) {
  const TrajectoryReport& r = runs().at("static").report;
  EXPECT_EQ(r.verifiedFrames, r.frames);
  EXPECT_LT(r.jitterMm, 0.5);
}

TEST(TrackingAccuracy, HardViewsStayWithinTwoCentimetres) {
  // Noise and JPEG 30, +-1 EV gain, an occluder over 20..60 %, 50..80 % of the target out of
  // view, grazing views to 70 degrees, fast turns: at least 95 % of the visible frames.
  for (const char* name : {"noise_jpeg", "gain", "occluder", "partial", "grazing", "fast_turn", "lost_regained"}) {
    const TrajectoryReport& r = runs().at(name).report;
    EXPECT_GE(shareWithin2cm(r), 0.95) << name << ": " << formatReport(r);
  }
}

TEST(TrackingAccuracy, RelocalizesWithinTenFramesOfTheTargetReturning) {
  const TrajectoryReport& r = runs().at("lost_regained").report;
  ASSERT_GE(r.framesToRelocalize, 0) << formatReport(r);
  EXPECT_LE(r.framesToRelocalize, 10);
}

// Motion blur of 9..25 px is where the tracker falls short of its goal (docs/tracking.md):
// poses go LIMITED, never TRACKING off by more than 5 cm. Asserted as it is, so that a change
// that makes it worse (or better) shows.
TEST(TrackingAccuracy, MotionBlurDegradesToLimitedNotToFalsePoses) {
  const TrajectoryReport& r = runs().at("blur").report;
  EXPECT_EQ(r.falsePoses, 0);
  EXPECT_GE(shareWithin2cm(r), 0.2) << formatReport(r);
}

}  // namespace
