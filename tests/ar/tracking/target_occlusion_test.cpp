// The occlusion mask over the target (target_occlusion.hpp; docs/tracking.md, "Occlusion over
// the target") against the synthetic sequences' truth of which target pixels are hidden
// (SequenceRenderer::targetCoverage): the standard occluder, hands reaching in, and nothing over
// the target under lighting changes, blur and noise; an empty mask with the target out of view or
// no pose; the tracker's occlusionMask(), computed only when asked; AprilTag has none.
//
// The bounds are the figures measured here (printed by each test, and in docs/tracking.md) with a
// margin: IoU and the hidden share found about 0.05 under them, the false shares about 1.5 times
// over them (the regression bounds of docs/testing.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "tracking/occlusion_metrics.hpp"
#include "tracking/scenario_run.hpp"
#include "tracking/stress_scenarios.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;
using namespace marionette::ar::synthetic;

ImageView view(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)};
}

const SequenceRenderer& standard() {
  static const SequenceRenderer renderer = standardRenderer();
  return renderer;
}

void print(const char* what, const MaskSummary& m) {
  std::printf("[ occlusion ] %s: %d frames (%d with hidden pixels): IoU mean %.3f worst %.3f; false hidden mean %.2f %% "
              "worst %.2f %%; missed mean %.2f %% worst %.2f %%; pooled %.3f / %.2f %% / %.2f %%\n",
              what, m.frames, m.hiddenFrames, m.iouMean, m.iouWorst, 100 * m.falseHiddenMean, 100 * m.falseHiddenWorst,
              100 * m.missedHiddenMean, 100 * m.missedHiddenWorst, m.pooledIou, 100 * m.pooledFalseHidden,
              100 * m.pooledMissedHidden);
}

bool allZero(const OcclusionMask& m) {
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      if (m.at(x, y) != 0) return false;
  return true;
}

// The truth output is the renderer's own geometry: its shares agree with the visibility grid's
// (visibleTargetFraction, occludedTargetFraction), and asking for it changes no rendered bit.
TEST(OcclusionTruth, AgreesWithTheRenderersSharesAndChangesNoRender) {
  cv::setNumThreads(2);
  const SequenceRenderer& r = standard();
  // Straight down, so that a share of the target's pixels is a share of its area.
  const glm::dmat4 pose = lookAtCameraToWorld({0.01, 0.7, 0.02}, glm::dvec3(0), {0, 0, -1});
  FrameEffects fx;
  fx.occluderFraction = 0.4, fx.occluderPhase = 0.3;
  cv::Mat before, after, on, hidden;
  r.render(pose, fx, before);
  r.targetCoverage({SubFrame{pose, {}}}, fx, on, hidden);
  r.render(pose, fx, after);
  ASSERT_EQ(before.size(), after.size());
  EXPECT_EQ(std::memcmp(before.data, after.data, before.total() * before.elemSize()), 0);
  // The target's area in pixels: the on-target share summed, against the grid's share times the
  // target's image area (its four corners' quadrilateral: no lens distortion here).
  std::vector<cv::Point2f> corners;
  for (const auto& c : {glm::dvec2(-0.5, -0.5), glm::dvec2(0.5, -0.5), glm::dvec2(0.5, 0.5), glm::dvec2(-0.5, 0.5)}) {
    const glm::dvec2 p = projectWorldPoint(r.camera(), pose, {c.x * r.targetWidth(), 0, c.y * r.targetDepth()});
    corners.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  }
  const double area = cv::contourArea(corners);
  EXPECT_NEAR(cv::sum(on)[0] / area, r.visibleTargetFraction(pose), 0.01);
  // The rectangle covers 40 % of the target's area (less its parallax: it is 3 mm above).
  EXPECT_NEAR(cv::sum(hidden)[0] / cv::sum(on)[0], 0.4, 0.01);
  // A hand: the renderer's own share of the target hidden (alpha over one half, on its grid).
  const HandPicture hand = handPicture(3);
  Occluder o;
  o.texture = premultipliedTexture(hand.hand);
  o.centre = {0.02, 0.08, 0.0};
  o.axisU = {hand.texel, 0, 0};
  o.axisV = {0, 0, hand.texel};
  cv::Mat onHand, hiddenByHand;
  r.targetCoverage({SubFrame{pose, {o}}}, {}, onHand, hiddenByHand);
  const double share = r.occludedTargetFraction(pose, {o});
  EXPECT_GT(share, 0.1);
  EXPECT_NEAR(cv::sum(hiddenByHand)[0] / cv::sum(onHand)[0], share, 0.02);
  // Where the render shows the occluder's colour over the target, the truth says hidden.
  int occluderPixels = 0, agree = 0;
  for (int y = 0; y < before.rows; ++y)
    for (int x = 0; x < before.cols; ++x)
      if (before.at<cv::Vec3b>(y, x) == kOccluderRgb && on.at<float>(y, x) == 1.0f) {
        ++occluderPixels;
        agree += hidden.at<float>(y, x) == 1.0f;
      }
  EXPECT_GT(occluderPixels, 1000);
  EXPECT_EQ(agree, occluderPixels);
}

