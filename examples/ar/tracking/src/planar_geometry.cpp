#include "planar_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "marionette_ar/tracking/tracker.hpp"
#include "perspective_warp.hpp"
#include "planar_pose.hpp"

namespace marionette::ar {

namespace {

// planar_pose's conversions: cv::Rodrigues allocates.
cv::Matx33d rotation(const cv::Vec3d& rvec) { return rotationFromRodrigues(rvec); }

}  // namespace

cv::Point2f applyHomography(const cv::Matx33d& h, const cv::Point2f& p) noexcept {
  const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
  return {static_cast<float>(q[0] / q[2]), static_cast<float>(q[1] / q[2])};
}

cv::Matx33d planeToImageHomography(const cv::Matx33d& k, const PlanarPose& pose) { return planeToImage(k, pose); }

bool poseFromPlaneHomography(const cv::Matx33d& k, const cv::Matx33d& h, PlanarPose& pose) {
  cv::Matx33d m = k.inv() * h;
  const double s = 1.0 / std::sqrt(cv::norm(cv::Vec3d(m(0, 0), m(1, 0), m(2, 0))) *
                                    cv::norm(cv::Vec3d(m(0, 1), m(1, 1), m(2, 1))));
  m *= (m(2, 2) < 0 ? -s : s);  // the plane in front of the camera
  const cv::Vec3d r1(m(0, 0), m(1, 0), m(2, 0)), r3(m(0, 1), m(1, 1), m(2, 1));
  const cv::Vec3d r2 = r3.cross(r1);  // r1 x r2 = r3 for a right-handed rotation
  const cv::Matx33d r(r1[0], r2[0], r3[0], r1[1], r2[1], r3[1], r1[2], r2[2], r3[2]);
  const cv::Vec3d rvec = rodriguesFromRotation(nearestRotation(r));
  pose.rvec = rvec;
  pose.tvec = cv::Vec3d(m(0, 2), m(1, 2), m(2, 2));
  return std::isfinite(rvec[0]) && std::isfinite(pose.tvec[2]);
}

glm::dvec3 cameraPosition(const PlanarPose& pose) {
  const cv::Matx33d r = rotation(pose.rvec);
  const cv::Vec3d c = -(r.t() * pose.tvec);
  return {c[0], c[1], c[2]};
}

glm::dmat4 cameraToWorld(const PlanarPose& pose) {
  const cv::Matx33d r = rotation(pose.rvec);
  glm::dmat3 g;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) g[c][row] = r(row, c);
  return cameraToWorldFromOpenCv(g, glm::dvec3(pose.tvec[0], pose.tvec[1], pose.tvec[2]));
}

double homographyScaleAt(const cv::Matx33d& h, const cv::Point2f& p) noexcept {
  const cv::Point2f a = applyHomography(h, p), bx = applyHomography(h, p + cv::Point2f(1, 0)),
                    by = applyHomography(h, p + cv::Point2f(0, 1));
  const double j00 = bx.x - a.x, j10 = bx.y - a.y, j01 = by.x - a.x, j11 = by.y - a.y;
  return std::sqrt(std::abs(j00 * j11 - j01 * j10));
}

namespace {

// Mean and variance of the pixels within `half` of p (clipped to the image), accumulated.
void accumulatePatch(const cv::Mat& image, const cv::Point2f& p, int half, double& sum, double& sumSq, double& n) {
  const int x0 = static_cast<int>(p.x), y0 = static_cast<int>(p.y);
  for (int y = std::max(0, y0 - half); y <= std::min(image.rows - 1, y0 + half); ++y) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(y);
    for (int x = std::max(0, x0 - half); x <= std::min(image.cols - 1, x0 + half); ++x) {
      sum += row[x];
      sumSq += double(row[x]) * row[x];
      n += 1;
    }
  }
}

}  // namespace

