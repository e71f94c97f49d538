#include "marionette/prt/mirror_ball.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <numbers>
#include <utility>

#include "rgb_image_reader.hpp"

namespace marionette::prt {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kMaxOutputWidth = 1 << 16;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

// The ball image, read only inside the circle.
class BallImage {
 public:
  BallImage(const float* rgb, int width, int height, const MirrorBallCircle& circle)
      : rgb_(rgb), width_(width), height_(height), circle_(circle), radius2_(circle.radius * circle.radius) {}

  [[nodiscard]] bool inside(int column, int row) const noexcept {
    if (column < 0 || row < 0 || column >= width_ || row >= height_) return false;
    const double dx = column + 0.5 - circle_.centerX, dy = row + 0.5 - circle_.centerY;
    return dx * dx + dy * dy <= radius2_;
  }

  // Bilinear sample at the ball point (a, b) of the unit disc, between pixel centres, from
  // the ball pixels only. The point is first pulled in to half a pixel inside the rim: from
  // there at least one of the four neighbours has its centre in the circle (for radius >= 1:
  // the nearest corner of the cell is within sqrt(d^2 + 1/2) <= R of the centre).
  [[nodiscard]] glm::dvec3 sample(glm::dvec2 p) const noexcept {
    const double reach = std::max(0.0, circle_.radius - 0.5);
    const double len = std::hypot(p.x, p.y) * circle_.radius;
    if (len > reach) p *= reach / len;
    const double x = circle_.centerX + p.x * circle_.radius - 0.5;
    const double y = circle_.centerY - p.y * circle_.radius - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int c0 = static_cast<int>(fx), r0 = static_cast<int>(fy);
    glm::dvec3 sum(0.0);
    double weightSum = 0.0;
    glm::dvec3 any(0.0);
    bool found = false;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        if (!inside(c0 + i, r0 + j)) continue;
        const float* t = rgb_ + (static_cast<std::size_t>(r0 + j) * static_cast<std::size_t>(width_) +
                                 static_cast<std::size_t>(c0 + i)) * 3;
        const glm::dvec3 value(t[0], t[1], t[2]);
        const double w = (i ? ax : 1.0 - ax) * (j ? ay : 1.0 - ay);
        sum += w * value;
        weightSum += w;
        if (!found) any = value, found = true;
      }
    if (weightSum > 0.0) return sum / weightSum;
    return any;  // only zero-weight neighbours in the ball (the point on a cell edge): one of them
  }

  // Ball point (a, b) to image pixel coordinates.
  [[nodiscard]] glm::dvec2 pixel(const glm::dvec2& p) const noexcept {
    return {circle_.centerX + p.x * circle_.radius, circle_.centerY - p.y * circle_.radius};
  }

 private:
  const float* rgb_;
  int width_, height_;
  MirrorBallCircle circle_;
  double radius2_;
};
}  // namespace

glm::dvec3 mirrorBallDirection(const glm::dvec2& ballPoint) noexcept {
  glm::dvec2 p = ballPoint;
  const double rho = std::hypot(p.x, p.y);
  if (!(rho <= 1.0)) {
    if (!(rho > 0.0) || !std::isfinite(rho)) return {0.0, 0.0, -1.0};
    p /= rho;
  }
  const double rhoClamped = std::min(rho, 1.0);
  // c = n.z = sqrt(1 - rho^2), written to keep its precision near the rim.
  const double c2 = (1.0 - rhoClamped) * (1.0 + rhoClamped);
  const double c = std::sqrt(c2);
  return {2.0 * c * p.x, 2.0 * c * p.y, 2.0 * c2 - 1.0};
}

glm::dvec2 mirrorBallPoint(const glm::dvec3& direction) noexcept {
  const double len = std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0, 0.0};
  const glm::dvec3 w = direction / len;
  // n = normalize(w + (0,0,1)): |w + Z|^2 = 2 (1 + w.z) = 2 s^2 / (1 - w.z), s = |(w.x, w.y)|,
  // so (a, b) = (w.x, w.y) / s * sqrt((1 - w.z) / 2), without the cancellation of 1 + w.z
  // near -Z.
  const double rho = std::sqrt(std::clamp((1.0 - w.z) * 0.5, 0.0, 1.0));
  const double s = std::hypot(w.x, w.y);
  if (!(s > 0.0)) return w.z > 0.0 ? glm::dvec2(0.0, 0.0) : glm::dvec2(1.0, 0.0);
  return {w.x / s * rho, w.y / s * rho};
}