// The standard occluder (a flat rectangle 3 mm above the target sweeping over 20..60 % of it) at
// the exact poses and at the tracker's, 60 frames.
TEST(TargetOcclusion, FindsTheStandardOccluder) {
  cv::setNumThreads(2);
  const OcclusionSequence s = standardOcclusionSequence(standard(), "occluder", 60, 4);
  cv::setNumThreads(1);
  const MaskSummary exact = maskAtExactPoses(s, standard().camera(), {});
  int drawn = 0;
  const MaskSummary tracked = maskAtTrackerPoses(s, standard().camera(), {}, drawn);
  print("occluder, exact poses", exact);
  print("occluder, tracker's poses", tracked);
  // Measured (exact / tracker's poses): IoU 0.942 / 0.941 mean, 0.913 / 0.893 worst; false hidden
  // 1.7 / 1.9 % mean, 4.1 / 4.4 % worst; missed 3.7 / 3.7 % mean, 7.4 / 7.5 % worst.
  for (const MaskSummary* m : {&exact, &tracked}) {
    EXPECT_GE(m->hiddenFrames, 55);
    EXPECT_GE(m->iouMean, 0.89);
    EXPECT_GE(m->iouWorst, 0.81);
    EXPECT_LE(m->falseHiddenMean, 0.028);
    EXPECT_LE(m->falseHiddenWorst, 0.085);
    EXPECT_LE(m->missedHiddenMean, 0.056);
    EXPECT_LE(m->missedHiddenWorst, 0.113);
  }
  EXPECT_GE(drawn, 57);
}

