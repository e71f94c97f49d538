#include "tracking/synthetic_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <glm/mat3x3.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace marionette::ar::synthetic {

namespace {

constexpr int kSupersample = 2;
// The 2x2 supersample positions sub-frame k of an exposure takes (k % 4), in an order whose
// first two are already a diagonal pair; targetCoverage counts the same samples.
constexpr int kPhase[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
constexpr int kFloorLevels = 6;  // floor pyramid levels; beyond them the floor's mean colour
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

cv::Mat toRgbFloat(const cv::Mat& image, const char* what) {
  if (image.empty() || image.depth() != CV_8U || !(image.channels() == 1 || image.channels() == 3))
    throw std::invalid_argument(std::string(what) + " must be a non-empty 8-bit grey or RGB image");
  cv::Mat rgb;
  if (image.channels() == 1) cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB);
  else rgb = image;
  cv::Mat f;
  rgb.convertTo(f, CV_32FC3);
  return f;
}

// OpenCV's radial-tangential model on normalized coordinates, and its Jacobian.
struct Lens {
  double k1, k2, p1, p2, k3;
  explicit Lens(const CameraModel& c)
      : k1(c.distortion[0]), k2(c.distortion[1]), p1(c.distortion[2]), p2(c.distortion[3]), k3(c.distortion[4]) {}
  void distort(double x, double y, double& xd, double& yd, double j[4]) const {
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dRadial = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // d radial / d r2
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    j[0] = radial + 2 * x * x * dRadial + 2 * p1 * y + 6 * p2 * x;
    j[1] = 2 * x * y * dRadial + 2 * p1 * x + 2 * p2 * y;
    j[2] = j[1];
    j[3] = radial + 2 * y * y * dRadial + 6 * p1 * y + 2 * p2 * x;
  }
  // Newton from the distorted point; false when it does not converge or leaves the
  // physical (monotonic) branch of the radial model.
  bool undistort(double xd, double yd, double maxRadius, double& x, double& y) const {
    x = xd;
    y = yd;
    for (int it = 0; it < 60; ++it) {
      double fx, fy, j[4];
      distort(x, y, fx, fy, j);
      const double ex = fx - xd, ey = fy - yd;
      const double det = j[0] * j[3] - j[1] * j[2];
      if (!(det > 1e-9)) return false;
      const double dx = (j[3] * ex - j[1] * ey) / det, dy = (j[0] * ey - j[2] * ex) / det;
      x -= dx;
      y -= dy;
      if (!(x * x + y * y <= 4 * maxRadius * maxRadius)) return false;
      if (std::abs(dx) + std::abs(dy) < 1e-15) break;
    }
    double fx, fy, j[4];
    distort(x, y, fx, fy, j);
    return std::hypot(fx - xd, fy - yd) < 1e-11 && x * x + y * y <= maxRadius * maxRadius &&
           j[0] * j[3] - j[1] * j[2] > 0;
  }
};

// Bilinear fetch at (x, y) (pixel centres at integers), edges replicated or wrapped.
inline cv::Vec3f fetch(const cv::Mat& img, double x, double y, bool wrap) {
  const int w = img.cols, h = img.rows;
  if (wrap) {  // fmod returns x itself when |x| < w: the call only when it does more
    if (!(std::abs(x) < w)) x = std::fmod(x, w);
    if (x < 0) x += w;
    if (!(std::abs(y) < h)) y = std::fmod(y, h);
    if (y < 0) y += h;
  } else {
    x = std::clamp(x, 0.0, w - 1.0);
    y = std::clamp(y, 0.0, h - 1.0);
  }
  int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float ax = static_cast<float>(x - x0), ay = static_cast<float>(y - y0);
  int x1 = x0 + 1, y1 = y0 + 1;
  if (wrap) {  // x0 in [0, w] and x1 in [1, w + 1] (x + w may round up to w): at most one wrap
    if (x0 >= w) x0 -= w;
    if (x1 >= w) x1 -= w;
    if (y0 >= h) y0 -= h;
    if (y1 >= h) y1 -= h;
  } else {
    x1 = std::min(x1, w - 1);
    y1 = std::min(y1, h - 1);
  }
  const auto* r0 = img.ptr<cv::Vec3f>(y0);
  const auto* r1 = img.ptr<cv::Vec3f>(y1);
  return (r0[x0] * (1 - ax) + r0[x1] * ax) * (1 - ay) + (r1[x0] * (1 - ax) + r1[x1] * ax) * ay;
}

// Trilinear: level log2(footprint) between the two nearest pyramid levels (level l holds
// pixel 2^l x of level 0 at x, as pyrDown decimates the even pixels).
cv::Vec3f fetchFiltered(const std::vector<cv::Mat>& levels, const cv::Vec3f& mean, double x, double y,
                        double footprintTexels, bool wrap, int fadeLevels) {
  const double lod = footprintTexels > 1 ? std::log2(footprintTexels) : 0.0;
  const int last = static_cast<int>(levels.size()) - 1;
  if (lod >= last + fadeLevels) return mean;
  const int l0 = std::min(static_cast<int>(lod), last);
  const int l1 = std::min(l0 + 1, last);
  const float a = static_cast<float>(std::clamp(lod - l0, 0.0, 1.0));
  const double s0 = 1.0 / (1 << l0), s1 = 1.0 / (1 << l1);  // exact, as ldexp; cheaper
  cv::Vec3f c = fetch(levels[l0], x * s0, y * s0, wrap) * (1 - a);
  if (a > 0) c += fetch(levels[l1], x * s1, y * s1, wrap) * a;
  if (fadeLevels > 0 && lod > last) {  // past the coarsest level: fade into the mean
    const float m = static_cast<float>((lod - last) / fadeLevels);
    c = c * (1 - m) + mean * m;
  }
  return c;
}

cv::Vec3f toVec3f(const cv::Vec3b& c) { return {float(c[0]), float(c[1]), float(c[2])}; }

cv::Mat lineKernel(double length, double angleDeg) {
  const int half = static_cast<int>(std::ceil(length / 2));
  const int size = 2 * half + 1;
  cv::Mat k = cv::Mat::zeros(size, size, CV_32F);
  const double a = angleDeg * CV_PI / 180.0, ca = std::cos(a), sa = std::sin(a);
  const int n = static_cast<int>(std::ceil(length * 16));
  for (int i = 0; i < n; ++i) {  // splat points spaced evenly along the segment
    const double t = ((i + 0.5) / n - 0.5) * length;
    const double x = half + t * ca, y = half + t * sa;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int xx = x0 + dx, yy = y0 + dy;
        if (xx < 0 || yy < 0 || xx >= size || yy >= size) continue;
        k.at<float>(yy, xx) += static_cast<float>((dx ? fx : 1 - fx) * (dy ? fy : 1 - fy));
      }
  }
  return k / cv::sum(k)[0];
}

