#include "planar_pose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "homography_ransac.hpp"  // symmetricEigen, solveLinear
#include "perspective_warp.hpp"   // invertHomography

namespace marionette::ar {

cv::Matx33d rotationFromRodrigues(const cv::Vec3d& r) noexcept {
  const double t2 = r.dot(r), t = std::sqrt(t2);
  // R = I + a [r]x + b [r]x^2 with a = sin t / t, b = (1 - cos t) / t^2; series below 1e-4.
  const double a = t < 1e-4 ? 1 - t2 / 6 : std::sin(t) / t;
  const double b = t < 1e-4 ? 0.5 - t2 / 24 : (1 - std::cos(t)) / t2;
  const cv::Matx33d k(0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0);
  return cv::Matx33d::eye() + a * k + b * (k * k);
}

namespace {

cv::Matx33d fromQuaternion(double w, double x, double y, double z) noexcept {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  return cv::Matx33d(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
                     2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),  //
                     2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
}

}  // namespace

cv::Vec3d rodriguesFromRotation(const cv::Matx33d& m) noexcept {
  // Shepperd: the quaternion from its largest component, so no division by a small one.
  double w, x, y, z;
  const double tr = m(0, 0) + m(1, 1) + m(2, 2);
  if (tr >= m(0, 0) && tr >= m(1, 1) && tr >= m(2, 2)) {
    w = 0.5 * std::sqrt(std::max(0.0, 1 + tr));
    const double f = 0.25 / w;
    x = (m(2, 1) - m(1, 2)) * f, y = (m(0, 2) - m(2, 0)) * f, z = (m(1, 0) - m(0, 1)) * f;
  } else if (m(0, 0) >= m(1, 1) && m(0, 0) >= m(2, 2)) {
    x = 0.5 * std::sqrt(std::max(0.0, 1 + m(0, 0) - m(1, 1) - m(2, 2)));
    const double f = 0.25 / x;
    w = (m(2, 1) - m(1, 2)) * f, y = (m(0, 1) + m(1, 0)) * f, z = (m(0, 2) + m(2, 0)) * f;
  } else if (m(1, 1) >= m(2, 2)) {
    y = 0.5 * std::sqrt(std::max(0.0, 1 - m(0, 0) + m(1, 1) - m(2, 2)));
    const double f = 0.25 / y;
    w = (m(0, 2) - m(2, 0)) * f, x = (m(0, 1) + m(1, 0)) * f, z = (m(1, 2) + m(2, 1)) * f;
  } else {
    z = 0.5 * std::sqrt(std::max(0.0, 1 - m(0, 0) - m(1, 1) + m(2, 2)));
    const double f = 0.25 / z;
    w = (m(1, 0) - m(0, 1)) * f, x = (m(0, 2) + m(2, 0)) * f, y = (m(1, 2) + m(2, 1)) * f;
  }
  if (w < 0) w = -w, x = -x, y = -y, z = -z;  // the angle in [0, pi]
  const double s = std::sqrt(x * x + y * y + z * z);
  // angle / s = 2 atan2(s, w) / s, which tends to 2 / w as s -> 0.
  const double f = s > 1e-12 ? 2 * std::atan2(s, w) / s : 2 / std::max(w, 1e-300);
  return {x * f, y * f, z * f};
}

cv::Matx33d nearestRotation(const cv::Matx33d& m) noexcept {
  // Horn: trace(R^T m) = q^T N q for the unit quaternion q = (w, x, y, z); N's top eigenvector.
  const double xx = m(0, 0), xy = m(1, 0), xz = m(2, 0), yx = m(0, 1), yy = m(1, 1), yz = m(2, 1), zx = m(0, 2),
               zy = m(1, 2), zz = m(2, 2);
  const double n[16] = {xx + yy + zz, yz - zy,      zx - xz,       xy - yx,   //
                        yz - zy,      xx - yy - zz, xy + yx,       zx + xz,   //
                        zx - xz,      xy + yx,      -xx + yy - zz, yz + zy,   //
                        xy - yx,      zx + xz,      yz + zy,       -xx - yy + zz};
  double values[4], vectors[16];
  if (!symmetricEigen(4, n, values, vectors)) return cv::Matx33d::eye();
  const double* q = vectors + 12;
  return fromQuaternion(q[0], q[1], q[2], q[3]);
}

cv::Matx33d planeToImage(const cv::Matx33d& k, const PlanarPose& pose) noexcept {
  const cv::Matx33d r = rotationFromRodrigues(pose.rvec);
  const cv::Vec3d& t = pose.tvec;
  return k * cv::Matx33d(r(0, 0), r(0, 2), t[0], r(1, 0), r(1, 2), t[1], r(2, 0), r(2, 2), t[2]);
}

namespace {

cv::Vec3d column(const cv::Matx33d& m, int c) noexcept { return {m(0, c), m(1, c), m(2, c)}; }

bool finite(const cv::Matx33d& m) noexcept {
  for (double v : m.val)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

int planarPoseCandidates(const cv::Matx33d& k, const cv::Matx33d& planeToImage, cv::Point2f centre,
                         PlanarPose out[2]) noexcept {
  cv::Matx33d kInv;
  if (!finite(planeToImage) || !invertHomography(k, kInv)) return 0;
  const cv::Matx33d m = kInv * planeToImage;
  const cv::Vec3d m1 = column(m, 0), m2 = column(m, 1), m3 = column(m, 2);
  const double n = std::sqrt(cv::norm(m1) * cv::norm(m2));
  if (!(n > 0) || !std::isfinite(n)) return 0;
  // The sign that puts `centre` in front of the camera.
  const cv::Vec3d c = m1 * double(centre.x) + m2 * double(centre.y) + m3;
  const double s = (c[2] < 0 ? -1.0 : 1.0) / n;
  const cv::Vec3d a = m1 * s, b = m2 * s;
  // Plane frame (X, Z, normal) -> camera is [r1 r3 r1 x r3]; R's columns are r1, r2 = -(r1 x r3), r3.
  const cv::Vec3d ab = a.cross(b);
  const cv::Matx33d q = nearestRotation(cv::Matx33d(a[0], b[0], ab[0], a[1], b[1], ab[1], a[2], b[2], ab[2]));
  const cv::Matx33d r1(q(0, 0), -q(0, 2), q(0, 1), q(1, 0), -q(1, 2), q(1, 1), q(2, 0), -q(2, 2), q(2, 1));
  const cv::Vec3d t1 = m3 * s;
  out[0] = PlanarPose{rodriguesFromRotation(r1), t1};
  // The mirror: R2 = (I - 2 d d^T) R1 diag(1, -1, 1), d the ray to the centre. A step in the
  // plane then differs from R1's only along d, so the image is the same to first order.
  const cv::Vec3d w(centre.x, 0, centre.y);
  const cv::Vec3d p = r1 * w + t1;
  const double pn = cv::norm(p);
  if (!(pn > 0)) return 1;
  const cv::Vec3d d = p * (1 / pn);
  const cv::Matx33d reflect = cv::Matx33d::eye() - 2.0 * (cv::Matx31d(d) * cv::Matx13d(d[0], d[1], d[2]));
  const cv::Matx33d r2 = reflect * r1 * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, 1);
  out[1] = PlanarPose{rodriguesFromRotation(r2), p - r2 * w};
  return 2;
}

namespace {

struct Pairs {
  std::span<const cv::Point2f> plane, image;
  std::span<const std::uint8_t> mask;
  [[nodiscard]] bool used(std::size_t i) const noexcept { return mask.empty() || mask[i]; }
};

// Sum of squared reprojection errors; infinite when a point is not in front of the camera.
double cost(const cv::Matx33d& k, const cv::Matx33d& r, const cv::Vec3d& t, const Pairs& pairs) noexcept {
  double sum = 0;
  for (std::size_t i = 0; i < pairs.plane.size(); ++i) {
    if (!pairs.used(i)) continue;
    const cv::Vec3d p = r * cv::Vec3d(pairs.plane[i].x, 0, pairs.plane[i].y) + t;
    if (!(p[2] > 1e-9)) return HUGE_VAL;
    const double u = (k(0, 0) * p[0] + k(0, 1) * p[1]) / p[2] + k(0, 2) - pairs.image[i].x;
    const double v = k(1, 1) * p[1] / p[2] + k(1, 2) - pairs.image[i].y;
    sum += u * u + v * v;
  }
  return sum;
}

// The Jacobian of one pair's pixel (u, v) with respect to the step (w, dt) that turns R to
// exp([w]x) R and moves t to t + dt; q = R X is the plane point turned, p = q + t in the camera.
void pairJacobian(const cv::Matx33d& k, const cv::Vec3d& q, const cv::Vec3d& p, double ju[6], double jv[6]) noexcept {
  const double iz = 1 / p[2], x = p[0] * iz, y = p[1] * iz;
  // d(u, v)/dp, then dp/dw = -[q]x and dp/dt = I.
  const double du[3] = {k(0, 0) * iz, k(0, 1) * iz, -(k(0, 0) * x + k(0, 1) * y) * iz};
  const double dv[3] = {0, k(1, 1) * iz, -k(1, 1) * y * iz};
  ju[0] = -du[1] * q[2] + du[2] * q[1], ju[1] = du[0] * q[2] - du[2] * q[0], ju[2] = -du[0] * q[1] + du[1] * q[0];
  jv[0] = -dv[1] * q[2] + dv[2] * q[1], jv[1] = dv[0] * q[2] - dv[2] * q[0], jv[2] = -dv[0] * q[1] + dv[1] * q[0];
  for (int c = 0; c < 3; ++c) ju[3 + c] = du[c], jv[3 + c] = dv[c];
}

bool usable(const Pairs& pairs, std::size_t& used) noexcept {
  used = 0;
  if (pairs.plane.size() != pairs.image.size() || (!pairs.mask.empty() && pairs.mask.size() < pairs.plane.size()))
    return false;
  for (std::size_t i = 0; i < pairs.plane.size(); ++i) {
    if (!pairs.used(i)) continue;
    const cv::Point2f a = pairs.plane[i], b = pairs.image[i];
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y)) return false;
    ++used;
  }
  return used >= 4;
}

}  // namespace