// Nothing over the target: under a gain of -1 and +1 EV, a white balance, a light falling off
// across the view, a 15 px motion blur, a 3 px defocus and noise, (almost) no pixel is hidden.
TEST(TargetOcclusion, NothingIsHiddenUnderLightingChangeBlurAndNoise) {
  cv::setNumThreads(2);
  const SequenceRenderer& r = standard();
  auto occlusion = standardTargetOcclusion(r.camera(), {});
  struct Case {
    const char* name;
    FrameEffects fx;
    bool gradient = false;  // the light from 50 % to 150 % across the view, diagonally
  };
  std::vector<Case> cases(7);
  cases[0].name = "sharp";
  cases[1].name = "-1 EV", cases[1].fx.gainEv = -1;
  cases[2].name = "+1 EV", cases[2].fx.gainEv = 1;
  cases[3].name = "white balance", cases[3].fx.channelGain = {1.25, 1.0, 0.75};
  cases[4].name = "light gradient", cases[4].gradient = true;
  cases[5].name = "15 px blur", cases[5].fx.motionBlurPx = 15, cases[5].fx.motionBlurAngleDeg = 30;
  cases[6].name = "3 px defocus, noise 4", cases[6].fx.defocusPx = 3, cases[6].fx.noiseSigma = 4;
  double worstAll = 0;
  for (const Case& c : cases) {
    double worst = 0, sum = 0;
    int frames = 0;
    for (int k = 0; k < 6; ++k) {
      const glm::dmat4 pose = orbitPose(60.0 * k, 40 + 4 * k, 0.6 + 0.05 * k, 5.0 * k);
      cv::Mat frame, on, hidden;
      r.render(pose, c.fx, frame);
      if (c.gradient) {
        cv::Mat f;
        frame.convertTo(f, CV_32FC3);
        for (int y = 0; y < f.rows; ++y)
          for (int x = 0; x < f.cols; ++x)
            f.at<cv::Vec3f>(y, x) *= static_cast<float>(0.5 + 1.0 * (x + y) / double(f.cols + f.rows));
        f.convertTo(frame, CV_8UC3);
      }
      r.targetCoverage({SubFrame{pose, {}}}, c.fx, on, hidden);
      ASSERT_TRUE(occlusion->update(view(frame), pose));
      const MaskScore score = scoreMask(occlusion->mask(), maskTruth(on, hidden, occlusion->mask().scale));
      ASSERT_GT(score.truthVisible, 500) << c.name << " view " << k;
      worst = std::max(worst, score.falseHidden);
      sum += score.falseHidden;
      ++frames;
    }
    std::printf("[ occlusion ] nothing over the target, %s: false hidden mean %.2f %% worst %.2f %%\n", c.name,
                100 * sum / frames, 100 * worst);
    EXPECT_LE(sum / frames, 0.015) << c.name;  // measured: 1.0 % at most (+1 EV)
    EXPECT_LE(worst, 0.04) << c.name;          // measured: 2.4 % (+1 EV: a few saturated blocks)
    worstAll = std::max(worstAll, worst);
  }
  std::printf("[ occlusion ] nothing over the target: worst false hidden %.2f %%\n", 100 * worstAll);
}

// Through a lens with barrel distortion (k1 -0.3, k2 0.1): the mask is in the frame's own pixels,
// its rays undistorted, and finds the occluder as well as through a pinhole; the target near the
// image's corner, where the distortion is strongest.
TEST(TargetOcclusion, FindsTheOccluderThroughADistortingLens) {
  cv::setNumThreads(2);
  CameraModel camera = standard().camera();
  camera.distortion = {-0.3, 0.1, 0.0, 0.0, 0.0};
  PlanarScene scene;
  cv::cvtColor(cv::imread(standardTargetImage(), cv::IMREAD_COLOR), scene.target, cv::COLOR_BGR2RGB);
  scene.targetWidth = kStandardTargetWidth;
  const SequenceRenderer lens(scene, camera);
  auto occlusion = standardTargetOcclusion(camera, {});
  auto pinhole = standardTargetOcclusion(standard().camera(), {});
  MaskSummary distorted, straight;
  for (int k = 0; k < 6; ++k) {
    // The target's centre 130..180 px from the image centre, towards a corner.
    const glm::dmat4 pose = lookAtCameraToWorld({-0.16 - 0.01 * k, 0.55, 0.2}, {0.0, 0.0, 0.0}, {0, 0, -1});
    FrameEffects fx;
    fx.occluderFraction = 0.3 + 0.05 * k, fx.occluderPhase = 0.15 * k;
    cv::Mat frame, on, hidden;
    lens.render(pose, fx, frame);
    lens.targetCoverage({SubFrame{pose, {}}}, fx, on, hidden);
    ASSERT_TRUE(occlusion->update(view(frame), pose));
    addFrame(distorted, scoreMask(occlusion->mask(), maskTruth(on, hidden, 4)), k);
    // The same view through the pinhole model, for comparison.
    cv::Mat straightFrame;
    const SequenceRenderer flat(scene, standard().camera());
    flat.render(pose, fx, straightFrame);
    flat.targetCoverage({SubFrame{pose, {}}}, fx, on, hidden);
    ASSERT_TRUE(pinhole->update(view(straightFrame), pose));
    addFrame(straight, scoreMask(pinhole->mask(), maskTruth(on, hidden, 4)), k);
  }
  finishSummary(distorted);
  finishSummary(straight);
  print("occluder through k1 -0.3, k2 0.1", distorted);
  print("the same views through the pinhole", straight);
  EXPECT_EQ(distorted.hiddenFrames, 6);
  EXPECT_GE(distorted.iouMean, 0.90);  // measured 0.954 (0.956 through the pinhole), false hidden 1.45 %
  EXPECT_GE(distorted.iouMean, straight.iouMean - 0.04);
  EXPECT_LE(distorted.falseHiddenMean, 0.02);
}