// A disk of `radius` pixels, its edge pixels weighted by about the share the disk covers.
cv::Mat diskKernel(double radius) {
  const int half = static_cast<int>(std::ceil(radius + 0.5));
  cv::Mat k(2 * half + 1, 2 * half + 1, CV_32F);
  for (int y = -half; y <= half; ++y)
    for (int x = -half; x <= half; ++x)
      k.at<float>(y + half, x + half) = static_cast<float>(std::clamp(radius + 0.5 - std::hypot(x, y), 0.0, 1.0));
  return k / cv::sum(k)[0];
}

// Bilinear fetch of a CV_32FC4 texture at (a, b), transparent (all zero) outside it.
cv::Vec4f fetchClear(const cv::Mat& t, double a, double b) {
  if (!(a > -1 && b > -1 && a < t.cols && b < t.rows)) return {};
  const int a0 = static_cast<int>(std::floor(a)), b0 = static_cast<int>(std::floor(b));
  const float fa = static_cast<float>(a - a0), fb = static_cast<float>(b - b0);
  auto at = [&t](int i, int j) {
    return i < 0 || j < 0 || i >= t.cols || j >= t.rows ? cv::Vec4f() : t.at<cv::Vec4f>(j, i);
  };
  return (at(a0, b0) * (1 - fa) + at(a0 + 1, b0) * fa) * (1 - fb) + (at(a0, b0 + 1) * (1 - fa) + at(a0 + 1, b0 + 1) * fa) * fb;
}

}  // namespace

cv::Mat premultipliedTexture(const cv::Mat& rgba8) {
  if (rgba8.empty() || rgba8.type() != CV_8UC4) throw std::invalid_argument("an occluder picture must be RGBA8");
  cv::Mat out(rgba8.size(), CV_32FC4);
  for (int y = 0; y < rgba8.rows; ++y)
    for (int x = 0; x < rgba8.cols; ++x) {
      const cv::Vec4b c = rgba8.at<cv::Vec4b>(y, x);
      const float a = c[3] / 255.0f;
      out.at<cv::Vec4f>(y, x) = {c[0] * a, c[1] * a, c[2] * a, a};
    }
  return out;
}

