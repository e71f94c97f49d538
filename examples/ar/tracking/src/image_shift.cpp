#include "image_shift.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace marionette::ar {

namespace {

constexpr int kMaxRadius = 16;
constexpr int kRefineRadius = 2;

// A block of `previous` and its statistics (zero-mean: the ZNCC needs them once per level).
struct Block {
  int x0 = 0, y0 = 0, w = 0, h = 0;
  double mean = 0, norm = 0;  // norm: sqrt of the sum of squared deviations
};

// The largest block of `previous` that stays inside `current`, a pixel in from its border, for
// every offset within radius of (gx, gy). It lies on the side the shift comes from: centred, it
// would lose the guess's length on both sides (a 72 px guess left a 60 px level 8 rows).
bool centralBlock(const GreyLevel& previous, const GreyLevel& current, int gx, int gy, int radius, Block& b) noexcept {
  const int reach = radius + 1;
  b.x0 = std::max(reach, reach - gx);
  b.y0 = std::max(reach, reach - gy);
  b.w = std::min(previous.width - reach, current.width - reach - gx) - b.x0;
  b.h = std::min(previous.height - reach, current.height - reach - gy) - b.y0;
  if (b.w < 16 || b.h < 12) return false;
  double sum = 0, sumSq = 0;
  for (int y = 0; y < b.h; ++y) {
    const std::uint8_t* p = previous.row(b.y0 + y) + b.x0;
    for (int x = 0; x < b.w; ++x) {
      const double v = p[x];
      sum += v;
      sumSq += v * v;
    }
  }
  const double n = static_cast<double>(b.w) * b.h;
  b.mean = sum / n;
  const double var = sumSq - sum * sum / n;
  b.norm = var > 0 ? std::sqrt(var) : 0;
  return b.norm > 2.0 * std::sqrt(n);  // a standard deviation of 2 grey levels at least: texture
}

// ZNCC of the block against `current` offset by (dx, dy). Integer sums, a row at a time (a
// row's products fit 32 bits; the compiler vectorizes them): 8 times the double loop's speed.
double zncc(const GreyLevel& previous, const GreyLevel& current, const Block& b, int dx, int dy) noexcept {
  std::int64_t sum = 0, sumSq = 0, cross = 0;
  for (int y = 0; y < b.h; ++y) {
    const std::uint8_t* p = previous.row(b.y0 + y) + b.x0;
    const std::uint8_t* c = current.row(b.y0 + y + dy) + b.x0 + dx;
    std::int32_t rowSum = 0, rowSq = 0, rowCross = 0;
    for (int x = 0; x < b.w; ++x) {
      const std::int32_t v = c[x];
      rowSum += v;
      rowSq += v * v;
      rowCross += static_cast<std::int32_t>(p[x]) * v;
    }
    sum += rowSum;
    sumSq += rowSq;
    cross += rowCross;
  }
  const double n = static_cast<double>(b.w) * b.h;
  const double var = static_cast<double>(sumSq) - static_cast<double>(sum) * static_cast<double>(sum) / n;
  if (!(var > 0) || !(b.norm > 0)) return -1;
  // sum (p - mean) c = sum p c - mean sum c
  return (static_cast<double>(cross) - b.mean * static_cast<double>(sum)) / (b.norm * std::sqrt(var));
}

// The ZNCC at every offset within a radius of (cx, cy), kept for the runner-up and the parabola.
struct ScoreGrid {
  static constexpr int kSide = 2 * kMaxRadius + 1;
  std::array<double, kSide * kSide> scores{};
  int radius = 0, bx = 0, by = 0;  // the best's offset from (cx, cy)
  double best = -2;

  [[nodiscard]] double at(int dx, int dy) const noexcept {
    return scores[static_cast<std::size_t>((dy + kMaxRadius) * kSide + dx + kMaxRadius)];
  }
  [[nodiscard]] bool bestOnBorder() const noexcept { return std::abs(bx) == radius || std::abs(by) == radius; }
  void search(const GreyLevel& previous, const GreyLevel& current, const Block& b, int cx, int cy, int r) noexcept {
    radius = r;
    bx = by = 0;
    best = -2;
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const double v = zncc(previous, current, b, cx + dx, cy + dy);
        scores[static_cast<std::size_t>((dy + kMaxRadius) * kSide + dx + kMaxRadius)] = v;
        if (v > best) best = v, bx = dx, by = dy;
      }
  }
};

// The vertex of the parabola through (-1, a), (0, b), (1, c), within +-0.5.
double parabolaPeak(double a, double b, double c) noexcept {
  const double d = a - 2 * b + c;
  if (!(d < 0)) return 0;
  return std::clamp(0.5 * (a - c) / d, -0.5, 0.5);
}

}  // namespace