std::optional<EnvironmentMap> mirrorBallToLatLong(const float* rgb, int width, int height,
                                                  const MirrorBallOptions& options, Diagnostics& diagnostics,
                                                  const std::string& source) {
  if (width <= 0 || height <= 0 || rgb == nullptr) {
    diagnostics.error(source, "mirror ball has no pixels (" + std::to_string(width) + "x" + std::to_string(height) +
                                  (rgb == nullptr ? ", no data)" : ")"));
    return std::nullopt;
  }
  const MirrorBallCircle circle = options.circle.value_or(
      MirrorBallCircle{width * 0.5, height * 0.5, std::min(width, height) * 0.5});
  const std::string where = "mirror-ball circle (centre " + number(circle.centerX) + ", " +
                            number(circle.centerY) + ", radius " + number(circle.radius) + " pixels)";
  if (!std::isfinite(circle.centerX) || !std::isfinite(circle.centerY) || !std::isfinite(circle.radius) ||
      circle.radius < 1.0) {
    diagnostics.error(source, where + " is not usable: expected finite values and a radius of at least 1 pixel");
    return std::nullopt;
  }
  constexpr double kSlack = 0.5;  // half a pixel beyond the image is tolerated (rounded circles)
  if (circle.centerX - circle.radius < -kSlack || circle.centerY - circle.radius < -kSlack ||
      circle.centerX + circle.radius > width + kSlack || circle.centerY + circle.radius > height + kSlack) {
    diagnostics.error(source, where + " extends beyond the " + std::to_string(width) + "x" +
                                  std::to_string(height) + " image");
    return std::nullopt;
  }
  int outWidth = options.outputWidth;
  if (outWidth == 0) {
    outWidth = std::max(8, 2 * static_cast<int>(std::lround(2.0 * circle.radius)));
    outWidth = std::min(outWidth, kMaxOutputWidth);
  }
  if (outWidth < 4 || outWidth % 2 != 0 || outWidth > kMaxOutputWidth) {
    diagnostics.error(source, "lat-long output width " + std::to_string(outWidth) +
                                  " is not usable: expected an even number from 4 to " +
                                  std::to_string(kMaxOutputWidth) + " (or 0 for the default)");
    return std::nullopt;
  }
  const int outHeight = outWidth / 2;

  const BallImage ball(rgb, width, height, circle);
  std::vector<float> out(static_cast<std::size_t>(outWidth) * static_cast<std::size_t>(outHeight) * 3);
  for (int row = 0; row < outHeight; ++row) {
    for (int column = 0; column < outWidth; ++column) {
      // Sub-samples per axis from the footprint of the pixel on the ball: its corners' bounding
      // box in ball pixels (about one sample per ball pixel it spans, 2 to 8 per axis).
      double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
      for (int corner = 0; corner < 4; ++corner) {
        const double u = static_cast<double>(column + (corner & 1)) / outWidth;
        const double v = static_cast<double>(row + (corner >> 1)) / outHeight;
        const glm::dvec2 p = ball.pixel(mirrorBallPoint(EnvironmentMap::direction(u, v)));
        minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
        minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
      }
      const int k = std::clamp(static_cast<int>(std::ceil(std::max(maxX - minX, maxY - minY))), 2, 8);
      glm::dvec3 sum(0.0);
      double weightSum = 0.0;
      for (int j = 0; j < k; ++j) {
        const double v = (row + (j + 0.5) / k) / outHeight;
        const double weight = std::sin(kPi * v);  // solid angle of the sub-sample's share of the row
        for (int i = 0; i < k; ++i) {
          const double u = (column + (i + 0.5) / k) / outWidth;
          sum += weight * ball.sample(mirrorBallPoint(EnvironmentMap::direction(u, v)));
          weightSum += weight;
        }
      }
      const glm::dvec3 value = sum / weightSum;
      float* o = &out[(static_cast<std::size_t>(row) * static_cast<std::size_t>(outWidth) +
                       static_cast<std::size_t>(column)) * 3];
      o[0] = static_cast<float>(value.x), o[1] = static_cast<float>(value.y), o[2] = static_cast<float>(value.z);
    }
  }
  return EnvironmentMap(outWidth, outHeight, std::move(out));
}

std::vector<float> renderMirrorBall(const EnvironmentMap& map, int size, int subsamples) {
  if (size < 1) return {};
  const int k = std::max(1, subsamples);
  const double radius = size * 0.5;
  std::vector<float> out(static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 3, 0.0f);
  for (int row = 0; row < size; ++row) {
    for (int column = 0; column < size; ++column) {
      const double cx = (column + 0.5 - radius) / radius, cy = (radius - row - 0.5) / radius;
      if (cx * cx + cy * cy > 1.0) continue;  // not a ball pixel (the same test mirrorBallToLatLong reads with)
      glm::dvec3 sum(0.0);
      int n = 0;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const glm::dvec2 p((column + (i + 0.5) / k - radius) / radius, (radius - row - (j + 0.5) / k) / radius);
          if (p.x * p.x + p.y * p.y > 1.0) continue;
          sum += glm::dvec3(map.sample(mirrorBallDirection(p)));
          ++n;
        }
      if (n == 0) sum = glm::dvec3(map.sample(mirrorBallDirection({cx, cy}))), n = 1;
      const glm::dvec3 value = sum / static_cast<double>(n);
      float* o = &out[(static_cast<std::size_t>(row) * static_cast<std::size_t>(size) +
                       static_cast<std::size_t>(column)) * 3];
      o[0] = static_cast<float>(value.x), o[1] = static_cast<float>(value.y), o[2] = static_cast<float>(value.z);
    }
  }
  return out;
}

EnvironmentMapLoad loadLightProbe(const std::string& path, LightProbeKind kind, const MirrorBallOptions& options) {
  if (kind == LightProbeKind::LatLong) return loadEnvironmentMap(path);
  EnvironmentMapLoad result;
  auto image = detail::readRgbImage(path, "light probe", result.diagnostics);
  if (!image) return result;
  const bool ball = kind == LightProbeKind::MirrorBall || image->width == image->height;
  if (!ball) {
    detail::warnIfNotTwoToOne(path, image->width, image->height, result.diagnostics);
    result.map.emplace(image->width, image->height, std::move(image->rgb));
    return result;
  }
  result.map = mirrorBallToLatLong(image->rgb.data(), image->width, image->height, options, result.diagnostics, path);
  return result;
}

}  // namespace marionette::prt