SequenceRenderer::SequenceRenderer(PlanarScene scene, CameraModel camera)
    : scene_(std::move(scene)), camera_(camera) {
  if (const std::string p = camera_.problem(); !p.empty()) throw std::invalid_argument("camera: " + p);
  if (!(scene_.targetWidth > 0) || !std::isfinite(scene_.targetWidth))
    throw std::invalid_argument("target width must be positive");
  target_.levels.push_back(toRgbFloat(scene_.target, "target"));
  while (std::min(target_.levels.back().cols, target_.levels.back().rows) >= 8) {
    cv::Mat down;
    cv::pyrDown(target_.levels.back(), down);
    target_.levels.push_back(down);
  }
  const cv::Scalar tm = cv::mean(target_.levels[0]);
  target_.mean = cv::Vec3f(float(tm[0]), float(tm[1]), float(tm[2]));

  if (scene_.floor.empty()) {
    floor_.levels.push_back(cv::Mat(1, 1, CV_32FC3, cv::Scalar::all(128)));
    floor_.mean = cv::Vec3f(128, 128, 128);
    floorPeriodX_ = floorPeriodZ_ = 1;
  } else {
    if (!(scene_.floorMetresPerPixel > 0)) throw std::invalid_argument("floor metres per pixel must be positive");
    cv::Mat f = toRgbFloat(scene_.floor, "floor");
    floorPeriodX_ = f.cols * scene_.floorMetresPerPixel;
    floorPeriodZ_ = f.rows * scene_.floorMetresPerPixel;
    // Sides a multiple of 2^levels so that every level tiles exactly.
    constexpr int m = 1 << (kFloorLevels - 1);
    const int w = std::max(m, (f.cols + m / 2) / m * m), h = std::max(m, (f.rows + m / 2) / m * m);
    if (w != f.cols || h != f.rows) cv::resize(f, f, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    floor_.levels.push_back(f);
    for (int l = 1; l < kFloorLevels; ++l) {
      const cv::Mat& prev = floor_.levels.back();
      cv::Mat tiled, down;
      cv::repeat(prev, 3, 3, tiled);  // periodic borders for the Gaussian
      cv::pyrDown(tiled, down);
      floor_.levels.push_back(down(cv::Rect(prev.cols / 2, prev.rows / 2, prev.cols / 2, prev.rows / 2)).clone());
    }
    const cv::Scalar fm = cv::mean(f);
    floor_.mean = cv::Vec3f(float(fm[0]), float(fm[1]), float(fm[2]));
  }

  for (auto [from, rgba, to] : {std::tuple{&target_, &targetRgba_, &targetLevels_}, std::tuple{&floor_, &floorRgba_, &floorLevels_}})
    for (const cv::Mat& level : from->levels) {
      cv::Mat bytes, back;
      level.convertTo(bytes, CV_8UC3);  // rounded and saturated: exact only where the level is whole bytes
      bytes.convertTo(back, CV_32FC3);
      const bool exact = cv::norm(back, level, cv::NORM_INF) == 0;
      rgba->emplace_back();
      cv::cvtColor(exact ? bytes : level, rgba->back(), cv::COLOR_BGR2BGRA);  // the fourth channel is never read
      const cv::Mat& m = rgba->back();
      to->push_back({m.data, static_cast<std::ptrdiff_t>(m.step), level.cols, level.rows, exact ? 4 : 16});
    }

  // Where the radial model stops growing with the radius; beyond it no ray reaches the image.
  const Lens lens(camera_);
  maxUndistortedRadius_ = 1e3;
  for (double r = 0; r < 1e3; r += 1e-3) {
    const double r2 = r * r;
    if (1 + r2 * (3 * lens.k1 + r2 * (5 * lens.k2 + r2 * 7 * lens.k3)) <= 0) {
      maxUndistortedRadius_ = r;
      break;
    }
  }
  const int sw = camera_.width * kSupersample, sh = camera_.height * kSupersample;
  auto normalized = [&](int x, int y) {
    const double px = (x + 0.5) / kSupersample - 0.5, py = (y + 0.5) / kSupersample - 0.5;
    return cv::Vec2d((px - camera_.cx) / camera_.fx, (py - camera_.cy) / camera_.fy);
  };
  if (!camera_.hasDistortion()) {
    // A pinhole's ray is separable: a column's x and a row's y (small enough to stay in cache).
    for (int x = 0; x < sw; ++x) columnRays_.push_back(normalized(x, 0)[0]);
    for (int y = 0; y < sh; ++y) rowRays_.push_back(normalized(0, y)[1]);
    return;
  }
  rays_.resize(static_cast<std::size_t>(sw) * sh);
  for (int y = 0; y < sh; ++y)
    for (int x = 0; x < sw; ++x) {
      const cv::Vec2d d = normalized(x, y);
      double xu, yu;
      rays_[static_cast<std::size_t>(y) * sw + x] =
          lens.undistort(d[0], d[1], maxUndistortedRadius_, xu, yu) ? cv::Vec2d(xu, yu) : cv::Vec2d(kNaN, kNaN);
    }
}

inline cv::Vec2d SequenceRenderer::ray(int x, int y) const noexcept {
  const auto ux = static_cast<std::size_t>(x), uy = static_cast<std::size_t>(y);
  return rays_.empty() ? cv::Vec2d(columnRays_[ux], rowRays_[uy])
                       : rays_[uy * static_cast<std::size_t>(camera_.width * kSupersample) + ux];
}

double SequenceRenderer::targetDepth() const noexcept {
  return scene_.targetWidth * scene_.target.rows / scene_.target.cols;
}

glm::dvec3 SequenceRenderer::targetPixelToWorld(double u, double v) const noexcept {
  const double s = scene_.targetWidth / scene_.target.cols;
  return {(u + 0.5 - 0.5 * scene_.target.cols) * s, 0.0, (v + 0.5 - 0.5 * scene_.target.rows) * s};
}

struct SequenceRenderer::View {
  glm::dmat3 toGround, toOccluder;  // also in `source`, as arrays
  struct Plane {
    glm::dmat3 toTexture;  // OpenCV camera ray -> texel (a, b, 1) / depth
    const cv::Mat* texture;
  };
  std::vector<Plane> occluders;
  // The rest of what a sample reads (the ground's and the bar's constants, the textures), for
  // both sceneSample and sceneSamplesAvx2.
  SampleSource source;
};

SequenceRenderer::View SequenceRenderer::view(const glm::dmat4& cameraToWorld, const FrameEffects& fx,
                                              const std::vector<Occluder>& occluders) const {
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(cameraToWorld, r, t);
  View v;
  // Plane point (X, Z) -> OpenCV camera: X r1 + Z r3 + t (the homography without K, whose
  // inverse is applied to the undistorted ray); w = 1 / depth, so w > 0 is in front.
  v.toGround = glm::inverse(glm::dmat3(r[0], r[2], t));
  v.toOccluder = glm::inverse(glm::dmat3(r[0], r[2], t + kOccluderHeight * r[1]));
  v.source.groundOk = std::abs(glm::determinant(glm::dmat3(r[0], r[2], t))) > 1e-12;
  const double tw = scene_.targetWidth;
  v.source.occW = std::clamp(fx.occluderFraction, 0.0, 1.0) * tw;
  v.source.occX0 = -0.5 * tw + std::clamp(fx.occluderPhase, 0.0, 1.0) * (tw - v.source.occW);
  v.source.targetDepth = targetDepth();
  v.source.texel = tw / scene_.target.cols;
  v.source.floorTexel = std::min(floorPeriodX_ / floor_.levels[0].cols, floorPeriodZ_ / floor_.levels[0].rows);
  for (const Occluder& o : occluders) {
    if (o.texture.empty() || o.texture.type() != CV_32FC4)
      throw std::invalid_argument("an occluder's texture must be a non-empty CV_32FC4 image");
    // Texel (a, b) -> OpenCV camera, the same way as the ground's.
    const glm::dvec3 origin = o.centre - 0.5 * (o.texture.cols - 1) * o.axisU - 0.5 * (o.texture.rows - 1) * o.axisV;
    const glm::dmat3 toCamera(r * o.axisU, r * o.axisV, r * origin + t);
    if (!(std::abs(glm::determinant(toCamera)) > 1e-18)) continue;  // seen edge-on: invisible
    v.occluders.push_back({glm::inverse(toCamera), &o.texture});
  }
  SampleSource& w = v.source;
  if (rays_.empty()) {
    w.columnRays = columnRays_.data();
    w.rowRays = rowRays_.data();
  } else {
    w.rays = reinterpret_cast<const double*>(rays_.data());  // Vec2d: two doubles each
  }
  w.width = camera_.width * kSupersample;
  w.height = camera_.height * kSupersample;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) {
      w.toGround[3 * c + k] = v.toGround[c][k];
      w.toOccluder[3 * c + k] = v.toOccluder[c][k];
    }
  w.targetWidth = tw;
  w.targetCols = scene_.target.cols;
  w.targetRows = scene_.target.rows;
  w.floorPeriodX = floorPeriodX_;
  w.floorPeriodZ = floorPeriodZ_;
  w.floorCols = floor_.levels[0].cols;
  w.floorRows = floor_.levels[0].rows;
  w.floorEmpty = scene_.floor.empty();
  w.target = {targetLevels_.data(), static_cast<int>(targetLevels_.size()), target_.mean, false, 0};
  w.floor = {floorLevels_.data(), static_cast<int>(floorLevels_.size()), floor_.mean, true, 2};
  w.invalidLens = toVec3f(kInvalidLensRgb);
  w.occluder = toVec3f(kOccluderRgb);
  w.sky = toVec3f(kSkyRgb);
  return v;
}