// A target filling most of the view (from 0.32..0.42 m) is worked at twice the scale
// (maxTargetPixels) and upsampled: the mask keeps its size and about the accuracy of working at the
// full scale.
TEST(TargetOcclusion, ACloseTargetIsWorkedAtTwiceTheScale) {
  cv::setNumThreads(2);
  const SequenceRenderer& r = standard();
  auto occlusion = standardTargetOcclusion(r.camera(), {});
  auto full = standardTargetOcclusion(r.camera(), OcclusionSettings{.maxTargetPixels = 0});
  MaskSummary coarse, fine;
  for (int k = 0; k < 6; ++k) {
    const glm::dmat4 pose = orbitPose(40.0 * k, 55 + 3 * k, 0.32 + 0.02 * k);
    FrameEffects fx;
    fx.occluderFraction = 0.25 + 0.05 * k, fx.occluderPhase = 0.2 * k;
    cv::Mat frame, on, hidden;
    r.render(pose, fx, frame);
    r.targetCoverage({SubFrame{pose, {}}}, fx, on, hidden);
    const MaskTruth truth = maskTruth(on, hidden, 4);
    ASSERT_TRUE(occlusion->update(view(frame), pose));
    EXPECT_EQ(occlusion->mask().scale, 4);
    EXPECT_EQ(occlusion->mask().computedScale, 8) << "view " << k;
    EXPECT_EQ(occlusion->mask().width, 160);
    EXPECT_GT(occlusion->mask().targetPixels, 6000) << "view " << k;  // in the mask's pixels
    addFrame(coarse, scoreMask(occlusion->mask(), truth), k);
    ASSERT_TRUE(full->update(view(frame), pose));
    EXPECT_EQ(full->mask().computedScale, 4);
    addFrame(fine, scoreMask(full->mask(), truth), k);
  }
  finishSummary(coarse);
  finishSummary(fine);
  print("occluder from 0.32..0.42 m, worked at scale 8", coarse);
  print("the same at scale 4", fine);
  EXPECT_GE(coarse.iouMean, 0.92);
  EXPECT_GE(coarse.iouMean, fine.iouMean - 0.03);
  EXPECT_LE(coarse.falseHiddenMean, 0.02);
}

