// The stress sequences' generator and harness (tests/support/tracking/stress_scenarios.hpp,
// stress_run.hpp): what each class promises, exposures averaged from sub-frames, and the
// worst-case summary. Not the tracker's accuracy on them (that is an accuracy test's).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/scenario_run.hpp"
#include "tracking/stress_run.hpp"
#include "tracking/stress_scenarios.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace {

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

const SequenceRenderer& standard() {
  static const SequenceRenderer renderer = standardRenderer();
  return renderer;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

// Mean squared Sobel gradient of the grey picture inside `box`.
double gradientEnergy(const cv::Mat& rgb, const cv::Rect& box) {
  cv::Mat grey, gx, gy;
  cv::cvtColor(rgb(box), grey, cv::COLOR_RGB2GRAY);
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  return cv::mean(gx.mul(gx) + gy.mul(gy))[0];
}

glm::dmat4 lookingDown(double height, double rollDeg = 0) {
  const double a = rollDeg * 3.14159265358979323846 / 180;
  // Image right along +X rotated by the roll, image down along +Z rotated likewise.
  return lookAtCameraToWorld({0, height, 0}, glm::dvec3(0), {std::sin(a), 0, -std::cos(a)});
}

// An exposure's effects without noise, so that renders compare exactly.
FrameEffects quiet() { return FrameEffects{}; }

TEST(StressSequence, SameSeedSameFramesOtherSeedOtherFrames) {
  cv::setNumThreads(1);
  for (StressClass kind : kStressClasses) {
    const std::string name(stressClassName(kind));
    const StressSequence a = stressSequence(standard(), kind, 7, 30);
    const StressSequence b = stressSequence(standard(), kind, 7, 30);
    const StressSequence c = stressSequence(standard(), kind, 8, 30);
    ASSERT_EQ(a.frames.size(), 30u) << name;
    ASSERT_EQ(a.scenario.cameraToWorld.size(), 30u) << name;
    EXPECT_EQ(a.scenario.name, name + "/7");
    EXPECT_EQ(std::memcmp(a.scenario.cameraToWorld.data(), b.scenario.cameraToWorld.data(), 30 * sizeof(glm::dmat4)), 0)
        << name;
    EXPECT_EQ(a.scenario.visibleFraction, b.scenario.visibleFraction) << name;
    double apart = 0;
    for (std::size_t i = 0; i < 30; ++i) {
      EXPECT_EQ(a.frames[i].subFrames.size(), b.frames[i].subFrames.size()) << name << " frame " << i;
      apart = std::max(apart, glm::length(glm::dvec3(a.scenario.cameraToWorld[i][3] - c.scenario.cameraToWorld[i][3])));
    }
    EXPECT_GT(apart, 0.05) << name << ": another seed, another path";
    // The frame with the most sub-frames (the fastest motion, or hands), rendered twice.
    std::size_t busiest = 0;
    for (std::size_t i = 0; i < 30; ++i)
      if (a.frames[i].subFrames.size() > a.frames[busiest].subFrames.size()) busiest = i;
    cv::Mat fa, fb, fc;
    renderStressFrame(standard(), a, static_cast<int>(busiest), fa);
    renderStressFrame(standard(), b, static_cast<int>(busiest), fb);
    renderStressFrame(standard(), c, static_cast<int>(busiest), fc);
    EXPECT_TRUE(sameBytes(fa, fb)) << name;
    EXPECT_GT(cv::norm(fa, fc, cv::NORM_L1), 640.0 * 480 * 3 * 5) << name;
  }
  // Rendered by two threads, the frames are the same as one by one.
  StressSequence s = stressSequence(standard(), StressClass::Hands, 3, 30);
  s.frames.resize(4);
  s.scenario.cameraToWorld.resize(4);
  s.scenario.effects.resize(4);
  s.scenario.visibleFraction.resize(4);
  const RenderedScenario threaded = renderStress(standard(), s, 2);
  ASSERT_EQ(threaded.frames.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    cv::Mat one;
    renderStressFrame(standard(), s, i, one);
    EXPECT_TRUE(sameBytes(one, threaded.frames[static_cast<std::size_t>(i)])) << "frame " << i;
  }
}

// Four or eight sub-frames of a still camera sample every pixel's 2x2 positions as render()
// does: the same picture but for rounding. Fewer than four would miss positions.
TEST(StressRender, StillExposureIsTheSharpRenderWithinRounding) {
  cv::setNumThreads(1);
  const glm::dmat4 pose = lookAtCameraToWorld({0.25, 0.5, 0.45}, {0.02, 0, -0.01}, {0, 1, 0});
  const HandPicture hand = handPicture(5);
  Occluder o;
  o.texture = premultipliedTexture(hand.hand);
  o.centre = {0.05, 0.12, 0.02};
  o.axisU = {0.001, 0, 0};
  o.axisV = {0, 0, 0.001};
  for (const bool withHand : {false, true}) {
    const std::vector<Occluder> hands = withHand ? std::vector<Occluder>{o} : std::vector<Occluder>{};
    cv::Mat sharp;
    standard().renderExposure({SubFrame{pose, hands}}, quiet(), sharp);
    if (!withHand) {
      cv::Mat plain;
      standard().render(pose, quiet(), plain);
      EXPECT_TRUE(sameBytes(sharp, plain)) << "one sub-frame is render()";
    }
    for (const std::size_t n : {4u, 8u}) {
      cv::Mat averaged, diff;
      standard().renderExposure(std::vector<SubFrame>(n, SubFrame{pose, hands}), quiet(), averaged);
      cv::absdiff(sharp, averaged, diff);
      double worst = 0;
      cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
      EXPECT_LE(worst, 1.0) << n << " sub-frames, hand " << withHand;
    }
    // Two sub-frames see two of the four positions: not the same picture.
    cv::Mat two, diff;
    standard().renderExposure(std::vector<SubFrame>(2, SubFrame{pose, hands}), quiet(), two);
    cv::absdiff(sharp, two, diff);
    double worst = 0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
    EXPECT_GT(worst, 4.0) << "hand " << withHand;
  }
  // The hand shows, with parallax: 12 cm above the floor it hides floor and target.
  cv::Mat without, with;
  standard().render(pose, quiet(), without);
  standard().renderExposure({SubFrame{pose, {o}}}, quiet(), with);
  cv::Mat diff, grey;
  cv::absdiff(without, with, diff);
  cv::cvtColor(diff, grey, cv::COLOR_RGB2GRAY);
  EXPECT_GT(cv::countNonZero(grey > 30), 3000);
}

// A roll about the optical axis during the exposure: a pixel r px from the centre moves r times
// the angle, so the edges lose their detail and the centre keeps it.
TEST(StressRender, RollSmearsTheEdgesMoreThanTheCentre) {
  cv::setNumThreads(1);
  std::vector<SubFrame> roll;
  for (int k = 0; k < 24; ++k) roll.push_back({lookingDown(0.45, -2 + 4.0 * (k + 0.5) / 24), {}});
  cv::Mat sharp, smeared;
  standard().render(lookingDown(0.45), quiet(), sharp);
  standard().renderExposure(roll, quiet(), smeared);
  const cv::Rect centre(320 - 40, 240 - 40, 80, 80);
  const cv::Rect corners[4] = {{0, 0, 80, 80}, {560, 0, 80, 80}, {0, 400, 80, 80}, {560, 400, 80, 80}};
  const double kept = gradientEnergy(smeared, centre) / gradientEnergy(sharp, centre);
  EXPECT_GT(kept, 0.6) << "the centre moves under 3 px";
  for (const cv::Rect& c : corners) {
    const double cornerKept = gradientEnergy(smeared, c) / gradientEnergy(sharp, c);
    EXPECT_LT(cornerKept, 0.35) << "a corner moves 28 px";
    EXPECT_LT(cornerKept, 0.5 * kept);
  }
}

TEST(StressSequence, ReentryComesBackPartlyAtTheNamedEdge) {
  const CameraModel& camera = standard().camera();
  for (const ImageEdge edge : {ImageEdge::Left, ImageEdge::Right, ImageEdge::Top, ImageEdge::Bottom})
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const std::string what = std::string(imageEdgeName(edge)) + " seed " + std::to_string(seed);
      const StressSequence s = reentrySequence(standard(), seed, 60, edge);
      EXPECT_EQ(s.edge, edge);
      const std::vector<double>& v = s.scenario.visibleFraction;
      EXPECT_GT(v[0], 0.9) << what << ": starts with the target in view";
      std::size_t back = 0;
      for (std::size_t i = 1; i < v.size() && back == 0; ++i)
        if (v[i] > 0 && v[i - 1] == 0) back = i;
      ASSERT_GT(back, 0u) << what << ": the target leaves and comes back";
      EXPECT_LT(v[back], 0.9) << what << ": partly in view as it comes back";
      // It shows only partly for a while (the hesitation) before the rest of it comes in.
      int partial = 0;
      for (std::size_t i = back; i < v.size() && v[i] > 0 && v[i] < 0.6; ++i) ++partial;
      EXPECT_GE(partial, 3) << what;
      // Through the named edge: the target's outline crosses it, and not the opposite one.
      double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
      const double hw = 0.5 * standard().targetWidth(), hd = 0.5 * standard().targetDepth();
      for (const glm::dvec3 corner : {glm::dvec3(-hw, 0, -hd), glm::dvec3(hw, 0, -hd), glm::dvec3(hw, 0, hd), glm::dvec3(-hw, 0, hd)}) {
        const glm::dvec2 p = projectWorldPoint(camera, s.scenario.cameraToWorld[back], corner);
        minX = std::min(minX, p.x), maxX = std::max(maxX, p.x), minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
      }
      switch (edge) {
        case ImageEdge::Left: EXPECT_TRUE(minX < 0 && maxX < camera.width) << what << " x " << minX << ".." << maxX; break;
        case ImageEdge::Right: EXPECT_TRUE(maxX > camera.width && minX > 0) << what << " x " << minX << ".." << maxX; break;
        case ImageEdge::Top: EXPECT_TRUE(minY < 0 && maxY < camera.height) << what << " y " << minY << ".." << maxY; break;
        case ImageEdge::Bottom: EXPECT_TRUE(maxY > camera.height && minY > 0) << what << " y " << minY << ".." << maxY; break;
      }
    }
  // The seed picks the edge: every one of them among four consecutive blocks of seeds.
  EXPECT_EQ(reentrySequence(standard(), 1, 30).edge, ImageEdge::Left);
  EXPECT_EQ(reentrySequence(standard(), 6, 30).edge, ImageEdge::Right);
  EXPECT_EQ(reentrySequence(standard(), 10, 30).edge, ImageEdge::Top);
  EXPECT_EQ(reentrySequence(standard(), 14, 30).edge, ImageEdge::Bottom);
}

