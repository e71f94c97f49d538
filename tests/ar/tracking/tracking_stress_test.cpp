// The markerless tracker on 20 fresh stress sequences (tests/support/tracking/stress_scenarios.hpp:
// random hand-held pans to 180 deg/s, re-entries from each image edge, hands crossing, gain,
// white-balance and defocus jumps; every frame an exposure averaged from sub-frames), judged by
// its WORST drawn pose, not the mean (issue 40). About a minute on two cores, most of it
// rendering. The table in docs/tracking.md is `marionette_tracking_eval --stress 20 --split`.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "marionette/core/diagnostic.hpp"
#include "tracking/scenario_run.hpp"
#include "tracking/stress_run.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace {

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

// One stress sequence of `kind` and `seed`, rendered from sub-frame exposures (or read back from
// the tests' cache), as the single-sequence tests below track it.
RenderedScenario renderedStress(const SequenceRenderer& renderer, StressClass kind, int seed) {
  const StressSequence sequence = stressSequence(renderer, kind, seed, defaultStressFrames(kind));
  std::vector<double> renderMs;
  return cachedRender(renderer, sequence, StressOptions{}, 2, renderMs);
}

TEST(TrackingStress, NoDrawnPoseIsWildlyWrongOnTwentySeeds) {
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  const StressReport report = runStressSeeds(renderer, stressCases(20, true), MarkerlessSettings{});
  std::printf("%s\n", stressTable(report).c_str());
  ASSERT_EQ(report.classes.size(), 4u);
  for (const StressClassReport& c : report.classes) {
    const std::string name(stressClassName(c.kind));
    ASSERT_EQ(c.sequences, 5) << name;
    ASSERT_GT(c.visibleFrames, 0) << name;
    // The promise: no drawn pose (TRACKING or LIMITED) 5 cm or 2 degrees off, on any frame.
    EXPECT_EQ(c.falsePoses, 0) << name;
    EXPECT_LT(c.worstPosition.value, 0.05) << name << " seed " << c.worstPosition.seed << " frame " << c.worstPosition.frame;
    EXPECT_LT(c.worstRotation.value, 2.0) << name << " seed " << c.worstRotation.seed << " frame " << c.worstRotation.frame;
    EXPECT_LT(c.trackingRmsM, 0.005) << name;
    // Regression bounds (issue 41: about 1.5x what docs/tracking.md publishes for this plan,
    // session 34: worst drawn 1.24 cm and 0.85 deg over the classes, TRACKING rms 0.14-0.21 cm).
    EXPECT_LT(c.worstPosition.value, 0.019) << name << " (regression: 1.24 cm published)";
    EXPECT_LT(c.worstRotation.value, 1.3) << name << " (regression: 0.85 deg published)";
    EXPECT_LT(c.trackingRmsM, 0.0032) << name << " (regression: 0.21 cm published)";
  }
  // Coverage: issue 40's goal is 95 % of the visible frames within 2 cm. Measured 94.8, 95.9,
  // 97.0 and 95.0 % (docs/tracking.md; 86.8, 85.3, 91.0 and 95.0 % before the floor around the
  // target was mapped; 85.1, 82.9, 84.0 and 95.0 % before the dense poses were judged by parts;
  // 69.5, 65.3, 84.5 and 95.0 % before the dense alignment followed smears). As regression
  // bounds (issue 41): the frames missed may grow at most 1.5 times, 5.2 / 4.1 / 3.0 / 5.0 %
  // published. (The floor keyframes lost: pan and reentry fall to 87 %, hands to 91 %.)
  const double minimum[4] = {0.92, 0.935, 0.95, 0.925};
  for (const StressClassReport& c : report.classes) {
    EXPECT_GE(double(c.within2cm) / c.visibleFrames, minimum[static_cast<std::size_t>(c.kind)])
        << stressClassName(c.kind);
  }
  // The goal itself, over every visible frame of the plan (fast pans and edge re-entries
  // included, as issue 40 counts it): 95.7 % measured (784 of 819 frames).
  EXPECT_GE(double(report.all.within2cm) / report.all.visibleFrames, 0.95)
      << report.all.within2cm << " of " << report.all.visibleFrames;
  EXPECT_EQ(report.all.falsePoses, 0);
}

