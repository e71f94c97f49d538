#include "tilted_views.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace marionette::ar {

namespace {

// Tilt 2 (the target 30 deg above the floor's horizon) at five in-plane directions, 36 deg apart
// (ASIFT's 72 deg / tilt).
constexpr double kViewTilt = 2.0;
constexpr int kViewDirections = 5;

}  // namespace

std::vector<TiltedView> makeTiltedViews(const cv::Mat& reference, int referenceWidth, int features) {
  std::vector<TiltedView> views;
  if (features <= 0) return views;
  auto detector = cv::ORB::create(features, 1.2f, 8, 19, 0, 2, cv::ORB::HARRIS_SCORE, 19, 15);
  const cv::Mat full(reference.size(), CV_8UC1, cv::Scalar(255));
  for (int k = 0; k < kViewDirections; ++k) {
    // Reference pixel -> view pixel: turn by phi into a canvas that holds the whole image, then
    // squeeze the rows by the tilt (area interpolation: no aliasing).
    const double phi = 180.0 * k / kViewDirections;
    cv::Matx23d turn = cv::getRotationMatrix2D(cv::Point2f(0, 0), phi, 1.0);
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const cv::Point2d c : {cv::Point2d(0, 0), cv::Point2d(reference.cols, 0), cv::Point2d(0, reference.rows),
                                cv::Point2d(reference.cols, reference.rows)}) {
      const cv::Vec2d q = turn * cv::Vec3d(c.x, c.y, 1.0);
      x0 = std::min(x0, q[0]), y0 = std::min(y0, q[1]), x1 = std::max(x1, q[0]), y1 = std::max(y1, q[1]);
    }
    turn(0, 2) -= x0;
    turn(1, 2) -= y0;
    const cv::Size canvas(static_cast<int>(std::ceil(x1 - x0)), static_cast<int>(std::ceil(y1 - y0)));
    cv::Mat turned, turnedMask, view, viewMask;
    cv::warpAffine(reference, turned, turn, canvas, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::warpAffine(full, turnedMask, turn, canvas, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
    const cv::Size squeezed(canvas.width, std::max(1, static_cast<int>(std::lround(canvas.height / kViewTilt))));
    cv::resize(turned, view, squeezed, 0, 0, cv::INTER_AREA);
    cv::resize(turnedMask, viewMask, squeezed, 0, 0, cv::INTER_NEAREST);
    cv::erode(viewMask, viewMask, cv::Mat(), cv::Point(-1, -1), 4);  // no corners on the canvas's edge
    std::vector<cv::KeyPoint> kps;
    TiltedView v;
    detector->detectAndCompute(view, viewMask, kps, v.descriptors);
    if (kps.size() < 2) continue;
    // Back: unsqueeze (pixel centres), undo the turn, then the level's scale to level-0 pixels.
    const double sy = static_cast<double>(canvas.height) / squeezed.height;
    const double level = static_cast<double>(referenceWidth) / reference.cols;
    const cv::Matx33d toView(turn(0, 0), turn(0, 1), turn(0, 2), turn(1, 0), turn(1, 1), turn(1, 2), 0, 0, 1);
    const cv::Matx33d back = toView.inv();
    for (const cv::KeyPoint& kp : kps) {
      const cv::Vec3d r = back * cv::Vec3d(kp.pt.x, (kp.pt.y + 0.5) * sy - 0.5, 1.0);
      v.featurePixels.emplace_back(static_cast<float>((r[0] + 0.5) * level - 0.5),
                                   static_cast<float>((r[1] + 0.5) * level - 0.5));
    }
    views.push_back(std::move(v));
  }
  return views;
}

}  // namespace marionette::ar