cv::Vec3f SequenceRenderer::sceneSample(const View& v, int x, int y) const {
  const int sw = camera_.width * kSupersample, sh = camera_.height * kSupersample;
  if (std::isnan(ray(x, y)[0])) return toVec3f(kInvalidLensRgb);
  auto hit = [&](const glm::dmat3& h, int hx, int hy, glm::dvec2& p) {
    const cv::Vec2d r = ray(hx, hy);
    if (std::isnan(r[0])) return false;
    const glm::dvec3 q = h * glm::dvec3(r[0], r[1], 1.0);
    if (!(q.z > 0)) return false;
    p = {q.x / q.z, q.y / q.z};
    return true;
  };
  const double tw = scene_.targetWidth, td = v.source.targetDepth;
  glm::dvec2 p, o;
  if (v.source.occW > 0 && hit(v.toOccluder, x, y, o) && o.x >= v.source.occX0 && o.x < v.source.occX0 + v.source.occW && std::abs(o.y) < 0.5 * td)
    return toVec3f(kOccluderRgb);
  // A ray that meets the plane beyond what a double holds (grazing): sky, as no texel is there.
  if (!v.source.groundOk || !hit(v.toGround, x, y, p) || !std::isfinite(p.x) || !std::isfinite(p.y)) return toVec3f(kSkyRgb);
  // The sample's footprint on the plane from its steps to the next sample across and
  // down (the previous one at the last column or row). Filtering for the longer step
  // alone would blur grazing views across too; the 2x2 supersampling covers half of it.
  double major = 0, minor = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2 && !std::isinf(major); ++axis) {
    const int nx = axis == 0 ? (x + 1 < sw ? x + 1 : x - 1) : x;
    const int ny = axis == 1 ? (y + 1 < sh ? y + 1 : y - 1) : y;
    glm::dvec2 pn;
    const double step = hit(v.toGround, nx, ny, pn) ? glm::length(pn - p) : std::numeric_limits<double>::infinity();
    major = std::max(major, step);
    minor = std::min(minor, step);
  }
  const double footprint = std::max(minor, 0.5 * major);
  const bool onTarget = std::abs(p.x) < 0.5 * tw && std::abs(p.y) < 0.5 * td;
  if (onTarget) {
    const double texel = v.source.texel;
    const double u = p.x / texel + 0.5 * scene_.target.cols - 0.5;
    const double w = p.y / texel + 0.5 * scene_.target.rows - 0.5;
    return fetchFiltered(target_.levels, target_.mean, u, w, footprint / texel, false, 0);
  }
  if (scene_.floor.empty()) return floor_.mean;
  const double a = p.x / floorPeriodX_ * floor_.levels[0].cols;
  const double b = p.y / floorPeriodZ_ * floor_.levels[0].rows;
  return fetchFiltered(floor_.levels, floor_.mean, a, b, footprint / v.source.floorTexel, true, 2);
}

