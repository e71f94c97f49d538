// Simulated tilted views of the markerless tracker's reference, in the spirit of ASIFT (Morel and
// Yu 2009; docs/tracking.md "Relocalization"): ORB is not invariant to the squeeze a camera low
// over the floor sees a target with, so relocalization also matches the reference turned and
// squeezed 2:1. Without them a 2 m mat seen from 3.4 m relocalized in 2 of 10 cold starts.
#pragma once
#include <vector>

#include <opencv2/core.hpp>

namespace marionette::ar {

struct TiltedView {
  cv::Mat descriptors;                     // ORB, one row per feature
  std::vector<cv::Point2f> featurePixels;  // in the reference's level-0 pixels
};

// Five views of `reference` (a grey image, perhaps a downscaled level of the reference, whose
// level 0 is `referenceWidth` pixels wide), `features` ORB features each; none for features <= 0.
[[nodiscard]] std::vector<TiltedView> makeTiltedViews(const cv::Mat& reference, int referenceWidth, int features);

}  // namespace marionette::ar
