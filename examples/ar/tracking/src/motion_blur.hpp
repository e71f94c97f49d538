// Motion blur of a camera frame, measured against the sharp template warped into the same view,
// and applied to that template so that KLT compares like with like.
//
// Why: a frame smeared 9..25 px along the image motion does not match a sharp template: KLT
// keeps a third of its points or fewer and their positions are biased. Blurring the template
// with the frame's own blur restores the match (docs/tracking.md measures it). The blur is
// estimated from the images, not predicted from the motion: the exposure (hence the length) is
// unknown, and the image motion is not one direction when the camera turns.
//
// How: around sample points, the gradient structure tensors of the frame and of the template,
// each normalized by its trace (gain and contrast cancel; an isotropic loss of sharpness, such
// as noise or defocus, cancels too). Blur along a direction removes gradient energy along it:
// the direction is the eigenvector of the largest energy loss. The length is the one whose
// line blur of the template's patches loses the same share along that direction (the share
// falls monotonically with the length: bisection).
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace marionette::ar {

struct MotionBlur {
  double lengthPx = 0;  // of a normalized line kernel; below 2: none
  double angleRad = 0;  // direction of the smear, 0 along +x, pi/2 along +y (image down)
  [[nodiscard]] bool any() const noexcept { return lengthPx >= 2; }
};

// Scratch of the line blur (one sheared row and its shifts) and of the blur search, sized once
// for the largest region (reserve) and reused.
struct MotionBlurScratch {
  std::vector<float> patches;
  std::vector<int> line, shifts;
  std::vector<int> prefix;             // applyMotionBlur's prefix sums of a sheared row
  std::vector<std::uint8_t> rowBytes;  // ... and its blurred values, before they are stored
  std::vector<int> patchLines, patchShifts;  // the searches' sheared rows around their patches
  void reserve(int width, int height) {
    const std::size_t side = static_cast<std::size_t>(std::max(width, height)) + 2;
    line.reserve(side + 2 * kMaxLineTaps + 2);
    shifts.reserve(side + 2 * kMaxLineTaps + 2);
    prefix.reserve(side + 2 * kMaxLineTaps + 3);
    rowBytes.reserve(side + 2 * kMaxLineTaps + 2);
    patches.reserve(32 * 17 * 17);  // refineMotionBlur's frame patches
    // Up to kMaxSearchPatches patches of kMaxSearchSide px (the estimate's), each 2 x side
    // sheared rows of side + 2 * 64 taps and their prefix.
    patchLines.reserve(kMaxSearchPatches * 2 * kMaxSearchSide * (kMaxSearchSide + 2 * (kMaxLineTaps / 2) + 1));
    patchShifts.reserve(kMaxSearchPatches * (kMaxSearchSide + 2 * (kMaxLineTaps / 2)));
  }
  static constexpr int kMaxLineTaps = 129;
  static constexpr int kMaxSearchPatches = 64, kMaxSearchSide = 19;  // motion_blur.cpp asserts its own fit
};

// `sharp` and `frame` are grey 8-bit images of the same size and geometry (the template warped
// into the frame's view); `points` where both show the target (the predicted corners).
// Deterministic; no allocation once `scratch` is reserved for 32x32 and more.
[[nodiscard]] MotionBlur estimateMotionBlur(const cv::Mat& sharp, const cv::Mat& frame,
                                            const std::vector<cv::Point2f>& points, double maxLengthPx,
                                            MotionBlurScratch& scratch) noexcept;

// The blur that best explains `frame` by `sharp` blurred, around matched points (`from` in
// `sharp`, `to` in the frame, as KLT found them): aligned patches, so this is unbiased where
// the statistics of estimateMotionBlur are only near. Searched around `start`; no blur when
// the sharp template explains the frame as well.
[[nodiscard]] MotionBlur refineMotionBlur(const cv::Mat& sharp, const cv::Mat& frame, const std::vector<cv::Point2f>& from,
                                          const std::vector<cv::Point2f>& to, const MotionBlur& start, double maxLengthPx,
                                          MotionBlurScratch& scratch) noexcept;

// The line blur of `image` inside `region`, written to the same pixels of `out` (same size and
// type, preallocated; outside `region` untouched). The line is digital (each tap on the nearest
// row or column), pixels outside the image clamp to its edge. O(1) per pixel: running sums
// along the sheared rows. `wide`: eight values at a time with AVX2 where the CPU has it (the
// same bits; false for the scalar loop, which the tests compare it with).
void applyMotionBlur(const cv::Mat& image, const MotionBlur& blur, const cv::Rect& region, cv::Mat& out,
                     MotionBlurScratch& scratch, bool wide = true) noexcept;

}  // namespace marionette::ar