cv::Vec3f SequenceRenderer::sample(const View& v, int x, int y, const cv::Vec3f* scene) const {
  if (v.occluders.empty()) return scene ? *scene : sceneSample(v, x, y);
  const cv::Vec2d r = ray(x, y);
  if (std::isnan(r[0])) return toVec3f(kInvalidLensRgb);
  // Front to back: the nearest occluder first (the largest 1 / depth), the scene behind only
  // when light still passes.
  struct Hit {
    double inverseDepth;
    cv::Vec4f texel;
  };
  constexpr std::size_t kMaxLayers = 8;
  Hit hits[kMaxLayers];
  std::size_t n = 0;
  for (const View::Plane& plane : v.occluders) {
    const glm::dvec3 q = plane.toTexture * glm::dvec3(r[0], r[1], 1.0);
    if (!(q.z > 0)) continue;
    const cv::Vec4f c = fetchClear(*plane.texture, q.x / q.z, q.y / q.z);
    if (c[3] <= 0) continue;
    if (n == kMaxLayers) break;
    std::size_t i = n++;  // insertion by depth, nearest first
    for (; i > 0 && hits[i - 1].inverseDepth < q.z; --i) hits[i] = hits[i - 1];
    hits[i] = {q.z, c};
  }
  cv::Vec3f colour(0, 0, 0);
  float through = 1;
  for (std::size_t i = 0; i < n && through > 0; ++i) {
    colour += through * cv::Vec3f(hits[i].texel[0], hits[i].texel[1], hits[i].texel[2]);
    through *= 1 - std::min(hits[i].texel[3], 1.0f);
  }
  if (through > 0) colour += through * (scene ? *scene : sceneSample(v, x, y));
  return colour;
}