bool matchGain(const cv::Mat& source, const std::vector<cv::Point2f>& sourcePoints, const cv::Mat& frame,
               const std::vector<cv::Point2f>& framePoints, int window, double& gain, double& bias) {
  gain = 1;
  bias = 0;
  double ss = 0, sss = 0, ns = 0, sf = 0, sff = 0, nf = 0;
  const int half = std::max(2, window / 4);
  const std::size_t step = std::max<std::size_t>(1, framePoints.size() / 40);
  for (std::size_t i = 0; i < framePoints.size() && i < sourcePoints.size(); i += step) {
    accumulatePatch(source, sourcePoints[i], half, ss, sss, ns);
    accumulatePatch(frame, framePoints[i], half, sf, sff, nf);
  }
  if (ns < 25 || nf < 25) return false;
  const double ms = ss / ns, mf = sf / nf;
  const double ds = std::sqrt(std::max(1e-6, sss / ns - ms * ms)), df = std::sqrt(std::max(1e-6, sff / nf - mf * mf));
  gain = std::clamp(df / ds, 0.25, 4.0);
  bias = mf - gain * ms;
  return true;
}

void PlanarPoseSolver::reserve(std::size_t maxPoints) {
  ransac.reserve(maxPoints);
  plane.reserve(maxPoints);
  image.reserve(maxPoints);
}

bool robustPlanarPose(const cv::Matx33d& k, const std::vector<cv::Point2f>& plane,
                      const std::vector<cv::Point2f>& image, double thresholdPx, double maxDistance,
                      PlanarPoseSolver& solver, std::vector<unsigned char>& mask, PlanarPose& out, double& rmsPx,
                      int& inliers, cv::Matx33d* homography) noexcept {
  inliers = 0;
  if (plane.size() < 6 || plane.size() != image.size() || plane.size() > solver.ransac.capacity() ||
      plane.size() > mask.capacity())
    return false;
  mask.resize(plane.size());  // within capacity: no allocation
  HomographyRansacOptions params;
  params.thresholdPx = thresholdPx;
  cv::Matx33d h;
  int found = 0;
  if (!solver.ransac.estimate(plane, image, params, h, mask, found)) return false;
  if (homography) *homography = h;
  solver.plane.clear();
  solver.image.clear();
  for (std::size_t i = 0; i < plane.size(); ++i)
    if (mask[i]) {
      solver.plane.push_back(plane[i]);
      solver.image.push_back(image[i]);
    }
  const std::vector<cv::Point2f>& pixels = solver.image;
  if (pixels.size() < 6) return false;
  // The spread of the inliers: the smaller eigenvalue of their covariance.
  double mx = 0, my = 0;
  for (const cv::Point2f& p : pixels) {
    mx += p.x;
    my += p.y;
  }
  const double n = static_cast<double>(pixels.size());
  mx /= n;
  my /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (const cv::Point2f& p : pixels) {
    sxx += (p.x - mx) * (p.x - mx);
    syy += (p.y - my) * (p.y - my);
    sxy += (p.x - mx) * (p.y - my);
  }
  sxx /= n;
  syy /= n;
  sxy /= n;
  const double smallest = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  if (!(smallest >= 64.0)) return false;
  // IPPE's two candidates refined by Levenberg-Marquardt, the better kept (planar_pose.hpp).
  PlanarPose pose;
  double rms = 0;
  if (!planarPoseFromHomography(k, h, solver.plane, pixels, {}, PoseRefineOptions{}, pose, rms)) return false;
  const glm::dvec3 centre = cameraPosition(pose);
  if (!(centre.y > 1e-3) || !(glm::length(centre) <= maxDistance)) return false;  // seen from above, near enough
  if (!std::isfinite(rms)) return false;
  rmsPx = rms;
  out = pose;
  inliers = static_cast<int>(pixels.size());
  return true;
}