TEST(TargetOcclusion, EmptyWhenTheTargetIsOutOfViewOrThereIsNoPose) {
  cv::setNumThreads(1);
  const SequenceRenderer& r = standard();
  auto occlusion = standardTargetOcclusion(r.camera(), {});
  cv::Mat frame;
  FrameEffects fx;
  fx.occluderFraction = 0.5;
  // First a mask with hidden pixels, so that emptying it is something.
  const glm::dmat4 onTarget = orbitPose(0, 60, 0.6);
  r.render(onTarget, fx, frame);
  ASSERT_TRUE(occlusion->update(view(frame), onTarget));
  EXPECT_TRUE(occlusion->mask().targetInView);
  EXPECT_GT(occlusion->mask().hiddenShare, 0.3);
  // Looking away over the floor, then up at the sky (the plane behind the camera).
  for (const glm::dmat4& away : {lookAtCameraToWorld({0, 0.5, 0.6}, {0, 0, 2.0}, {0, 1, 0}),
                                 lookAtCameraToWorld({0, 0.5, 0}, {0, 2.0, 0.5}, {0, 0, -1})}) {
    r.render(away, fx, frame);
    EXPECT_TRUE(occlusion->update(view(frame), away));
    EXPECT_FALSE(occlusion->mask().targetInView);
    EXPECT_EQ(occlusion->mask().targetPixels, 0.0);
    EXPECT_TRUE(allZero(occlusion->mask()));
  }
  // Bad input: an empty mask and false.
  r.render(onTarget, fx, frame);
  ASSERT_TRUE(occlusion->update(view(frame), onTarget));
  cv::Mat small;
  cv::resize(frame, small, cv::Size(320, 240));
  EXPECT_FALSE(occlusion->update(view(small), onTarget));
  EXPECT_TRUE(allZero(occlusion->mask()));
  ASSERT_TRUE(occlusion->update(view(frame), onTarget));
  glm::dmat4 nan = onTarget;
  nan[3][0] = std::nan("");
  EXPECT_FALSE(occlusion->update(view(frame), nan));
  EXPECT_TRUE(allZero(occlusion->mask()));
  EXPECT_FALSE(occlusion->update(ImageView{}, onTarget));
  ASSERT_TRUE(occlusion->update(view(frame), onTarget));
  occlusion->clear();
  EXPECT_TRUE(allZero(occlusion->mask()));
  EXPECT_FALSE(occlusion->mask().targetInView);

  // The tracker: nothing before a pose; once LOST (the target gone), an empty mask.
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(r.camera(), standardTargetImage(), kStandardTargetWidth, {}, d);
  ASSERT_TRUE(tracker) << d.format();
  EXPECT_TRUE(tracker->hasOcclusionMask());
  const OcclusionMask* none = tracker->occlusionMask();
  ASSERT_NE(none, nullptr);
  EXPECT_FALSE(none->targetInView);
  EXPECT_EQ(none->width, 160);
  EXPECT_EQ(none->height, 120);
  bool sawHidden = false;
  for (int i = 0; i < 8; ++i) {
    const glm::dmat4 pose = orbitPose(0.5 * i, 60, 0.6);
    r.render(pose, fx, frame);
    const TrackedPose p = tracker->update(view(frame), i / 30.0);
    const OcclusionMask* m = tracker->occlusionMask();
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->targetInView, p.state != TrackingState::Lost) << "frame " << i;
    sawHidden = sawHidden || m->hiddenShare > 0.3;
  }
  EXPECT_TRUE(sawHidden);
  const glm::dmat4 away = lookAtCameraToWorld({0, 0.5, 0.6}, {0, 0, 2.0}, {0, 1, 0});
  r.render(away, fx, frame);
  for (int i = 8; i < 20; ++i) {
    const TrackedPose p = tracker->update(view(frame), i / 30.0);
    const OcclusionMask* m = tracker->occlusionMask();
    if (p.state == TrackingState::Lost) {
      EXPECT_FALSE(m->targetInView);
      EXPECT_TRUE(allZero(*m));
    }
  }
  tracker->reset();
  EXPECT_TRUE(allZero(*tracker->occlusionMask()));
}