bool refinePlanarPose(const cv::Matx33d& k, std::span<const cv::Point2f> plane, std::span<const cv::Point2f> image,
                      std::span<const std::uint8_t> mask, const PoseRefineOptions& params, PlanarPose& pose) noexcept {
  const Pairs pairs{plane, image, mask};
  std::size_t used = 0;
  if (!usable(pairs, used) || !finite(k) || !std::isfinite(cv::norm(pose.rvec)) || !std::isfinite(cv::norm(pose.tvec)))
    return false;
  cv::Matx33d r = rotationFromRodrigues(pose.rvec);
  cv::Vec3d t = pose.tvec;
  double current = cost(k, r, t, pairs), lambda = 1e-3;
  if (!std::isfinite(current)) return false;
  for (int it = 0; it < params.maxIterations && current > 0; ++it) {
    // Normal equations of the step (w, dt): R <- exp([w]x) R, t <- t + dt.
    double jtj[36] = {}, jtr[6] = {};
    for (std::size_t i = 0; i < plane.size(); ++i) {
      if (!pairs.used(i)) continue;
      const cv::Vec3d q = r * cv::Vec3d(plane[i].x, 0, plane[i].y), p = q + t;
      const double iz = 1 / p[2], x = p[0] * iz, y = p[1] * iz;
      const double ru = k(0, 0) * x + k(0, 1) * y + k(0, 2) - image[i].x, rv = k(1, 1) * y + k(1, 2) - image[i].y;
      double ju[6], jv[6];
      pairJacobian(k, q, p, ju, jv);
      for (int a = 0; a < 6; ++a) {
        jtr[a] += ju[a] * ru + jv[a] * rv;
        for (int b = a; b < 6; ++b) jtj[a * 6 + b] += ju[a] * ju[b] + jv[a] * jv[b];
      }
    }
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < a; ++b) jtj[a * 6 + b] = jtj[b * 6 + a];
    bool improved = false;
    double stepLength = 0;
    while (!improved && lambda < 1e12) {
      double step[6];
      if (!dampedStep(6, jtj, jtr, lambda, 1e-15, step)) {
        lambda *= 10;
        continue;
      }
      const cv::Matx33d rt = rotationFromRodrigues(cv::Vec3d(step[0], step[1], step[2])) * r;
      const cv::Vec3d tt = t + cv::Vec3d(step[3], step[4], step[5]);
      const double c = cost(k, rt, tt, pairs);
      if (c < current) {
        r = rt, t = tt, current = c;
        lambda = std::max(lambda * 0.1, 1e-15);
        improved = true;
        stepLength = 0;
        for (double s : step) stepLength += s * s;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || std::sqrt(stepLength) < params.epsilon) break;
  }
  const cv::Vec3d rvec = rodriguesFromRotation(nearestRotation(r));
  if (!std::isfinite(cv::norm(rvec)) || !std::isfinite(cv::norm(t))) return false;
  pose = PlanarPose{rvec, t};
  return true;
}