// The angular speed of R(t) between instants 1 ms apart, deg/s, and the change of the angular
// velocity (in the camera's frame) between them, deg/s^2.
void speedsOf(const StressSequence& s, double& peakSpeed, double& peakAcceleration) {
  constexpr double dt = 0.001;
  const double end = static_cast<double>(s.frames.size()) / s.scenario.fps;
  peakSpeed = peakAcceleration = 0;
  glm::dvec3 previous(0.0);
  for (double t = -s.exposure; t < end + s.exposure; t += dt) {
    const glm::dmat3 d = glm::transpose(glm::dmat3(s.cameraAt(t))) * glm::dmat3(s.cameraAt(t + dt));
    // The rotation vector of a small rotation from its skew part.
    const glm::dvec3 w = glm::dvec3(d[1][2] - d[2][1], d[2][0] - d[0][2], d[0][1] - d[1][0]) * (0.5 / dt);
    const double speed = rotationErrorDeg(glm::dmat4(d), glm::dmat4(1.0)) / dt;
    peakSpeed = std::max(peakSpeed, speed);
    if (t > -s.exposure) peakAcceleration = std::max(peakAcceleration, glm::degrees(glm::length(w - previous)) / dt);
    previous = w;
  }
}

TEST(StressSequence, CameraTurnsAtUpTo180DegreesPerSecondWithBoundedAcceleration) {
  double fastestPan = 0;
  for (StressClass kind : kStressClasses)
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const StressSequence s = stressSequence(standard(), kind, seed, defaultStressFrames(kind));
      const std::string what = s.scenario.name;
      double speed = 0, acceleration = 0;
      speedsOf(s, speed, acceleration);
      EXPECT_LE(speed, 180.0) << what;
      // Turns accelerate at up to 1500 deg/s^2 (pan, reentry) or 400; the tremor adds its own.
      EXPECT_LT(acceleration, kind == StressClass::Pan || kind == StressClass::Reentry ? 2500.0 : 1400.0) << what;
      if (kind == StressClass::Pan || kind == StressClass::Reentry) fastestPan = std::max(fastestPan, speed);
      if (kind == StressClass::Hands || kind == StressClass::Photometric) {
        EXPECT_LE(speed, 80.0) << what << ": moderate motion";
      }
      // The frames' facts agree with the path.
      for (const StressFrame& f : s.frames) {
        EXPECT_LE(f.angularSpeedDeg, speed + 0.5) << what;  // the 1 ms grid may miss the peak a little
        EXPECT_GE(static_cast<int>(f.subFrames.size()), 4) << what;
        EXPECT_LE(static_cast<int>(f.subFrames.size()), 16) << what;
        EXPECT_GE(f.exposure, 1.0 / 60 - 1e-12);
        EXPECT_LE(f.exposure, 1.0 / 30 + 1e-12);
      }
    }
  EXPECT_GT(fastestPan, 140.0) << "pans reach speeds near 180 deg/s";
}