// A look away whose chain of image motions breaks (up at a blank sky, or through a smear the
// image's motion cannot follow) leaves nothing to predict from; the target then comes back
// smeared by 40-100 px, where ORB finds no features. The re-entry search aligns the reference
// densely from the poses of the way out (docs/tracking.md, "Re-entry along the way out"):
// on `pan/12` the target is drawn again frames earlier, each such pose confirmed by the next
// frame, and nothing drawn is off.
TEST(TrackingStress, ATargetComingBackThroughASmearIsFoundFromTheWayOut) {
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  const RenderedScenario rendered = renderedStress(renderer, StressClass::Pan, 12);
  const Scenario& truth = rendered.scenario;
  struct Outcome {
    int within2cm = 0, found = 0, foundThenDrawn = 0;
    double worstCm = 0, worstDeg = 0;
  };
  auto run = [&](const MarkerlessSettings& settings) {
    marionette::Diagnostics d;
    auto tracker = MarkerlessTracker::fromTarget(renderer.camera(), standardTargetImage(), kStandardTargetWidth, settings, d);
    EXPECT_TRUE(tracker) << d.format();
    Outcome o;
    if (!tracker) return o;
    bool foundLast = false;
    for (std::size_t i = 0; i < rendered.frames.size(); ++i) {
      const cv::Mat& f = rendered.frames[i];
      const TrackedPose p = tracker->update({f.data, f.cols, f.rows, 3, static_cast<std::ptrdiff_t>(f.step)},
                                           static_cast<double>(i) / truth.fps);
      const bool drawn = p.state != TrackingState::Lost;
      if (drawn) {
        const double cm = 100 * glm::length(p.position() - glm::dvec3(truth.cameraToWorld[i][3]));
        const double deg = rotationErrorDeg(p.cameraToWorld, truth.cameraToWorld[i]);
        o.worstCm = std::max(o.worstCm, cm), o.worstDeg = std::max(o.worstDeg, deg);
        o.within2cm += truth.visibleFraction[i] > 0 && cm < 2;
      }
      o.foundThenDrawn += foundLast && drawn;
      const auto& st = tracker->lastFrame();
      o.found += st.reentry;
      foundLast = st.reentry && st.rejection == MarkerlessTracker::Rejection::Unconfirmed;
    }
    return o;
  };
  const Outcome with = run(MarkerlessSettings{});
  MarkerlessSettings off;
  off.reentrySearch = false;
  const Outcome without = run(off);
  std::printf("pan/12: %d visible frames within 2 cm with the re-entry search (%d poses found from the way out, %d "
              "confirmed and drawn the next frame; worst drawn %.2f cm, %.2f deg), %d without\n",
              with.within2cm, with.found, with.foundThenDrawn, with.worstCm, with.worstDeg, without.within2cm);
  EXPECT_GE(with.foundThenDrawn, 1) << "a pose found from the way out, confirmed by the next frame";
  EXPECT_GE(with.within2cm, without.within2cm + 3) << "the target drawn again earlier";
  EXPECT_LT(with.worstCm, 5.0);
  EXPECT_LT(with.worstDeg, 2.0);
  EXPECT_EQ(without.found, 0);
}

// A blur model KLT kept from a smear must not outlive it. On `reentry/54` (a seed past the 40 the
// docs tabulated) a 25 px template blur was carried through two dense poses onto sharp frames
// (frames 24-26, their own smear under 1 px), and KLT against the floor keyframe found 14-15 of 28
// corners agreeing on a pose 2.6 deg and 3.8 cm off, drawn LIMITED. A dense pose that measures a
// smear under half the blur model's now ends it (docs/tracking.md, session 38).
TEST(TrackingStress, ABlurModelEndsWhereADensePoseMeasuresNoSmear) {
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  const RenderedScenario rendered = renderedStress(renderer, StressClass::Reentry, 54);
  const Scenario& truth = rendered.scenario;
  marionette::Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(renderer.camera(), standardTargetImage(), kStandardTargetWidth, {}, d);
  ASSERT_TRUE(tracker) << d.format();
  ASSERT_GT(rendered.frames.size(), 27u);
  double worstCm = 0, worstDeg = 0;
  int drawnNear = 0;  // frames 24-26 drawn within 2 cm
  for (std::size_t i = 0; i < rendered.frames.size(); ++i) {
    const cv::Mat& f = rendered.frames[i];
    const TrackedPose p = tracker->update({f.data, f.cols, f.rows, 3, static_cast<std::ptrdiff_t>(f.step)},
                                         static_cast<double>(i) / truth.fps);
    if (p.state == TrackingState::Lost) continue;
    const double cm = 100 * glm::length(p.position() - glm::dvec3(truth.cameraToWorld[i][3]));
    const double deg = rotationErrorDeg(p.cameraToWorld, truth.cameraToWorld[i]);
    worstCm = std::max(worstCm, cm), worstDeg = std::max(worstDeg, deg);
    drawnNear += i >= 24 && i <= 26 && cm < 2;
  }
  std::printf("reentry/54: worst drawn %.2f cm, %.2f deg; frames 24-26 drawn within 2 cm: %d of 3\n", worstCm, worstDeg,
              drawnNear);
  EXPECT_LT(worstCm, 5.0);
  EXPECT_LT(worstDeg, 2.0);
  EXPECT_GE(drawnNear, 2);
}

}  // namespace
