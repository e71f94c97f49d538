// The camera pose over the ground plane from a plane homography and matched points,
// replacing cv::solvePnP(SOLVEPNP_IPPE) + cv::solvePnPRefineLM + cv::projectPoints (and
// cv::Rodrigues) in the markerless tracker's per frame path: no allocation, no exception.
// World points are (X, 0, Z) for plane points (X, Z); poses are PlanarPose's (world ->
// OpenCV camera). K is a pinhole (undistorted frames).
#pragma once
#include <cstdint>
#include <span>

#include <opencv2/core.hpp>

#include "planar_geometry.hpp"

namespace marionette::ar {

// Rotation vector (axis times angle, radians) <-> matrix. Exact at and near 0 (series) and
// near pi (through the quaternion, whose largest component is taken: no division by sin).
[[nodiscard]] cv::Matx33d rotationFromRodrigues(const cv::Vec3d& rvec) noexcept;
[[nodiscard]] cv::Vec3d rodriguesFromRotation(const cv::Matx33d& r) noexcept;
// The rotation nearest (Frobenius) to m, det +1 (the quaternion that maximizes trace(R^T m)).
[[nodiscard]] cv::Matx33d nearestRotation(const cv::Matx33d& m) noexcept;

// K [r1 r3 t]: plane (X, Z, 1) -> pixel, as planeToImageHomography (whose cv::Rodrigues
// allocates) without allocating.
[[nodiscard]] cv::Matx33d planeToImage(const cv::Matx33d& k, const PlanarPose& pose) noexcept;

// The two poses a plane-to-image homography allows (IPPE's ambiguity): the decomposition
// K^-1 H = s [r1 r3 t], then its mirror about the ray to plane point `centre`, which images
// the plane alike to first order there. Returns how many (0 when H or K is unusable).
int planarPoseCandidates(const cv::Matx33d& k, const cv::Matx33d& planeToImage, cv::Point2f centre,
                         PlanarPose out[2]) noexcept;

struct PoseRefineOptions {
  int maxIterations = 20;   // Levenberg-Marquardt steps
  double epsilon = 1e-10;   // stop when a step is shorter than this (radians + metres)
};

// Levenberg-Marquardt on the 6-DOF reprojection error of the pairs with mask[i] != 0 (all
// when mask is empty) from `pose`. False (pose untouched) for fewer than 4 pairs, non-finite
// input, or a pose that puts a point behind the camera at the start.
bool refinePlanarPose(const cv::Matx33d& k, std::span<const cv::Point2f> plane, std::span<const cv::Point2f> image,
                      std::span<const std::uint8_t> mask, const PoseRefineOptions& params, PlanarPose& pose) noexcept;

// Both candidates refined, the one with the smaller reprojection error kept (its rms in
// pixels): what solvePnP(IPPE) + solvePnPRefineLM give.
bool planarPoseFromHomography(const cv::Matx33d& k, const cv::Matx33d& planeToImage, std::span<const cv::Point2f> plane,
                              std::span<const cv::Point2f> image, std::span<const std::uint8_t> mask,
                              const PoseRefineOptions& params, PlanarPose& out, double& rmsPx) noexcept;

// The covariance of `pose` fitted to the used pairs, to first order: sigmaPx^2 (J^T J)^-1 in the
// refinement's parameters, the normal equations scaled by effectivePoints / used (feature
// errors are correlated: blur, a misaligned template move many together), then mapped to the
// world: row-major 6x6 of (rotation vector in world axes, radians; camera position, metres).
// False (covariance untouched) for fewer than 4 pairs, a point behind the camera, or a
// singular system (the pairs do not constrain the pose).
bool planarPoseCovariance(const cv::Matx33d& k, std::span<const cv::Point2f> plane, std::span<const cv::Point2f> image,
                          std::span<const std::uint8_t> mask, const PlanarPose& pose, double sigmaPx,
                          double effectivePoints, double covariance[36]) noexcept;

// The square roots of the traces of a covariance in that layout: the camera position's
// standard deviation (metres) and the orientation's (degrees).
void covarianceSigmas(const double covariance[36], double& positionM, double& rotationDeg) noexcept;
// Adds a rotation variance (radians^2) and a position variance (metres^2) spread evenly over the
// three axes: the traces, so covarianceSigmas' squares, grow by exactly those.
void addIsotropicVariance(double covariance[36], double rotationRad2, double positionM2) noexcept;

// Pixels of plane points (X, Z) under the pose; a point on or behind the camera plane gives NaN.
void projectPlanePoints(const cv::Matx33d& k, const PlanarPose& pose, std::span<const cv::Point2f> plane,
                        std::span<cv::Point2f> out) noexcept;
// Root-mean-square distance (pixels) between the projections and `image` over the used pairs;
// NaN when there is none or a point is behind the camera.
[[nodiscard]] double reprojectionRms(const cv::Matx33d& k, const PlanarPose& pose, std::span<const cv::Point2f> plane,
                                     std::span<const cv::Point2f> image, std::span<const std::uint8_t> mask) noexcept;

}  // namespace marionette::ar