// The same frame and pose give the same bits, whatever came before; the tracker's mask is the
// standalone one's at the pose it measured, computed once per frame however often it is asked.
TEST(TargetOcclusion, SameInputsGiveTheSameBits) {
  cv::setNumThreads(1);
  const SequenceRenderer& r = standard();
  auto occlusion = standardTargetOcclusion(r.camera(), {});
  FrameEffects fx;
  fx.occluderFraction = 0.35, fx.occluderPhase = 0.6, fx.motionBlurPx = 9, fx.motionBlurAngleDeg = 10;
  cv::Mat a, b;
  const glm::dmat4 pa = orbitPose(20, 45, 0.7), pb = orbitPose(80, 55, 0.6);
  r.render(pa, fx, a);
  r.render(pb, {}, b);
  occlusion->update(view(a), pa);
  const std::vector<std::uint8_t> first(occlusion->mask().pixels,
                                        occlusion->mask().pixels + occlusion->mask().width * occlusion->mask().height);
  occlusion->update(view(b), pb);
  occlusion->update(view(a), pa);
  EXPECT_EQ(std::memcmp(first.data(), occlusion->mask().pixels, first.size()), 0);
  EXPECT_GT(occlusion->mask().hiddenShare, 0.2);

  // Grey or RGB: the same grey (OpenCV's weights), the same mask.
  cv::Mat grey;
  cv::cvtColor(a, grey, cv::COLOR_RGB2GRAY);
  occlusion->update(view(grey), pa);
  int different = 0;
  for (std::size_t i = 0; i < first.size(); ++i) different += std::abs(first[i] - occlusion->mask().pixels[i]) > 8;
  EXPECT_LE(different, static_cast<int>(first.size() / 200));

  // The tracker's: a TargetOcclusion of its map, its grey frame, the pose it measured.
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(r.camera(), standardTargetImage(), kStandardTargetWidth, {}, d);
  ASSERT_TRUE(tracker) << d.format();
  auto fromMap = TargetOcclusion::create(r.camera(), tracker->map(), {}, d);
  ASSERT_TRUE(fromMap) << d.format();
  cv::Mat frame, frameGrey;
  TrackedPose p;
  FrameEffects hand;
  hand.occluderFraction = 0.3, hand.occluderPhase = 0.6;
  for (int i = 0; i < 8; ++i) {
    const glm::dmat4 pose = orbitPose(20 + 0.5 * i, 45, 0.7);
    r.render(pose, hand, frame);
    p = tracker->update(view(frame), i / 30.0);
  }
  ASSERT_EQ(p.state, TrackingState::Tracking);
  const OcclusionMask* m = tracker->occlusionMask();
  ASSERT_NE(m, nullptr);
  const std::vector<std::uint8_t> tracked(m->pixels, m->pixels + m->width * m->height);
  EXPECT_EQ(tracker->occlusionMask(), m);  // asked again: the same mask
  cv::cvtColor(frame, frameGrey, cv::COLOR_RGB2GRAY);
  fromMap->update(view(frameGrey), tracker->lastFrame().judgedCameraToWorld);
  EXPECT_EQ(std::memcmp(tracked.data(), fromMap->mask().pixels, tracked.size()), 0);
  EXPECT_GT(m->hiddenShare, 0.2);
}

TEST(TargetOcclusion, SettingsAndReferencesOutOfRangeAreErrors) {
  const SequenceRenderer& r = standard();
  const cv::Mat ref = standardTargetGrey(cv::Size(200, 160));
  const std::array<double, 9> h{200 / 0.3, 0, 99.5, 0, 200 / 0.3, 79.5, 0, 0, 1};
  for (auto bad : {OcclusionSettings{.scale = 1}, OcclusionSettings{.window = 4}, OcclusionSettings{.searchRadius = 4},
                   OcclusionSettings{.hiddenNcc = 0.8, .visibleNcc = 0.7}, OcclusionSettings{.fineWeight = 2}}) {
    Diagnostics d;
    EXPECT_FALSE(TargetOcclusion::create(r.camera(), view(ref), h, bad, d));
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.items[0].file, "occlusion settings");
    EXPECT_FALSE(bad.problem().empty());
  }
  Diagnostics d;
  cv::Mat rgb;
  cv::cvtColor(ref, rgb, cv::COLOR_GRAY2RGB);
  EXPECT_FALSE(TargetOcclusion::create(r.camera(), view(rgb), h, {}, d));
  EXPECT_FALSE(TargetOcclusion::create(r.camera(), view(ref), std::array<double, 9>{}, {}, d));
  // A tracker with occlusion settings out of range is refused when made.
  MarkerlessSettings s;
  s.occlusion.scale = 40;
  Diagnostics t;
  EXPECT_FALSE(MarkerlessTracker::fromTarget(r.camera(), standardTargetImage(), kStandardTargetWidth, s, t));
  EXPECT_NE(t.format().find("occlusion"), std::string::npos);
  // Another scale: the mask's size follows.
  Diagnostics e;
  auto eighth = TargetOcclusion::create(r.camera(), view(ref), h, OcclusionSettings{.scale = 8}, e);
  ASSERT_TRUE(eighth) << e.format();
  EXPECT_EQ(eighth->mask().width, 80);
  EXPECT_EQ(eighth->mask().height, 60);
  EXPECT_EQ(eighth->mask().scale, 8);
}