bool planarPoseCovariance(const cv::Matx33d& k, std::span<const cv::Point2f> plane, std::span<const cv::Point2f> image,
                          std::span<const std::uint8_t> mask, const PlanarPose& pose, double sigmaPx,
                          double effectivePoints, double covariance[36]) noexcept {
  const Pairs pairs{plane, image, mask};
  std::size_t used = 0;
  if (!usable(pairs, used) || !finite(k) || !(sigmaPx > 0) || !(effectivePoints > 0)) return false;
  const cv::Matx33d r = rotationFromRodrigues(pose.rvec);
  const cv::Vec3d t = pose.tvec;
  double jtj[36] = {};
  for (std::size_t i = 0; i < plane.size(); ++i) {
    if (!pairs.used(i)) continue;
    const cv::Vec3d q = r * cv::Vec3d(plane[i].x, 0, plane[i].y), p = q + t;
    if (!(p[2] > 1e-9)) return false;
    double ju[6], jv[6];
    pairJacobian(k, q, p, ju, jv);  // the refinement's (refinePlanarPose)
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) jtj[a * 6 + b] += ju[a] * ju[b] + jv[a] * jv[b];
  }
  const double scale = std::min(1.0, effectivePoints / double(used));
  // Sigma = sigma^2 (scale J^T J)^-1, column by column.
  double sigma[36];
  for (int c = 0; c < 6; ++c) {
    double a[36], b[6] = {};
    for (int e = 0; e < 36; ++e) a[e] = jtj[e] * scale;
    b[c] = sigmaPx * sigmaPx;
    if (!solveLinear(6, a, b, 1e-14)) return false;
    for (int row = 0; row < 6; ++row) sigma[row * 6 + c] = b[row];
  }
  // To the world: a step (w, dt) turns camera-to-world R^T by -R^T w (in world axes) and
  // moves the centre c = -R^T t by dc = -R^T (dt + w x t) = R^T [t]x w - R^T dt.
  // J = [[-R^T, 0], [R^T [t]x, -R^T]].
  const cv::Matx33d rt = r.t();
  const cv::Matx33d tx(0, -t[2], t[1], t[2], 0, -t[0], -t[1], t[0], 0);
  const cv::Matx33d rtTx = rt * tx;
  double j[36] = {};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      j[a * 6 + b] = -rt(a, b);
      j[(a + 3) * 6 + b] = rtTx(a, b);
      j[(a + 3) * 6 + b + 3] = -rt(a, b);
    }
  double js[36] = {};
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      for (int e = 0; e < 6; ++e) js[a * 6 + b] += j[a * 6 + e] * sigma[e * 6 + b];
  double out[36] = {};
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      for (int e = 0; e < 6; ++e) out[a * 6 + b] += js[a * 6 + e] * j[b * 6 + e];
  for (int e = 0; e < 36; ++e)
    if (!std::isfinite(out[e])) return false;
  std::copy(out, out + 36, covariance);
  return true;
}

