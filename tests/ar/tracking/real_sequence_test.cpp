// The markerless tracker on a real recorded sequence: ViSP's mire-2 (Debian visp-images-data),
// 501 frames at 384x288 from a camera standing in front of a wall of posters while a hand
// carries a box with a dot target across it. No motion capture: the camera barely moves, and
// what little it does (a few tenths of a pixel) is measured independently on the wall's upper
// right, which the box never reaches, by phase correlation. What the test measures
// (docs/tracking.md): how many frames are tracked while the box hides more and more of the
// reference (frame 1, the box included), how far the wall's points are from where the still
// camera saw them, and whether the tracker's motion agrees with the phase correlation. Pixels,
// not metres: ViSP publishes no intrinsics for mire-2, so metres would scale with a guess.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

std::string mireFrame(int i) {
  char name[64];
  std::snprintf(name, sizeof name, "mire-2/image.%04d.pgm", i);
  return test::vispImage(name);
}

cv::Point2d transfer(const std::array<double, 9>& h, const cv::Point2d& p) {
  const double w = h[6] * p.x + h[7] * p.y + h[8];
  return {(h[0] * p.x + h[1] * p.y + h[2]) / w, (h[3] * p.x + h[4] * p.y + h[5]) / w};
}

TEST(RealSequence, StillCameraOverAPosterWallWithAHandHeldBoxInFront) {
  constexpr int kFrames = 501;
  // Until about here the box hides less than two thirds of the reference's corners; past it,
  // TRACKING (which needs a third of them) is not expected.
  constexpr int kBoxCoversMost = 280;
  const cv::Mat first = cv::imread(mireFrame(1), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(first.empty()) << mireFrame(1) << " (Debian visp-images-data) is missing";
  const CameraModel camera{.width = first.cols, .height = first.rows, .fx = 400, .fy = 400,
                           .cx = (first.cols - 1) * 0.5, .cy = (first.rows - 1) * 0.5};  // a guess
  constexpr double kWidth = 1.0;  // the reference (frame 1), metres: also a guess
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(camera, mireFrame(1), kWidth, MarkerlessSettings{}, d);
  ASSERT_TRUE(tracker) << d.format();
  const double mpp = kWidth / first.cols;
  auto planeOf = [&](const cv::Point2d& px) {  // frame-1 pixel -> the reference's plane (X, Z)
    return cv::Point2d((px.x + 0.5) * mpp - kWidth * 0.5, (px.y + 0.5) * mpp - first.rows * mpp * 0.5);
  };
  // The wall's upper right (above the box all along): phase correlation's window, and its centre.
  const cv::Rect wallWindow(200, 40, 176, 96);
  const cv::Point2d wallCentre(wallWindow.x + wallWindow.width * 0.5 - 0.5, wallWindow.y + wallWindow.height * 0.5 - 0.5);
  const std::array<cv::Point2d, 4> wallPoints = {cv::Point2d(40, 30), cv::Point2d(340, 30), cv::Point2d(360, 120),
                                                 cv::Point2d(350, 260)};
  cv::Mat firstWindow;
  first(wallWindow).convertTo(firstWindow, CV_64F);
  int trackingEarly = 0, posedEarly = 0, posed = 0, tracking = 0, compared = 0;
  double worst = 0, sum = 0, worstDisagreement = 0, sumDisagreement = 0;
  int samples = 0;
  for (int i = 1; i <= kFrames; ++i) {
    const cv::Mat f = cv::imread(mireFrame(i), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(f.empty()) << mireFrame(i);
    const TrackedPose p = tracker->update({f.data, f.cols, f.rows, 1, static_cast<std::ptrdiff_t>(f.step)}, (i - 1) / 25.0);
    posed += p.state != TrackingState::Lost;
    posedEarly += p.state != TrackingState::Lost && i <= kBoxCoversMost;
    if (p.state != TrackingState::Tracking) continue;
    ++tracking;
    trackingEarly += i <= kBoxCoversMost;
    const auto& h = tracker->lastFrame().planeToImage;
    for (const cv::Point2d& px : wallPoints) {
      const cv::Point2d moved = transfer(h, planeOf(px)) - px;
      worst = std::max(worst, std::hypot(moved.x, moved.y));
      sum += std::hypot(moved.x, moved.y);
      ++samples;
    }
    // The tracker's motion of the wall against phase correlation's, every 10th frame.
    if (i % 10 == 0) {
      cv::Mat window;
      f(wallWindow).convertTo(window, CV_64F);
      const cv::Point2d shift = cv::phaseCorrelate(firstWindow, window);
      const cv::Point2d tracked = transfer(h, planeOf(wallCentre)) - wallCentre;
      const double disagreement = std::hypot(tracked.x - shift.x, tracked.y - shift.y);
      worstDisagreement = std::max(worstDisagreement, disagreement);
      sumDisagreement += disagreement;
      ++compared;
    }
  }
  ASSERT_GT(samples, 0);
  ASSERT_GT(compared, 0);
  std::printf("[ mire-2 ] %d frames: %d TRACKING (%d of the first %d), %d with a pose (%d of the first %d); wall "
              "points off the first frame's: mean %.3f px, worst %.3f px; against phase correlation: mean %.3f px, worst "
              "%.3f px (%d frames)\n",
              kFrames, tracking, trackingEarly, kBoxCoversMost, posed, posedEarly, kBoxCoversMost, sum / samples, worst,
              sumDisagreement / compared, worstDisagreement, compared);
  // A pose (the first frame's once the second confirms it) in 95 % of the early frames; TRACKING
  // in 40 % or more: with the guessed focal length and a 1 m reference seen from about 1.3 m,
  // three standard deviations of the pose are often past TRACKING's 2.6 cm (LIMITED then).
  EXPECT_GE(posedEarly, kBoxCoversMost * 95 / 100) << posedEarly;
  EXPECT_GE(trackingEarly, kBoxCoversMost * 40 / 100);
  // The camera moved about 0.3 px (phase correlation): the wall's points stay within a pixel
  // or so of the first frame's (the worst, 3.4 px, at the frame's corner while the box hides
  // most of the reference: the inliers bunch on one side), and the tracker moves with the wall.
  // Regression bounds, about 1.5x docs/tracking.md's figures (session 26: 0.44 / 1.02 px off the
  // first frame, 0.13 / 0.23 px against phase correlation).
  EXPECT_LT(sum / samples, 0.6);
  EXPECT_LT(worst, 1.55);
  EXPECT_LT(sumDisagreement / compared, 0.2);
  EXPECT_LT(worstDisagreement, 0.35);
}

// ViSP's `cube`: 80 frames at 384x288 from a hand-held camera closing in on a magazine collage
// with a dotted cube standing on it, the first frame as the reference (a guessed focal length,
// 0.3 m for its width). With one keyframe the template matched less and less (the cube stands
// off the plane, the guessed intrinsics bend the homographies): LIMITED from frame 38, LOST from
// 61 (issue 40). Keyframes are now added while tracking still holds and the match degrades, as
// PTAM adds them: every frame after the first is TRACKING, the camera path has no jump, and the
// saved map keeps the keyframes.
TEST(RealSequence, HandHeldCameraClosingInOnACollageKeepsTrackingWithNewKeyframes) {
  constexpr int kFrames = 80;
  auto cubeFrame = [](int i) {
    char name[64];
    std::snprintf(name, sizeof name, "cube/image.%04d.pgm", i);
    return test::vispImage(name);
  };
  const cv::Mat first = cv::imread(cubeFrame(0), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(first.empty()) << cubeFrame(0) << " (Debian visp-images-data) is missing";
  const CameraModel camera{.width = first.cols, .height = first.rows, .fx = 400, .fy = 400,
                           .cx = (first.cols - 1) * 0.5, .cy = (first.rows - 1) * 0.5};  // a guess
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(camera, cubeFrame(0), 0.3, MarkerlessSettings{}, d);
  ASSERT_TRUE(tracker) << d.format();
  int tracking = 0;
  double worstStep = 0;
  glm::dvec3 last(0), start(0);
  bool haveLast = false;
  for (int i = 0; i < kFrames; ++i) {
    const cv::Mat f = cv::imread(cubeFrame(i), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(f.empty()) << cubeFrame(i);
    const TrackedPose p = tracker->update({f.data, f.cols, f.rows, 1, static_cast<std::ptrdiff_t>(f.step)}, i / 30.0);
    if (p.state == TrackingState::Lost) continue;
    tracking += p.state == TrackingState::Tracking;
    if (haveLast) worstStep = std::max(worstStep, glm::length(p.position() - last));
    else start = p.position();
    last = p.position();
    haveLast = true;
  }
  const std::size_t keyframes = tracker->map().keyframes.size();
  std::printf("[ cube ] %d frames: %d TRACKING, %zu keyframes, largest step between poses %.1f mm, "
              "camera from %.0f to %.0f mm above the collage\n",
              kFrames, tracking, keyframes, worstStep * 1000, start.y * 1000, last.y * 1000);
  EXPECT_GE(tracking, kFrames - 2);
  EXPECT_GE(keyframes, 3u);
  EXPECT_LT(worstStep, 0.0053);      // a hand-held camera at 30 fps, no jump (regression: 3.5 mm published)
  EXPECT_LT(last.y, 0.8 * start.y);  // it did close in
  // The map saved and read back keeps them (what --save-map writes).
  const std::string file = ::testing::TempDir() + "marionette_cube.map";
  Diagnostics error;
  ASSERT_TRUE(writePlanarMap(file, tracker->map(), error)) << error.format();
  Diagnostics r;
  const auto map = readPlanarMap(file, r);
  ASSERT_TRUE(map) << r.format();
  EXPECT_EQ(map->keyframes.size(), keyframes);
}

}  // namespace