void SequenceRenderer::coverageSample(const View& v, int x, int y, float& onTarget, float& hidden) const {
  onTarget = hidden = 0;
  const cv::Vec2d r = ray(x, y);
  if (std::isnan(r[0]) || !v.source.groundOk) return;
  const glm::dvec3 q = v.toGround * glm::dvec3(r[0], r[1], 1.0);
  if (!(q.z > 0)) return;
  const double px = q.x / q.z, pz = q.y / q.z;
  if (!(std::abs(px) < 0.5 * scene_.targetWidth && std::abs(pz) < 0.5 * v.source.targetDepth)) return;
  onTarget = 1;
  // The light that passes every occluder in front, as sample() composites them.
  if (v.source.occW > 0) {
    const glm::dvec3 o = v.toOccluder * glm::dvec3(r[0], r[1], 1.0);
    if (o.z > 0) {
      const double ox = o.x / o.z, oz = o.y / o.z;
      if (ox >= v.source.occX0 && ox < v.source.occX0 + v.source.occW && std::abs(oz) < 0.5 * v.source.targetDepth) {
        hidden = 1;
        return;
      }
    }
  }
  float through = 1;
  for (const View::Plane& plane : v.occluders) {
    const glm::dvec3 t = plane.toTexture * glm::dvec3(r[0], r[1], 1.0);
    if (!(t.z > 0)) continue;
    const cv::Vec4f c = fetchClear(*plane.texture, t.x / t.z, t.y / t.z);
    if (c[3] <= 0) continue;
    through *= 1 - std::min(c[3], 1.0f);
  }
  hidden = 1 - through;
}

void SequenceRenderer::targetCoverage(const std::vector<SubFrame>& subFrames, const FrameEffects& fx, cv::Mat& onTarget,
                                      cv::Mat& hidden) const {
  if (subFrames.empty()) throw std::invalid_argument("targetCoverage: no sub-frame");
  onTarget = cv::Mat::zeros(camera_.height, camera_.width, CV_32FC1);
  hidden = cv::Mat::zeros(camera_.height, camera_.width, CV_32FC1);
  // The samples renderExposure averages: all four of the 2x2 for one sub-frame, else one each.
  const bool one = subFrames.size() == 1;
  const std::size_t views = one ? 4 : subFrames.size();
  for (std::size_t k = 0; k < views; ++k) {
    const SubFrame& sub = subFrames[one ? 0 : k];
    const View v = view(sub.cameraToWorld, fx, sub.occluders);
    const int dx = kPhase[k % 4][0], dy = kPhase[k % 4][1];
    cv::parallel_for_(cv::Range(0, camera_.height), [&](const cv::Range& rows) {
      for (int y = rows.start; y < rows.end; ++y) {
        float* on = onTarget.ptr<float>(y);
        float* hid = hidden.ptr<float>(y);
        for (int x = 0; x < camera_.width; ++x) {
          float a = 0, b = 0;
          coverageSample(v, kSupersample * x + dx, kSupersample * y + dy, a, b);
          on[x] += a;
          hid[x] += b;
        }
      }
    });
  }
  onTarget *= 1.0 / static_cast<double>(views);
  hidden *= 1.0 / static_cast<double>(views);
}

void SequenceRenderer::samples(const View& v, int x, int stride, int y, int count, cv::Vec3f* out) const {
  // The scene four at a time where AVX2 can (the same bits), the hands over it per sample.
  const int wide = wide_ ? sceneSamplesAvx2(v.source, x, stride, y, count, out) : 0;
  if (!v.occluders.empty())
    for (int i = 0; i < wide; ++i) out[i] = sample(v, x + stride * i, y, &out[i]);
  for (int i = wide; i < count; ++i) out[i] = sample(v, x + stride * i, y);
}

void SequenceRenderer::shade(const View& v, cv::Mat& out) const {
  const int sw = camera_.width * kSupersample, sh = camera_.height * kSupersample;
  out.create(sh, sw, CV_32FC3);
  cv::parallel_for_(cv::Range(0, sh), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      samples(v, 0, 1, y, sw, out.ptr<cv::Vec3f>(y));
    }
  });
}

