// The whole image's shift from one frame to the next, by zero-mean normalized cross-correlation
// of a large central block over the coarse levels of both pyramids: what the markerless
// tracker's background prediction falls back on when KLT on its grid fails. Under a smear of
// 40-60 px the grid's windows hold little texture across the smear and slide along it (under
// half of them agree), while a block a third of the image wide, smeared alike in both frames,
// still correlates. A shift is a rotation of the camera about its centre (pan and tilt, not
// roll): rotationShiftHomography turns it into the homography the prediction needs.
#pragma once
#include <opencv2/core.hpp>

#include "lucas_kanade.hpp"

namespace marionette::ar {

struct ImageShift {
  cv::Point2f shift;  // level-0 pixels: a point of the previous frame is at p + shift in this one
  double score = 0;   // the ZNCC at the peak, -1..1
};

struct ImageShiftOptions {
  int coarseLevel = 3;    // the search level (80 x 60 for a 640 x 480 frame)
  int radius = 16;        // search radius at the coarse level, pixels (128 px of level 0 at level 3: 12 deg a frame at fx 600)
  double minScore = 0.6;  // a peak lower than this is no shift (a blank wall, a scene that changed)
  // The peak must stand out: every other local maximum of the search (its border included) must
  // be lower by this much (a repeating texture has several peaks; none is to be trusted). A peak
  // on the search's border, at any level, is refused: the true one lies beyond.
  double minMargin = 0.05;
};

// The shift from `previous` to `current` (pyramids of the same size, built to the coarse level
// or deeper), searched around `guess` (level-0 pixels) at the coarse level, then refined at each
// finer level down to level coarseLevel - 2 (or 0) by +-2 px and a parabola through the peak.
// False when the levels are missing or too small for the radius, the block has no texture, or
// the peak is low or ambiguous. Allocates nothing.
[[nodiscard]] bool estimateImageShift(const ImagePyramid& previous, const ImagePyramid& current, cv::Point2f guess,
                                      const ImageShiftOptions& params, ImageShift& out) noexcept;

// The homography (previous pixel -> current pixel) of a camera turning about its centre so
// that the principal point's image moves by `shift`: K R K^-1 with R the smallest rotation
// taking the optical axis to the ray through principal point + shift.
[[nodiscard]] cv::Matx33d rotationShiftHomography(const cv::Matx33d& K, cv::Point2f shift) noexcept;

}  // namespace marionette::ar