TEST(StressSequence, PansLoseTheTargetAndFindItAgainWithLongerSmearsWhenFaster) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const StressSequence s = panSequence(standard(), seed, 60);
    const std::vector<double>& v = s.scenario.visibleFraction;
    const auto gone = std::find(v.begin(), v.end(), 0.0);
    ASSERT_NE(gone, v.end()) << s.scenario.name << ": the target leaves the view";
    EXPECT_GT(*std::max_element(gone, v.end()), 0.5) << s.scenario.name << ": and comes back";
    // The fastest frame has more sub-frames and a longer smear than the slowest.
    const auto [slow, fast] = std::minmax_element(s.frames.begin(), s.frames.end(), [](const StressFrame& a, const StressFrame& b) {
      return a.imageMotionPx < b.imageMotionPx;
    });
    EXPECT_GT(fast->imageMotionPx, 25.0) << s.scenario.name;
    EXPECT_GT(fast->subFrames.size(), slow->subFrames.size()) << s.scenario.name;
    EXPECT_EQ(slow->subFrames.size(), 4u) << s.scenario.name;
  }
}

TEST(StressSequence, HandsCoverPartOfTheTargetInSomeFrames) {
  cv::setNumThreads(1);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const StressSequence s = handsSequence(standard(), seed, defaultStressFrames(StressClass::Hands));
    const std::string what = s.scenario.name;
    std::size_t most = 0;
    for (std::size_t i = 0; i < s.frames.size(); ++i)
      if (s.frames[i].handsCover > s.frames[most].handsCover) most = i;
    EXPECT_GT(s.frames[most].handsCover, 0.1) << what;
    EXPECT_LT(s.frames.front().handsCover, s.frames[most].handsCover) << what << ": the hands come";
    // Between the camera and the floor, 5..25 cm up (the palm's height, where the hand is).
    for (const Occluder& o : s.frames[most].subFrames.front().occluders) {
      EXPECT_GT(o.centre.y, 0.03) << what;
      EXPECT_LT(o.centre.y, 0.40) << what;
    }
    // The render shows them: the frame with and without the hands differs over the target.
    StressSequence bare = s;
    for (SubFrame& sub : bare.frames[most].subFrames) sub.occluders.clear();
    cv::Mat with, without, diff, grey;
    renderStressFrame(standard(), s, static_cast<int>(most), with);
    renderStressFrame(standard(), bare, static_cast<int>(most), without);
    cv::absdiff(with, without, diff);
    cv::cvtColor(diff, grey, cv::COLOR_RGB2GRAY);
    EXPECT_GT(cv::countNonZero(grey > 25), 0.03 * 640 * 480) << what;
    // Skin: red over green over blue where they show.
    const cv::Scalar skin = cv::mean(with, grey > 25);
    EXPECT_GT(skin[0], skin[1]) << what;
    EXPECT_GT(skin[1], skin[2]) << what;
  }
}