void SequenceRenderer::accumulateExposure(const std::vector<View>& views, cv::Mat& sum) const {
  // In tiles, every sub-frame of a tile before the next tile: the sub-frames' views differ
  // little (a sub-frame per 2 px of image motion), so the texels one reads are mostly still in
  // the cache for the next. Each pixel's sum is taken in sub-frame order, as one pass per
  // sub-frame would.
  constexpr int kTile = 32;
  const int across = (camera_.width + kTile - 1) / kTile, down = (camera_.height + kTile - 1) / kTile;
  cv::parallel_for_(cv::Range(0, across * down), [&](const cv::Range& tiles) {
    for (int tile = tiles.start; tile < tiles.end; ++tile) {
      const int x0 = tile % across * kTile, y0 = tile / across * kTile;
      const int n = std::min(x0 + kTile, camera_.width) - x0;
      cv::Vec3f colours[kTile];
      for (std::size_t k = 0; k < views.size(); ++k) {
        const int dx = kPhase[k % 4][0], dy = kPhase[k % 4][1];
        for (int y = y0; y < std::min(y0 + kTile, camera_.height); ++y) {
          samples(views[k], kSupersample * x0 + dx, kSupersample, kSupersample * y + dy, n, colours);
          auto* row = sum.ptr<cv::Vec3f>(y) + x0;
          for (int i = 0; i < n; ++i) row[i] += colours[i];
        }
      }
    }
  });
}

void SequenceRenderer::finish(cv::Mat& image, const FrameEffects& fx, cv::Mat& outRgb) const {
  if (fx.defocusPx >= 0.5) cv::filter2D(image, image, -1, diskKernel(fx.defocusPx));
  if (fx.motionBlurPx > 1) cv::filter2D(image, image, -1, lineKernel(fx.motionBlurPx, fx.motionBlurAngleDeg));
  if (fx.gainEv != 0) image *= std::exp2(fx.gainEv);
  if (fx.channelGain != cv::Vec3d(1, 1, 1))
    cv::multiply(image, cv::Scalar(fx.channelGain[0], fx.channelGain[1], fx.channelGain[2]), image);
  if (fx.noiseSigma > 0) {
    cv::Mat noise(image.size(), CV_32FC3);
    cv::RNG rng(fx.noiseSeed);
    rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(fx.noiseSigma));
    image += noise;
  }
  image.convertTo(outRgb, CV_8UC3);  // rounds and saturates
  if (fx.jpegQuality > 0) {
    cv::Mat bgr;
    cv::cvtColor(outRgb, bgr, cv::COLOR_RGB2BGR);  // JPEG's colour transform expects BGR
    std::vector<unsigned char> bytes;
    cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, std::clamp(fx.jpegQuality, 1, 100)});
    cv::cvtColor(cv::imdecode(bytes, cv::IMREAD_COLOR), outRgb, cv::COLOR_BGR2RGB);
  }
}

void SequenceRenderer::render(const glm::dmat4& cameraToWorld, const FrameEffects& fx, cv::Mat& outRgb) const {
  renderExposure({SubFrame{cameraToWorld, {}}}, fx, outRgb);
}

void SequenceRenderer::renderExposure(const std::vector<SubFrame>& subFrames, const FrameEffects& fx,
                                      cv::Mat& outRgb) const {
  cv::Mat image;
  renderLinear(subFrames, fx, image);
  finish(image, fx, outRgb);
}

void SequenceRenderer::renderLinear(const std::vector<SubFrame>& subFrames, const FrameEffects& fx,
                                    cv::Mat& image) const {
  if (subFrames.empty()) throw std::invalid_argument("renderLinear: no sub-frame");
  if (subFrames.size() == 1) {
    cv::Mat super;
    shade(view(subFrames[0].cameraToWorld, fx, subFrames[0].occluders), super);
    cv::resize(super, image, cv::Size(camera_.width, camera_.height), 0, 0, cv::INTER_AREA);
  } else {
    std::vector<View> views;
    views.reserve(subFrames.size());
    for (const SubFrame& sub : subFrames) views.push_back(view(sub.cameraToWorld, fx, sub.occluders));
    image = cv::Mat::zeros(camera_.height, camera_.width, CV_32FC3);
    accumulateExposure(views, image);
    image *= 1.0 / static_cast<double>(subFrames.size());
  }
}