// AprilTag has no image of the target to compare the frame with: no occlusion map (the renderer
// switches the feature off there).
TEST(TargetOcclusion, AprilTagTrackerHasNone) {
  const CameraModel camera{.width = 640, .height = 480, .fx = 600, .fy = 600, .cx = 319.5, .cy = 239.5};
  Diagnostics d;
  auto tracker = AprilTagTracker::create(camera, {}, d);
  ASSERT_TRUE(tracker) << d.format();
  EXPECT_FALSE(tracker->hasOcclusionMask());
  EXPECT_EQ(tracker->occlusionMask(), nullptr);
  Tracker& base = *tracker;
  EXPECT_EQ(base.occlusionMask(), nullptr);
}

// Hands (stress_scenarios.hpp: one or two textured hands with forearms, 5..25 cm above the
// target, reaching in while the camera moves, smeared over the exposure): three sequences.
TEST(TargetOcclusionAccuracy, FindsHandsOverTheTarget) {
  MaskSummary exact, tracked;
  int drawn = 0, frames = 0;
  auto add = [](MaskSummary& all, const MaskSummary& one) {
    all.iouMean += one.hiddenFrames > 0 ? one.iouMean * one.hiddenFrames : 0;
    all.missedHiddenMean += one.hiddenFrames > 0 ? one.missedHiddenMean * one.hiddenFrames : 0;
    all.falseHiddenMean += one.visibleFrames > 0 ? one.falseHiddenMean * one.visibleFrames : 0;
    if (one.hiddenFrames > 0) all.iouWorst = std::min(all.iouWorst, one.iouWorst);
    if (one.hiddenFrames > 0) all.missedHiddenWorst = std::max(all.missedHiddenWorst, one.missedHiddenWorst);
    all.falseHiddenWorst = std::max(all.falseHiddenWorst, one.visibleFrames > 0 ? one.falseHiddenWorst : 0.0);
    all.frames += one.frames, all.hiddenFrames += one.hiddenFrames, all.visibleFrames += one.visibleFrames;
    all.found += one.found, all.truthHidden += one.truthHidden, all.unionPixels += one.unionPixels;
    all.visibleSaidHidden += one.visibleSaidHidden, all.truthVisible += one.truthVisible;
  };
  for (const std::uint64_t seed : {5u, 7u, 10u}) {
    cv::setNumThreads(2);
    const OcclusionSequence s = stressOcclusionSequence(standard(), StressClass::Hands, seed, 0, 4);
    cv::setNumThreads(1);
    add(exact, maskAtExactPoses(s, standard().camera(), {}));
    int d = 0;
    add(tracked, maskAtTrackerPoses(s, standard().camera(), {}, d));
    drawn += d;
    frames += static_cast<int>(s.frames.size());
  }
  for (MaskSummary* m : {&exact, &tracked}) {
    m->iouMean /= std::max(1, m->hiddenFrames);
    m->missedHiddenMean /= std::max(1, m->hiddenFrames);
    m->falseHiddenMean /= std::max(1, m->visibleFrames);
    m->pooledIou = static_cast<double>(m->found) / static_cast<double>(std::max(1LL, m->unionPixels));
    m->pooledFalseHidden = static_cast<double>(m->visibleSaidHidden) / static_cast<double>(std::max(1LL, m->truthVisible));
    m->pooledMissedHidden = 1.0 - static_cast<double>(m->found) / static_cast<double>(std::max(1LL, m->truthHidden));
  }
  print("hands 5, 7, 10, exact poses", exact);
  print("hands 5, 7, 10, tracker's poses", tracked);
  std::printf("[ occlusion ] hands: %d of %d frames drawn by the tracker\n", drawn, frames);
  // Measured (exact / tracker's poses): IoU 0.80 / 0.78 mean, 0.84 / 0.82 pooled; false hidden
  // 1.3 / 1.0 % mean, 0.9 / 0.8 % pooled; missed 14 / 15 % pooled.
  for (const MaskSummary* m : {&exact, &tracked}) {
    EXPECT_GE(m->hiddenFrames, 55);
    EXPECT_GE(m->iouMean, 0.73);
    EXPECT_GE(m->pooledIou, 0.77);
    EXPECT_LE(m->falseHiddenMean, 0.021);
    EXPECT_LE(m->pooledFalseHidden, 0.015);
    EXPECT_LE(m->pooledMissedHidden, 0.21);
  }
  EXPECT_GE(drawn, 95);
}

}  // namespace