TEST(StressSequence, PhotometricStepsAndDefocusComeAndGo) {
  cv::setNumThreads(1);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const StressSequence s = photometricSequence(standard(), seed, defaultStressFrames(StressClass::Photometric));
    const std::string what = s.scenario.name;
    const std::vector<FrameEffects>& fx = s.scenario.effects;
    double biggestStep = 0, maxDefocus = 0;
    bool balanceChanges = false, sharpAfterDefocus = false, sharpBeforeDefocus = false;
    for (std::size_t i = 0; i < fx.size(); ++i) {
      EXPECT_LE(std::abs(fx[i].gainEv), 2.0) << what;
      EXPECT_LE(fx[i].defocusPx, 4.0) << what;
      maxDefocus = std::max(maxDefocus, fx[i].defocusPx);
      if (i == 0) continue;
      const double step = std::abs(fx[i].gainEv - fx[i - 1].gainEv);
      if (step > 0) {
        EXPECT_GE(step, 0.5) << what << ": auto-exposure steps";
        EXPECT_LE(step, 1.5) << what;
      }
      biggestStep = std::max(biggestStep, step);
      balanceChanges = balanceChanges || fx[i].channelGain != fx[i - 1].channelGain;
      sharpAfterDefocus = sharpAfterDefocus || (fx[i].defocusPx == 0 && fx[i - 1].defocusPx > 0);
      sharpBeforeDefocus = sharpBeforeDefocus || (fx[i].defocusPx > 0 && fx[i - 1].defocusPx == 0);
    }
    EXPECT_GE(biggestStep, 0.5) << what;
    EXPECT_TRUE(balanceChanges) << what;
    EXPECT_GE(maxDefocus, 1.0) << what;
    EXPECT_TRUE(sharpAfterDefocus || sharpBeforeDefocus) << what << ": defocus comes or goes";
  }
  // The effects as rendered: defocus takes detail away, channel gains tint.
  const glm::dmat4 pose = lookingDown(0.5);
  FrameEffects blurred = quiet(), tinted = quiet();
  blurred.defocusPx = 3;
  tinted.channelGain = {1.3, 1, 0.7};
  cv::Mat sharp, defocused, warm;
  standard().render(pose, quiet(), sharp);
  standard().render(pose, blurred, defocused);
  standard().render(pose, tinted, warm);
  const cv::Rect all(0, 0, 640, 480);
  EXPECT_LT(gradientEnergy(defocused, all), 0.5 * gradientEnergy(sharp, all));
  const cv::Scalar a = cv::mean(sharp), b = cv::mean(warm);
  EXPECT_GT(b[0], 1.15 * a[0]);
  EXPECT_NEAR(b[1], a[1], 0.5);
  EXPECT_LT(b[2], 0.8 * a[2]);
}

