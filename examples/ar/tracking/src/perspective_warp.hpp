// A grey image warped through a homography into a region of a preallocated image: the
// markerless tracker's template (the keyframe as the predicted camera sees it). Replaces
// cv::warpPerspective(src, dst(region), shift * H, region.size(), INTER_LINEAR,
// BORDER_CONSTANT, border), which allocates two scratch images per 32x32 tile.
#pragma once
#include <cstdint>

#include <opencv2/core.hpp>

namespace marionette::ar {

// The inverse by the adjugate; false when the determinant is 0 or not finite.
[[nodiscard]] bool invertHomography(const cv::Matx33d& h, cv::Matx33d& inverse) noexcept;

// dst(x, y) = src(H^-1 (x, y)) for the pixels of `region` (clipped to dst), bilinear, with
// `border` wherever a tap falls outside src; the rest of dst is left as it is. `srcToDst`
// maps src pixels to dst pixels (the full image's, not the region's). Like OpenCV, the source
// position is rounded to 1/32 px and the weights are exact integers, so the result matches
// cv::warpPerspective's to the bit but for rare ties. False (dst untouched) when src or dst
// is not 8-bit single-channel, or H is singular or not finite. Allocates nothing. `wide`:
// four pixels at a time with AVX2 where the CPU has it (the same bits; false for the scalar
// loop, which the tests compare it with).
bool warpPerspectiveRegion(const cv::Mat& src, const cv::Matx33d& srcToDst, cv::Mat& dst, cv::Rect region,
                           std::uint8_t border, bool wide = true) noexcept;

}  // namespace marionette::ar
