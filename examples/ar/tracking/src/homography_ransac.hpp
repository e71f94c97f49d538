// RANSAC homography from point pairs (the markerless tracker's plane (X, Z) metres -> frame
// pixels), replacing cv::findHomography(RANSAC): 4-point samples solved in normalized
// coordinates, a seeded RNG (the same input gives the same bits), OpenCV's adaptive iteration
// count, then a least-squares refit on the inliers and Levenberg-Marquardt on their
// reprojection error. Also the small dense solvers it and planar_pose use.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

namespace marionette::ar {

// Jacobi eigen-decomposition of a symmetric n x n matrix (row-major, n <= 9): eigenvalues
// ascending, eigenvector i in row i of `vectors`. False for n out of range or a non-finite entry.
bool symmetricEigen(int n, const double* a, double* values, double* vectors) noexcept;
// Solves the n x n system a x = b in place (a destroyed, x in b), partial pivoting, n <= 9.
// False when a pivot is below `tiny` times the largest entry of its column.
bool solveLinear(int n, double* a, double* b, double tiny = 1e-12) noexcept;
// A Levenberg-Marquardt step: solves (JtJ + lambda diag(JtJ)) step = -Jtr for `step`, n <= 9,
// `jtj` row-major and symmetric (left as it is). False when the damped system is singular.
bool dampedStep(int n, const double* jtj, const double* jtr, double lambda, double tiny, double* step) noexcept;

struct HomographyRansacOptions {
  double thresholdPx = 3;       // a pair is an inlier when the homography puts src within this of dst
  int maxIterations = 500;
  double confidence = 0.995;    // of having drawn one all-inlier sample: sets the iterations needed
  int refineIterations = 10;    // Levenberg-Marquardt steps after the least-squares refit (0: none)
  std::uint64_t seed = 0x2545F4914F6CDD1DULL;  // the RNG starts here on every call
};

class HomographyRansac {
 public:
  // Buffers for up to maxPoints pairs (allocates; the only call that does).
  void reserve(std::size_t maxPoints);
  [[nodiscard]] std::size_t capacity() const noexcept { return capacity_; }

  // h maps src to dst (h(2, 2) = 1); mask[i] = 1 for the inliers of the best sample (as
  // findHomography's mask), 0 for the others and for pairs with a non-finite coordinate;
  // `inliers` counts them. False (h untouched, mask all 0) when there are fewer than 4 usable
  // pairs, more than reserved, src and dst differ in size or mask is too short, no sample of 4
  // is free of collinear triples with a consistent orientation, or the inliers are degenerate.
  bool estimate(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst, const HomographyRansacOptions& params,
                cv::Matx33d& h, std::span<std::uint8_t> mask, int& inliers) noexcept;

  // The normalized-DLT least-squares homography of the pairs with mask[i] != 0 (all when mask
  // is empty), then `refineIterations` Levenberg-Marquardt steps. False when fewer than 4
  // pairs, more than reserved, or degenerate (the pairs do not fix a unique homography).
  bool fit(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst, std::span<const std::uint8_t> mask,
           int refineIterations, cv::Matx33d& h) noexcept;

 private:
  std::size_t capacity_ = 0;
  // Valid pairs in normalized coordinates (centroid 0, mean distance sqrt 2), their indices.
  std::vector<cv::Point2d> src_, dst_;
  std::vector<std::size_t> index_;
  std::vector<std::uint8_t> best_, current_;
  cv::Matx33d srcToNormal_, dstToNormal_;
  double dstScale_ = 1;  // normalized units per pixel

  std::size_t normalize(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst,
                        std::span<const std::uint8_t> mask) noexcept;
  bool finish(const std::uint8_t* use, std::size_t n, int refineIterations, cv::Matx33d& h) noexcept;
};

}  // namespace marionette::ar