bool planarPoseFromHomography(const cv::Matx33d& k, const cv::Matx33d& planeToImage, std::span<const cv::Point2f> plane,
                              std::span<const cv::Point2f> image, std::span<const std::uint8_t> mask,
                              const PoseRefineOptions& params, PlanarPose& out, double& rmsPx) noexcept {
  const Pairs pairs{plane, image, mask};
  std::size_t used = 0;
  if (!usable(pairs, used)) return false;
  double cx = 0, cz = 0;
  for (std::size_t i = 0; i < plane.size(); ++i)
    if (pairs.used(i)) cx += plane[i].x, cz += plane[i].y;
  const cv::Point2f centre(static_cast<float>(cx / double(used)), static_cast<float>(cz / double(used)));
  PlanarPose candidates[2];
  const int count = planarPoseCandidates(k, planeToImage, centre, candidates);
  double best = HUGE_VAL;
  for (int c = 0; c < count; ++c) {
    PlanarPose p = candidates[c];
    if (!refinePlanarPose(k, plane, image, mask, params, p)) continue;
    const double rms = reprojectionRms(k, p, plane, image, mask);
    if (rms < best) {  // NaN never wins
      best = rms;
      out = p;
    }
  }
  if (!std::isfinite(best)) return false;
  rmsPx = best;
  return true;
}