bool estimateImageShift(const ImagePyramid& previous, const ImagePyramid& current, cv::Point2f guess,
                        const ImageShiftOptions& params, ImageShift& out) noexcept {
  const int top = params.coarseLevel;
  const int radius = params.radius;
  if (top < 0 || top > previous.levels() || top > current.levels() || radius < 1 || radius > kMaxRadius ||
      !std::isfinite(guess.x) || !std::isfinite(guess.y))
    return false;
  // A guess past the image is no guess (and would overflow the integer offsets).
  if (std::abs(guess.x) > static_cast<float>(previous.level(0).width) ||
      std::abs(guess.y) > static_cast<float>(previous.level(0).height))
    return false;
  const float coarse = 1.0f / static_cast<float>(1 << top);
  int gx = static_cast<int>(std::lround(guess.x * coarse)), gy = static_cast<int>(std::lround(guess.y * coarse));
  const GreyLevel& p0 = previous.level(top);
  const GreyLevel& c0 = current.level(top);
  if (!p0.data || !c0.data) return false;
  Block b;
  // Every offset within the radius: the best. A best on the search's border is the slope of a
  // peak beyond it: the search moves there once (a turn faster than the guess), and a best on
  // the border again is no shift (the search would return a clipped one with a high score).
  ScoreGrid grid;
  for (int search = 0;; ++search) {
    if (!centralBlock(p0, c0, gx, gy, radius, b)) return false;
    grid.search(p0, c0, b, gx, gy, radius);
    if (!grid.bestOnBorder()) break;
    if (search > 0 || !(grid.best >= params.minScore)) return false;
    gx += grid.bx;
    gy += grid.by;
  }
  // The runner-up is another local maximum (the border's included), not the main peak's
  // shoulder (a smear stretches the peak along itself).
  double second = -2;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      if (dx == grid.bx && dy == grid.by) continue;
      const double v = grid.at(dx, dy);
      bool peak = true;
      for (int ny = std::max(-1, -radius - dy); ny <= std::min(1, radius - dy) && peak; ++ny)
        for (int nx = std::max(-1, -radius - dx); nx <= std::min(1, radius - dx) && peak; ++nx)
          if ((nx || ny) && grid.at(dx + nx, dy + ny) > v) peak = false;
      if (peak) second = std::max(second, v);
    }
  if (!(grid.best >= params.minScore) || !(grid.best - second >= params.minMargin)) return false;
  // Finer levels: +-2 px around twice the coarser result; the parabola at the last one.
  int sx = gx + grid.bx, sy = gy + grid.by;
  int level = top;
  const int last = std::max(0, top - 2);
  double fx = 0, fy = 0, final = grid.best;
  while (level > last) {
    --level;
    sx *= 2;
    sy *= 2;
    const GreyLevel& p = previous.level(level);
    const GreyLevel& c = current.level(level);
    if (!p.data || !c.data || !centralBlock(p, c, sx, sy, kRefineRadius, b)) return false;
    grid.search(p, c, b, sx, sy, kRefineRadius);
    // The coarser level's integer peak is within a pixel of this level's: one at the border of
    // +-2 is no peak of this search.
    if (grid.bestOnBorder()) return false;
    fx = parabolaPeak(grid.at(grid.bx - 1, grid.by), grid.best, grid.at(grid.bx + 1, grid.by));
    fy = parabolaPeak(grid.at(grid.bx, grid.by - 1), grid.best, grid.at(grid.bx, grid.by + 1));
    sx += grid.bx;
    sy += grid.by;
    final = grid.best;
  }
  if (!(final >= params.minScore)) return false;
  const float scale = static_cast<float>(1 << level);
  out.shift = cv::Point2f(static_cast<float>((sx + fx) * scale), static_cast<float>((sy + fy) * scale));
  out.score = final;
  return true;
}

cv::Matx33d rotationShiftHomography(const cv::Matx33d& K, cv::Point2f shift) noexcept {
  // The ray through the principal point moved by the shift, in camera coordinates.
  const cv::Vec3d r(shift.x / K(0, 0), shift.y / K(1, 1), 1.0);
  const cv::Vec3d a(0, 0, 1), b = r / cv::norm(r);
  // Rodrigues for the rotation taking a to b about a x b.
  const cv::Vec3d axis = a.cross(b);
  const double s = cv::norm(axis), c = a.dot(b);
  cv::Matx33d R = cv::Matx33d::eye();
  if (s > 1e-12) {
    const cv::Vec3d k = axis / s;
    const cv::Matx33d kx(0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0);
    R = cv::Matx33d::eye() + s * kx + (1 - c) * kx * kx;
  }
  return K * R * K.inv();
}

}  // namespace marionette::ar