namespace {

// The target's 10 x 10 sample points (cell centres) that land within the image grown by margin.
int targetSamplesInView(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose, double width,
                        double height, double margin) {
  const cv::Matx33d g = planeToImageHomography(k, pose);
  constexpr int kGrid = 10;
  int inside = 0;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double x = ((i + 0.5) / kGrid - 0.5) * width, z = ((j + 0.5) / kGrid - 0.5) * height;
      const cv::Vec3d q = g * cv::Vec3d(x, z, 1.0);
      if (q[2] <= 0) continue;
      const double u = q[0] / q[2], v = q[1] / q[2];
      inside += u >= -margin && v >= -margin && u < camera.width + margin && v < camera.height + margin;
    }
  return inside;
}

}  // namespace

double visibleTargetFraction(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose, double width,
                             double height) {
  return targetSamplesInView(k, camera, pose, width, height, 0.0) / 100.0;
}

double targetImageShare(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose, double width,
                        double height) {
  const cv::Matx33d g = planeToImageHomography(k, pose);
  cv::Matx33d toPlane;
  if (!invertHomography(g, toPlane)) return 0;  // a camera in the plane: no target to cover the view
  constexpr int kColumns = 16, kRows = 12;
  int inside = 0;
  for (int i = 0; i < kColumns; ++i)
    for (int j = 0; j < kRows; ++j) {
      const cv::Vec3d q = toPlane * cv::Vec3d((i + 0.5) * camera.width / kColumns - 0.5,
                                              (j + 0.5) * camera.height / kRows - 0.5, 1.0);
      if (!(std::abs(q[2]) > 1e-12)) continue;
      const double x = q[0] / q[2], z = q[1] / q[2];
      // Where the ray meets the plane behind the camera (past the horizon), the point's depth is negative.
      inside += (g * cv::Vec3d(x, z, 1.0))[2] > 0 && std::abs(x) <= 0.5 * width && std::abs(z) <= 0.5 * height;
    }
  return inside / static_cast<double>(kColumns * kRows);
}

bool targetNearView(const cv::Matx33d& k, const CameraModel& camera, const PlanarPose& pose, double width, double height,
                    double marginPx) {
  return targetSamplesInView(k, camera, pose, width, height, marginPx) > 0;
}

PlanarPose extrapolateFrom(const PlanarPose& a, double ta, const PlanarPose& b, double tb, const PlanarPose& base,
                           double tbase, double t) {
  const double ratio = tb > ta ? std::clamp((t - tbase) / (tb - ta), 0.0, 8.0) : 0.0;
  const cv::Matx33d ra = rotation(a.rvec), rb = rotation(b.rvec);
  const cv::Matx33d delta = rb * ra.t();  // x_b = delta x_a + (tb - delta ta)
  const cv::Vec3d deltaRvec = rodriguesFromRotation(delta);
  const cv::Vec3d deltaT = b.tvec - delta * a.tvec;
  const cv::Matx33d step = rotation(deltaRvec * ratio);
  PlanarPose out;
  out.rvec = rodriguesFromRotation(step * rotation(base.rvec));
  out.tvec = step * base.tvec + deltaT * ratio;
  return out;
}

PlanarPose extrapolate(const PlanarPose& a, double ta, const PlanarPose& b, double tb, double t) {
  return extrapolateFrom(a, ta, b, tb, b, tb, t);
}

double rotationBetweenDeg(const PlanarPose& a, const PlanarPose& b) {
  return cv::norm(rodriguesFromRotation(rotation(a.rvec) * rotation(b.rvec).t())) * 180.0 / 3.14159265358979323846;
}

bool posesAgree(const PlanarPose& a, const PlanarPose& b, double fraction, double degrees) {
  const glm::dvec3 ca = cameraPosition(a), cb = cameraPosition(b);
  if (glm::length(ca - cb) > fraction * std::max(0.05, glm::length(cb))) return false;
  const cv::Matx33d d = rotation(a.rvec) * rotation(b.rvec).t();
  const double c = std::clamp((d(0, 0) + d(1, 1) + d(2, 2) - 1) * 0.5, -1.0, 1.0);
  return std::acos(c) < degrees * 3.14159265358979323846 / 180.0;
}

}  // namespace marionette::ar