std::vector<glm::dvec3> SequenceRenderer::targetPointsInView(const glm::dmat4& cameraToWorld, int& gridPoints) const {
  constexpr int kAcross = 96;
  const int down = std::max(1, static_cast<int>(std::lround(kAcross * targetDepth() / scene_.targetWidth)));
  gridPoints = kAcross * down;
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(cameraToWorld, r, t);
  std::vector<cv::Point3d> inFront;
  for (int j = 0; j < down; ++j)
    for (int i = 0; i < kAcross; ++i) {
      const glm::dvec3 p(((i + 0.5) / kAcross - 0.5) * scene_.targetWidth, 0.0, ((j + 0.5) / down - 0.5) * targetDepth());
      const glm::dvec3 c = r * p + t;
      // Behind the camera, or beyond the radius where the lens model folds back (where
      // projectPoints would put it in the image although no ray reaches it).
      if (!(c.z > 1e-9)) continue;
      const double x = c.x / c.z, y = c.y / c.z;
      if (x * x + y * y > maxUndistortedRadius_ * maxUndistortedRadius_) continue;
      inFront.emplace_back(p.x, p.y, p.z);
    }
  std::vector<glm::dvec3> out;
  if (inFront.empty()) return out;
  std::vector<cv::Point2d> pixels;
  const cv::Matx33d k(camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  const cv::Matx33d rcv(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  cv::Vec3d rvec;
  cv::Rodrigues(rcv, rvec);
  cv::projectPoints(inFront, rvec, cv::Vec3d(t.x, t.y, t.z), k, std::vector<double>(camera_.distortion.begin(), camera_.distortion.end()),
                    pixels);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const cv::Point2d& q = pixels[i];
    if (q.x >= -0.5 && q.y >= -0.5 && q.x < camera_.width - 0.5 && q.y < camera_.height - 0.5)
      out.emplace_back(inFront[i].x, inFront[i].y, inFront[i].z);
  }
  return out;
}

double SequenceRenderer::visibleTargetFraction(const glm::dmat4& cameraToWorld) const {
  int grid = 0;
  const std::size_t inside = targetPointsInView(cameraToWorld, grid).size();
  return static_cast<double>(inside) / static_cast<double>(grid);
}

double SequenceRenderer::occludedTargetFraction(const glm::dmat4& cameraToWorld,
                                                const std::vector<Occluder>& occluders) const {
  int grid = 0;
  const std::vector<glm::dvec3> points = targetPointsInView(cameraToWorld, grid);
  const glm::dvec3 eye(cameraToWorld[3]);
  int hidden = 0;
  for (const glm::dvec3& p : points)
    for (const Occluder& o : occluders) {
      // eye + s (p - eye) = origin + a axisU + b axisV, for s in (0, 1): the line of sight crosses it.
      const glm::dvec3 origin = o.centre - 0.5 * (o.texture.cols - 1) * o.axisU - 0.5 * (o.texture.rows - 1) * o.axisV;
      const glm::dmat3 m(o.axisU, o.axisV, eye - p);
      if (!(std::abs(glm::determinant(m)) > 1e-18)) continue;
      const glm::dvec3 abs = glm::inverse(m) * (eye - origin);
      if (abs.z > 0 && abs.z < 1 && fetchClear(o.texture, abs.x, abs.y)[3] > 0.5f) {
        ++hidden;
        break;
      }
    }
  return static_cast<double>(hidden) / static_cast<double>(grid);
}

glm::dmat4 lookAtCameraToWorld(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
  const glm::dvec3 f = glm::normalize(target - eye);
  glm::dvec3 x = glm::cross(f, up);
  if (glm::length(x) < 1e-9 * glm::length(up)) x = glm::cross(f, glm::dvec3(0, 0, -1));
  if (glm::length(x) < 1e-9) x = glm::cross(f, glm::dvec3(1, 0, 0));
  x = glm::normalize(x);
  const glm::dvec3 y = glm::cross(x, f);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(x, 0);
  m[1] = glm::dvec4(y, 0);
  m[2] = glm::dvec4(-f, 0);
  m[3] = glm::dvec4(eye, 1);
  return m;
}

void worldToOpenCvCamera(const glm::dmat4& cameraToWorld, glm::dmat3& rotation, glm::dvec3& translation) {
  // The OpenCV camera's axes in the world are the GL camera's with Y and Z negated.
  const glm::dmat3 cvToWorld{glm::dvec3(cameraToWorld[0]), -glm::dvec3(cameraToWorld[1]),
                             -glm::dvec3(cameraToWorld[2])};
  rotation = glm::transpose(cvToWorld);
  translation = -(rotation * glm::dvec3(cameraToWorld[3]));
}

glm::dvec2 projectWorldPoint(const CameraModel& camera, const glm::dmat4& cameraToWorld, glm::dvec3 p) {
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(cameraToWorld, r, t);
  const cv::Matx33d rcv(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  cv::Vec3d rvec;
  cv::Rodrigues(rcv, rvec);
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::projectPoints(std::vector<cv::Point3d>{{p.x, p.y, p.z}}, rvec, cv::Vec3d(t.x, t.y, t.z), k,
                    std::vector<double>(camera.distortion.begin(), camera.distortion.end()), out);
  return {out[0].x, out[0].y};
}

}  // namespace marionette::ar::synthetic
