// Motion blur estimated from a frame against the sharp template, and the line blur that applies
// it (examples/ar/tracking/src/motion_blur.hpp), against OpenCV's filter2D with an exact kernel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "motion_blur.hpp"
#include "test_data.hpp"
#include "tracking/scenario_run.hpp"

namespace {

using namespace marionette::ar;

constexpr double kPi = 3.14159265358979323846;

// A line kernel built independently of the code under test: 64 point splats per pixel of
// length, bilinear, normalized.
cv::Mat referenceKernel(double length, double angleDeg) {
  const int half = static_cast<int>(std::ceil(length / 2)) + 1;
  cv::Mat k = cv::Mat::zeros(2 * half + 1, 2 * half + 1, CV_64F);
  const double a = angleDeg * kPi / 180, c = std::cos(a), s = std::sin(a);
  const int n = static_cast<int>(length * 64);
  for (int i = 0; i < n; ++i) {
    const double t = ((i + 0.5) / n - 0.5) * length, x = half + t * c, y = half + t * s;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    k.at<double>(y0, x0) += (1 - fx) * (1 - fy);
    k.at<double>(y0, x0 + 1) += fx * (1 - fy);
    k.at<double>(y0 + 1, x0) += (1 - fx) * fy;
    k.at<double>(y0 + 1, x0 + 1) += fx * fy;
  }
  return k / cv::sum(k)[0];
}

cv::Mat graf() {
  cv::Mat g = cv::imread(marionette::ar::synthetic::standardTargetImage(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(g.empty()) << "opencv-doc's graf1.png is missing";
  cv::Mat small;
  cv::resize(g, small, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
  return small;
}

cv::Mat blurredWith(const cv::Mat& image, double length, double angleDeg) {
  cv::Mat out;
  cv::filter2D(image, out, -1, referenceKernel(length, angleDeg), cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  return out;
}

std::vector<cv::Point2f> gridPoints(const cv::Mat& image) {
  std::vector<cv::Point2f> p;
  for (int y = 60; y < image.rows - 60; y += 45)
    for (int x = 60; x < image.cols - 60; x += 60) p.emplace_back(static_cast<float>(x), static_cast<float>(y));
  return p;
}

double angleDifferenceDeg(double aRad, double bDeg) {
  double d = std::fmod(std::abs(aRad * 180 / kPi - bDeg), 180.0);  // a smear has no sign
  return std::min(d, 180 - d);
}

TEST(MotionBlur, LineBlurMatchesAnExactKernel) {
  const cv::Mat image = graf();
  MotionBlurScratch scratch;
  scratch.reserve(image.cols, image.rows);
  for (double angle : {0.0, 20.0, 45.0, 70.0, 90.0, 135.0, 160.0})
    for (double length : {5.0, 13.0, 25.0}) {
      const cv::Mat expected = blurredWith(image, length, angle);
      cv::Mat ours = image.clone();
      const cv::Rect region(40, 30, 560, 420);
      applyMotionBlur(image, {length, angle * kPi / 180}, region, ours, scratch);
      cv::Mat diff;
      cv::absdiff(ours(region), expected(region), diff);
      // The digital line puts each tap on the nearest row: up to half a pixel across.
      EXPECT_LT(cv::mean(diff)[0], 2.5) << "length " << length << " angle " << angle;
      EXPECT_EQ(cv::countNonZero(ours(cv::Rect(0, 0, 640, 30)) != image(cv::Rect(0, 0, 640, 30))), 0)
          << "outside the region must stay as it was";
      // No shift: the blurred image correlates best with the exact one at zero offset.
      cv::Mat a, b, score;
      ours(region).convertTo(a, CV_32F);
      expected(cv::Rect(region.x - 2, region.y - 2, region.width + 4, region.height + 4)).convertTo(b, CV_32F);
      cv::matchTemplate(b, a, score, cv::TM_SQDIFF);
      cv::Point best;
      cv::minMaxLoc(score, nullptr, nullptr, &best);
      EXPECT_EQ(best, cv::Point(2, 2)) << "length " << length << " angle " << angle;
    }
}

// The digital line blur of one pixel by its definition (motion_blur.cpp), tap by tap: the taps
// at whole steps along the dominant axis, each on the nearest row (or column) of the line
// through the pixel, pixels past the image clamped, the two outer taps weighted by `end`.
std::uint8_t lineBlurByDefinition(const cv::Mat& image, double length, double angle, int x, int y) {
  const double c = std::cos(angle), s = std::sin(angle);
  const bool alongX = std::abs(c) >= std::abs(s);
  const double major = alongX ? c : s, minor = alongX ? s : c, slope = minor / major;
  const double extent = std::clamp(length * std::abs(major), 1.0, 128.0);
  const int half = std::max(0, static_cast<int>(std::ceil(extent * 0.5 - 0.5)));
  const auto end = static_cast<float>(extent * 0.5 - (half - 0.5)), scale = static_cast<float>(1.0 / extent);
  auto shift = [&](int m) { return static_cast<int>(std::lround(m * slope)); };
  const int m0 = alongX ? x : y, n0 = alongX ? y : x;
  auto tap = [&](int m) {
    const int n = n0 - shift(m0) + shift(m);
    const int px = std::clamp(alongX ? m : n, 0, image.cols - 1), py = std::clamp(alongX ? n : m, 0, image.rows - 1);
    return static_cast<float>(image.at<std::uint8_t>(py, px));
  };
  float v = tap(m0);
  if (half > 0) {
    float inner = 0;
    for (int k = -half + 1; k <= half - 1; ++k) inner += tap(m0 + k);
    v = scale * (inner + end * (tap(m0 - half) + tap(m0 + half)));
  }
  return static_cast<std::uint8_t>(std::min(std::max(v + 0.5f, 0.0f), 255.0f));
}

// The running sums, the runs read without clamping, the rows skipped outside the region and the
// AVX2 loop (where the CPU has it) are only speed: every pixel is its definition's, to the bit,
// at any angle, length and region, with the AVX2 loop and without.
TEST(MotionBlur, LineBlurIsItsDefinitionToTheBit) {
  const cv::Mat image = graf();
  MotionBlurScratch scratch;
  scratch.reserve(image.cols, image.rows);
  const std::vector<cv::Rect> regions = {cv::Rect(0, 0, 640, 480), cv::Rect(-30, 200, 120, 300), cv::Rect(590, -10, 80, 60),
                                         cv::Rect(300, 200, 17, 17)};
  for (double angleDeg : {0.0, 8.0, -20.0, 45.0, -45.0, 60.0, 90.0, 112.0, 160.0, 200.0})
    for (double length : {1.5, 3.0, 6.3, 24.0, 90.0, 400.0})
      for (const cv::Rect& region : regions)
      for (const bool wide : {true, false}) {
        const double angle = angleDeg * kPi / 180;
        cv::Mat ours = image.clone();
        applyMotionBlur(image, {length, angle}, region, ours, scratch, wide);
        const cv::Rect inside = region & cv::Rect(0, 0, image.cols, image.rows);
        int differing = 0;
        for (int y = inside.y; y < inside.y + inside.height; y += 3)
          for (int x = inside.x; x < inside.x + inside.width; x += 3)
            differing += ours.at<std::uint8_t>(y, x) != (length >= 2 ? lineBlurByDefinition(image, length, angle, x, y)
                                                                        : image.at<std::uint8_t>(y, x));
        EXPECT_EQ(differing, 0) << "angle " << angleDeg << " length " << length << " region " << region << " wide " << wide;
        // Nothing outside the region is written.
        cv::Mat outside = cv::Mat::ones(image.size(), CV_8UC1);
        outside(inside).setTo(0);
        EXPECT_EQ(cv::countNonZero((ours != image) & outside), 0) << "angle " << angleDeg << " length " << length
                                                                  << " region " << region;
      }
}

// The statistics give a start (within a third of the length, 8 degrees), the aligned search
// the blur itself (within 5 %, 3 degrees): the tracker relies on the second.
TEST(MotionBlur, EstimatesThenRefinesLengthAndDirectionOfAKnownBlur) {
  const cv::Mat sharp = graf();
  const std::vector<cv::Point2f> points = gridPoints(sharp);
  MotionBlurScratch scratch;
  scratch.reserve(sharp.cols, sharp.rows);
  for (double angle : {0.0, 30.0, 90.0, 125.0})
    for (double length : {9.0, 17.0, 25.0}) {
      const cv::Mat frame = blurredWith(sharp, length, angle);
      const MotionBlur start = estimateMotionBlur(sharp, frame, points, 64, scratch);
      EXPECT_NEAR(start.lengthPx, length, length / 3) << "angle " << angle;
      EXPECT_LT(angleDifferenceDeg(start.angleRad, angle), 8.0) << "length " << length;
      // The blur moves nothing: the matched points are where they were.
      const MotionBlur refined = refineMotionBlur(sharp, frame, points, points, start, 64, scratch);
      EXPECT_NEAR(refined.lengthPx, length, 0.05 * length) << "angle " << angle;
      EXPECT_LT(angleDifferenceDeg(refined.angleRad, angle), 3.0) << "length " << length;
    }
  // A sharp frame refines to no blur from any start.
  EXPECT_FALSE(refineMotionBlur(sharp, sharp, points, points, {12, 0.5}, 64, scratch).any());
}

TEST(MotionBlur, NoBlurWhereTheFrameDiffersOnlyByGainNoiseOrDefocus) {
  const cv::Mat sharp = graf();
  const std::vector<cv::Point2f> points = gridPoints(sharp);
  MotionBlurScratch scratch;
  scratch.reserve(sharp.cols, sharp.rows);
  EXPECT_FALSE(estimateMotionBlur(sharp, sharp, points, 64, scratch).any());
  cv::Mat gained;
  sharp.convertTo(gained, -1, 1.8, -20);
  EXPECT_FALSE(estimateMotionBlur(sharp, gained, points, 64, scratch).any());
  cv::Mat noisy = sharp.clone(), noise(sharp.size(), CV_16S);
  cv::randn(noise, 0, 6);
  cv::Mat n16;
  sharp.convertTo(n16, CV_16S);
  cv::add(n16, noise, n16);
  n16.convertTo(noisy, CV_8U);
  EXPECT_FALSE(estimateMotionBlur(sharp, noisy, points, 64, scratch).any());
  cv::Mat defocused;
  cv::GaussianBlur(sharp, defocused, cv::Size(0, 0), 1.5);
  EXPECT_FALSE(estimateMotionBlur(sharp, defocused, points, 64, scratch).any());
}

TEST(MotionBlur, BadInputGivesNoBlurAndNoCrash) {
  const cv::Mat sharp = graf();
  MotionBlurScratch scratch;
  scratch.reserve(sharp.cols, sharp.rows);
  EXPECT_FALSE(estimateMotionBlur(sharp, sharp, {}, 64, scratch).any());
  EXPECT_FALSE(estimateMotionBlur(sharp, cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), gridPoints(sharp), 64, scratch).any());
  const cv::Mat black(480, 640, CV_8UC1, cv::Scalar(0));
  EXPECT_FALSE(estimateMotionBlur(black, black, gridPoints(black), 64, scratch).any());
  // Points at and past the border read clamped pixels.
  const std::vector<cv::Point2f> edge = {{0, 0}, {639, 479}, {-50, 20}, {700, 500}, {320, 0}, {0, 240}, {639, 240}};
  (void)estimateMotionBlur(sharp, blurredWith(sharp, 15, 0), edge, 64, scratch);
  cv::Mat out = sharp.clone();
  applyMotionBlur(sharp, {15, 0.3}, cv::Rect(-20, -20, 2000, 2000), out, scratch);  // clipped to the image
  applyMotionBlur(sharp, {15, 0.3}, cv::Rect(0, 0, 0, 0), out, scratch);
  MotionBlurScratch unreserved;  // too small: nothing done, nothing allocated
  cv::Mat untouched = sharp.clone();
  applyMotionBlur(sharp, {15, 0.3}, cv::Rect(0, 0, 640, 480), untouched, unreserved);
  EXPECT_EQ(cv::countNonZero(untouched != sharp), 0);
}

}  // namespace