// The summary keeps the worst drawn errors with where they happened; LOST frames are not drawn.
TEST(StressRun, ReportKeepsTheWorstDrawnPosesWithSeedAndFrame) {
  Scenario truth;
  for (int i = 0; i < 5; ++i) {
    glm::dmat4 m = lookingDown(0.6);
    m[3].x = 0.01 * i;
    truth.cameraToWorld.push_back(m);
    truth.visibleFraction.push_back(i == 4 ? 0.0 : 1.0);
    truth.hiddenFraction.push_back(i == 1 ? 0.6 : 0.0);  // a hand over 60 % of it in frame 1
  }
  auto pose = [&](int i, TrackingState state, glm::dvec3 offset, double rollDeg = 0) {
    TrackedPose p;
    p.state = state;
    const double a = rollDeg * 3.14159265358979323846 / 180;
    const glm::dmat3 roll(glm::dvec3(std::cos(a), std::sin(a), 0), glm::dvec3(-std::sin(a), std::cos(a), 0), glm::dvec3(0, 0, 1));
    p.cameraToWorld = glm::dmat4(glm::dmat3(truth.cameraToWorld[static_cast<std::size_t>(i)]) * roll);
    p.cameraToWorld[3] = truth.cameraToWorld[static_cast<std::size_t>(i)][3] + glm::dvec4(offset, 0);
    return p;
  };
  const std::vector<TrackedPose> first = {pose(0, TrackingState::Tracking, {}),
                                          pose(1, TrackingState::Limited, {0.03, 0, 0}),
                                          pose(2, TrackingState::Lost, {1, 0, 0}),
                                          pose(3, TrackingState::Tracking, {}, 3),
                                          pose(4, TrackingState::Tracking, {0, 0.01, 0})};
  const std::vector<TrackedPose> second = {pose(0, TrackingState::Tracking, {}), pose(1, TrackingState::Tracking, {}),
                                           pose(2, TrackingState::Limited, {0, 0, 0.1}), pose(3, TrackingState::Lost, {}),
                                           pose(4, TrackingState::Lost, {})};
  StressReport report;
  addStressRun(report, StressClass::Reentry, 9, truth, second, std::vector<double>(5, 2.0));
  addStressRun(report, StressClass::Pan, 7, truth, first, std::vector<double>(5, 1.0));
  finishStressReport(report);
  ASSERT_EQ(report.classes.size(), 2u);
  EXPECT_EQ(report.classes[0].kind, StressClass::Pan) << "kept in the classes' order";
  const StressClassReport& pan = report.classes[0];
  EXPECT_EQ(pan.sequences, 1);
  EXPECT_EQ(pan.frames, 5);
  EXPECT_EQ(pan.visibleFrames, 4);
  EXPECT_EQ(pan.drawnFrames, 4);
  EXPECT_EQ(pan.trackingFrames, 3);
  EXPECT_EQ(pan.within2cm, 2);  // frames 0 and 3 (frame 4 is out of view)
  EXPECT_EQ(pan.halfShownFrames, 3);  // frames 0, 2 and 3 (frame 1 40 % shown, frame 4 none)
  EXPECT_EQ(pan.halfShownWithin2cm, 2);  // frames 0 and 3 (frame 2 LOST)
  EXPECT_EQ(pan.falsePoses, 1);  // frame 3, 3 deg off
  EXPECT_NEAR(pan.worstPosition.value, 0.03, 1e-12);
  EXPECT_EQ(pan.worstPosition.seed, 7u);
  EXPECT_EQ(pan.worstPosition.frame, 1);
  EXPECT_NEAR(pan.worstRotation.value, 3.0, 1e-9);
  EXPECT_EQ(pan.worstRotation.frame, 3);
  EXPECT_NEAR(pan.trackingRmsM, std::sqrt(0.01 * 0.01 / 3), 1e-12);
  EXPECT_DOUBLE_EQ(pan.msMedian, 1.0);
  const StressClassReport& reentry = report.classes[1];
  EXPECT_NEAR(reentry.worstPosition.value, 0.1, 1e-12);
  EXPECT_EQ(reentry.worstPosition.seed, 9u);
  EXPECT_EQ(reentry.worstPosition.frame, 2);
  EXPECT_EQ(reentry.falsePoses, 1);
  // Pooled: every frame of both classes, the worst of either (naming its class in the table).
  const StressClassReport& all = report.all;
  EXPECT_EQ(all.sequences, 2);
  EXPECT_EQ(all.frames, 10);
  EXPECT_EQ(all.visibleFrames, pan.visibleFrames + reentry.visibleFrames);
  EXPECT_EQ(all.drawnFrames, pan.drawnFrames + reentry.drawnFrames);
  EXPECT_EQ(all.within2cm, pan.within2cm + reentry.within2cm);
  EXPECT_EQ(all.halfShownWithin2cm, pan.halfShownWithin2cm + reentry.halfShownWithin2cm);
  EXPECT_EQ(all.falsePoses, 2);
  EXPECT_NEAR(all.worstPosition.value, 0.1, 1e-12);
  EXPECT_EQ(all.worstPosition.seed, 9u);
  EXPECT_NEAR(all.worstRotation.value, 3.0, 1e-9);
  EXPECT_EQ(all.worstRotation.seed, 7u);
  EXPECT_EQ(all.halfShownFrames, pan.halfShownFrames + reentry.halfShownFrames);
  EXPECT_EQ(all.trackingFrames, pan.trackingFrames + reentry.trackingFrames);
  EXPECT_EQ(all.ms.size(), 10u);
  EXPECT_DOUBLE_EQ(all.msMedian, 1.5);  // five frames at 1 ms and five at 2 ms: both classes pooled
  EXPECT_DOUBLE_EQ(all.msP95, 2.0);
  EXPECT_EQ(report.allWorstPositionClass, "reentry");
  EXPECT_EQ(report.allWorstRotationClass, "pan");
  EXPECT_NEAR(all.trackingRmsM,
              std::sqrt((pan.sumSqTracking + reentry.sumSqTracking) / (pan.trackingFrames + reentry.trackingFrames)), 1e-12);
  const std::string table = stressTable(report);
  EXPECT_NE(table.find("| pan | 1 | 5 | 4 | 4 | 50.0 % | 66.7 % of 3 | 3.00 (seed 7, frame 1) | 3.00 (seed 7, frame 3) | 1 |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("| **all** | 2 | 10 | "), std::string::npos) << table;
  EXPECT_NE(table.find("reentry 10.00 (seed 9, frame 2) | pan 3.00 (seed 7, frame 3) | 2 |"), std::string::npos) << table;
  // Finishing again gives the same pooled row; classes with nothing drawn name no class.
  finishStressReport(report);
  EXPECT_EQ(report.all.frames, 10);
  EXPECT_EQ(report.all.within2cm, pan.within2cm + reentry.within2cm);
  StressReport blind;
  const std::vector<TrackedPose> lost(5, pose(0, TrackingState::Lost, {}));
  addStressRun(blind, StressClass::Pan, 1, truth, lost, std::vector<double>(5, 1.0));
  addStressRun(blind, StressClass::Hands, 2, truth, lost, std::vector<double>(5, 1.0));
  finishStressReport(blind);
  EXPECT_EQ(blind.all.drawnFrames, 0);
  EXPECT_EQ(blind.all.worstPosition.frame, -1);
  EXPECT_TRUE(blind.allWorstPositionClass.empty());
  EXPECT_NE(stressTable(blind).find("| **all** | 2 | 10 | 8 | 0 | 0.0 % | 0.0 % of 6 | - | - | 0 |"), std::string::npos)
      << stressTable(blind);
  EXPECT_NE(table.find("10.00 (seed 9, frame 2)"), std::string::npos) << table;
  EXPECT_THROW(addStressRun(report, StressClass::Pan, 1, truth, {first[0]}, {1.0}), std::invalid_argument);

  // The plans: every class's seeds, or the seeds split over the classes.
  const std::vector<StressCase> split = stressCases(20, true);
  ASSERT_EQ(split.size(), 20u);
  for (StressClass k : kStressClasses)
    EXPECT_EQ(std::count_if(split.begin(), split.end(), [k](const StressCase& c) { return c.kind == k; }), 5) << stressClassName(k);
  EXPECT_EQ(split[5].seed, 6u);
  EXPECT_EQ(split[5].kind, StressClass::Reentry);
  EXPECT_EQ(stressCases(3, false).size(), 12u);
}

// The harness end to end on one short sequence: a row whose worst case is a frame of it.
TEST(StressRun, RunsTheTrackerOverASequence) {
  cv::setNumThreads(1);
  const StressReport report = runStressSeeds(standard(), {{StressClass::Photometric, 2, 30}}, MarkerlessSettings{});
  ASSERT_EQ(report.classes.size(), 1u);
  const StressClassReport& c = report.classes[0];
  EXPECT_EQ(c.sequences, 1);
  EXPECT_EQ(c.frames, 30);
  EXPECT_EQ(report.renderedFrames, 30);
  EXPECT_GT(report.renderMsMean, 0);
  EXPECT_EQ(c.ms.size(), 30u);
  if (c.drawnFrames > 0) {
    EXPECT_EQ(c.worstPosition.seed, 2u);
    EXPECT_GE(c.worstPosition.frame, 0);
    EXPECT_LT(c.worstPosition.frame, 30);
  }
  std::printf("%s", stressTable(report).c_str());
}

}  // namespace