void projectPlanePoints(const cv::Matx33d& k, const PlanarPose& pose, std::span<const cv::Point2f> plane,
                        std::span<cv::Point2f> out) noexcept {
  const cv::Matx33d r = rotationFromRodrigues(pose.rvec);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < plane.size() && i < out.size(); ++i) {
    const cv::Vec3d p = r * cv::Vec3d(plane[i].x, 0, plane[i].y) + pose.tvec;
    if (!(p[2] > 0)) {
      out[i] = {nan, nan};
      continue;
    }
    out[i] = {static_cast<float>((k(0, 0) * p[0] + k(0, 1) * p[1]) / p[2] + k(0, 2)),
              static_cast<float>(k(1, 1) * p[1] / p[2] + k(1, 2))};
  }
}

double reprojectionRms(const cv::Matx33d& k, const PlanarPose& pose, std::span<const cv::Point2f> plane,
                       std::span<const cv::Point2f> image, std::span<const std::uint8_t> mask) noexcept {
  const Pairs pairs{plane, image, mask};
  std::size_t used = 0;
  for (std::size_t i = 0; i < plane.size() && i < image.size(); ++i) used += pairs.used(i);
  if (used == 0 || plane.size() != image.size()) return std::numeric_limits<double>::quiet_NaN();
  const double c = cost(k, rotationFromRodrigues(pose.rvec), pose.tvec, pairs);
  return std::isfinite(c) ? std::sqrt(c / double(used)) : std::numeric_limits<double>::quiet_NaN();
}

void addIsotropicVariance(double covariance[36], double rotationRad2, double positionM2) noexcept {
  for (int i = 0; i < 3; ++i) {
    covariance[i * 7] += rotationRad2 / 3;
    covariance[21 + i * 7] += positionM2 / 3;
  }
}

void covarianceSigmas(const double covariance[36], double& positionM, double& rotationDeg) noexcept {
  positionM = std::sqrt(covariance[21] + covariance[28] + covariance[35]);
  rotationDeg = std::sqrt(covariance[0] + covariance[7] + covariance[14]) * (180.0 / 3.14159265358979323846);
}

}  // namespace marionette::ar
