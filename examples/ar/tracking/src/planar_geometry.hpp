// Geometry of a camera over the world's ground plane Y = 0 (plane coordinates (X, Z)),
// shared by the markerless tracker's tracking and relocalization.
#pragma once
#include <vector>

#include <glm/mat4x4.hpp>
#include <opencv2/core.hpp>

#include "homography_ransac.hpp"
#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar {

// World -> OpenCV camera, as solvePnP gives it.
struct PlanarPose {
  cv::Vec3d rvec{0, 0, 0}, tvec{0, 0, 1};
};

[[nodiscard]] cv::Point2f applyHomography(const cv::Matx33d& h, const cv::Point2f& p) noexcept;
// K [r1 r3 t]: plane (X, Z, 1) -> pixel.
[[nodiscard]] cv::Matx33d planeToImageHomography(const cv::Matx33d& k, const PlanarPose& pose);
// The inverse, for a homography known to be K [r1 r3 t] up to scale (a keyframe's).
[[nodiscard]] bool poseFromPlaneHomography(const cv::Matx33d& k, const cv::Matx33d& h, PlanarPose& pose);
[[nodiscard]] glm::dvec3 cameraPosition(const PlanarPose& pose);
[[nodiscard]] glm::dmat4 cameraToWorld(const PlanarPose& pose);
// sqrt(|det J|) of the homography at p: how much it scales lengths there.
[[nodiscard]] double homographyScaleAt(const cv::Matx33d& h, const cv::Point2f& p) noexcept;
// The gain and bias that give the patches of `source` around `sourcePoints` the frame's mean
// and contrast around `framePoints`: KLT assumes constant brightness, a camera's exposure
// does not keep it. False when there is too little to measure (gain 1, bias 0).
bool matchGain(const cv::Mat& source, const std::vector<cv::Point2f>& sourcePoints, const cv::Mat& frame,
               const std::vector<cv::Point2f>& framePoints, int window, double& gain, double& bias);
// robustPlanarPose's buffers, sized once (reserve) for the most points it is given.
struct PlanarPoseSolver {
  HomographyRansac ransac;
  std::vector<cv::Point2f> plane, image;  // the inliers
  void reserve(std::size_t maxPoints);
};

// RANSAC homography plane -> image, then IPPE's two poses refined by Levenberg-Marquardt on the
// inliers (homography_ransac.hpp, planar_pose.hpp). False when fewer than 6 points agree, when
// they bunch up (less than 8 px of spread across their narrowest direction: any homography fits
// a cluster), when the camera would be under the plane or farther than `maxDistance` from the
// origin, or when there are more points than `solver` and `mask` were reserved for. `mask`
// gets the inliers. Allocates nothing.
[[nodiscard]] bool robustPlanarPose(const cv::Matx33d& k, const std::vector<cv::Point2f>& plane,
                                    const std::vector<cv::Point2f>& image, double thresholdPx, double maxDistance,
                                    PlanarPoseSolver& solver, std::vector<unsigned char>& mask, PlanarPose& out,
                                    double& rmsPx, int& inliers, cv::Matx33d* homography = nullptr) noexcept;
// The share of the image the target covers (a 16 x 12 grid of the image's cells, their centres
// taken back to the plane): what is left of the view is the floor around it.
[[nodiscard]] double targetImageShare(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose,
                                      double width, double height);
// The share of the target rectangle (width x height metres, centred) inside the image.
[[nodiscard]] double visibleTargetFraction(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose,
                                           double width, double height);
// Whether any of those sample points lands within the image grown by marginPx on every side.
[[nodiscard]] bool targetNearView(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose, double width,
                                  double height, double marginPx);
// Constant velocity: the motion from a to b continued to time t (at most 8 times the a-b step).
[[nodiscard]] PlanarPose extrapolate(const PlanarPose& a, double ta, const PlanarPose& b, double tb, double t);
// The same velocity applied to `base` (taken at tbase) instead of b.
[[nodiscard]] PlanarPose extrapolateFrom(const PlanarPose& a, double ta, const PlanarPose& b, double tb,
                                         const PlanarPose& base, double tbase, double t);
// The angle between two poses' rotations, degrees (atan2 form: exact for small angles).
[[nodiscard]] double rotationBetweenDeg(const PlanarPose& a, const PlanarPose& b);
// Camera centres within `fraction` of the distance to the origin and rotations within `degrees`.
[[nodiscard]] bool posesAgree(const PlanarPose& a, const PlanarPose& b, double fraction, double degrees = 3.0);

}  // namespace marionette::ar
