#include "dense_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

#include "dense_smear_taps.hpp"
#include "perspective_warp.hpp"
#include "planar_pose.hpp"

namespace marionette::ar {

// The valid samples' extent cut into kPartGrid x kPartGrid parts: which part a sample falls in.
struct DensePartGrid {
  static constexpr int g = DenseAlignment::kPartGrid;
  float x0 = 0, y0 = 0, sx = 0, sy = 0;
  bool valid = false;
  [[nodiscard]] std::size_t of(float x, float y) const noexcept {
    const int px = std::clamp(static_cast<int>((x - x0) * sx), 0, g - 1);
    const int py = std::clamp(static_cast<int>((y - y0) * sy), 0, g - 1);
    return static_cast<std::size_t>(py * g + px);
  }
};

namespace {

GreyLevel viewOf(const cv::Mat& m) noexcept {
  return GreyLevel{m.ptr<std::uint8_t>(0), m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
}

// Level-0 pixel -> level pixel: x_l = x_0 s. Both pyramids are pyrDown's (level l + 1's pixel x
// is centred on level l's 2x), not an area resize's ((x + 0.5) s - 0.5).
cv::Matx33d baseToLevel(int level) noexcept {
  const double s = 1.0 / (1 << level);
  return {s, 0, 0, 0, s, 0, 0, 0, 1};
}

// The pose moved by a step (rotation w, then translation v, both in the camera's axes).
PlanarPose applyStep(const PlanarPose& pose, const cv::Vec<double, 6>& step) noexcept {
  const cv::Matx33d dr = rotationFromRodrigues(cv::Vec3d(step[0], step[1], step[2]));
  const cv::Matx33d r = dr * rotationFromRodrigues(pose.rvec);
  PlanarPose out;
  out.rvec = rodriguesFromRotation(r);
  out.tvec = dr * pose.tvec + cv::Vec3d(step[3], step[4], step[5]);
  return out;
}

// Sums of a sample set's model m and frame f values: their means, variances and covariance.
struct Moments {
  double m = 0, f = 0, mm = 0, ff = 0, mf = 0;
  int n = 0;
  void add(double model, double frame) noexcept {
    m += model, f += frame, mm += model * model, ff += frame * frame, mf += model * frame;
    ++n;
  }
  [[nodiscard]] double varianceM() const noexcept { return mm - m * m / n; }  // times n
  [[nodiscard]] double varianceF() const noexcept { return ff - f * f / n; }
  [[nodiscard]] double covariance() const noexcept { return mf - m * f / n; }
  // Both sides vary (neither a flat model nor a flat frame).
  [[nodiscard]] bool textured() const noexcept { return n > 0 && varianceM() > 1e-3 * n && varianceF() > 1e-3 * n; }
  [[nodiscard]] double zncc() const noexcept { return covariance() / std::sqrt(varianceM() * varianceF()); }
};

// The ground plane (world Y = 0) in the camera's axes: the depth of the plane point on a ray.
struct PlaneInCamera {
  cv::Vec3d normal;
  double offset = 0;
  explicit PlaneInCamera(const PlanarPose& pose) noexcept {
    const cv::Matx33d r = rotationFromRodrigues(pose.rvec);
    normal = cv::Vec3d(r(0, 1), r(1, 1), r(2, 1));
    offset = normal.dot(pose.tvec);
  }
  // Z of the plane point on the ray (x, y, 1); not positive where the ray misses the plane ahead.
  [[nodiscard]] double depth(double x, double y) const noexcept {
    const double along = normal.dot(cv::Vec3d(x, y, 1));
    return std::abs(along) > 1e-12 ? offset / along : -1.0;
  }
};

double huberLoss(double r, double threshold) noexcept {
  const double a = std::abs(r);
  return a <= threshold ? 0.5 * r * r : threshold * (a - 0.5 * threshold);
}


// The model's and the frame's moments over the valid samples.
template <class Sample>
Moments momentsOf(const Sample* samples, int count) noexcept {
  Moments moments;
  for (int i = 0; i < count; ++i)
    if (samples[i].valid) moments.add(samples[i].model, samples[i].frame);
  return moments;
}

template <class Sample>
DensePartGrid partGridOf(const Sample* samples, int count) noexcept {
  float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
  for (int i = 0; i < count; ++i) {
    const Sample& s = samples[i];
    if (!s.valid) continue;
    x0 = std::min(x0, s.x), x1 = std::max(x1, s.x), y0 = std::min(y0, s.y), y1 = std::max(y1, s.y);
  }
  DensePartGrid grid;
  grid.valid = x1 > x0 && y1 > y0;
  if (!grid.valid) return grid;
  grid.x0 = x0, grid.y0 = y0;
  grid.sx = DensePartGrid::g / (x1 - x0 + 1e-3f), grid.sy = DensePartGrid::g / (y1 - y0 + 1e-3f);
  return grid;
}

}  // namespace

struct DenseAligner::Level {
  int index = 0;
  cv::Matx33d k;              // intrinsics at the level
  GreyLevel frame;
  int keyframeLevel = 0;
  cv::Matx33d planeToKeyframe;  // plane -> keyframe-level pixel
  GreyLevel keyframe;
  int count = 0;              // samples
  double stride = 1;
  double area = 0;            // of the keyframe's projection, level pixels
};

void DenseAligner::reserve(const DenseAlignmentOptions& params) {
  capacity_ = static_cast<std::size_t>(std::max(16, params.maxSamples)) * 2;
  samples_.resize(capacity_);
  scratch_.resize(capacity_);
}

bool DenseAligner::prepareLevel(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame,
                                const PlanarPose& pose, int level, const DenseAlignmentOptions& params,
                                Level& out) noexcept {
  if (level < 0 || level > frame.levels() || target.levels.empty() || capacity_ == 0) return false;
  out.index = level;
  out.k = baseToLevel(level) * K;
  out.frame = frame.level(level);
  if (out.frame.width < 16 || out.frame.height < 16) return false;
  const cv::Matx33d g = planeToImage(out.k, pose);
  cv::Matx33d imageToPlane;
  if (!invertHomography(target.planeToImage, imageToPlane)) return false;
  // The keyframe's corners in the frame level: the box the samples cover.
  const cv::Mat& base = target.levels[0];
  const double cw = base.cols - 1.0, ch = base.rows - 1.0;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  std::array<cv::Point2d, 4> quad;
  const cv::Vec3d corners[4] = {cv::Vec3d(0, 0, 1), cv::Vec3d(cw, 0, 1), cv::Vec3d(cw, ch, 1), cv::Vec3d(0, ch, 1)};
  for (std::size_t i = 0; i < 4; ++i) {
    const cv::Vec3d h = g * (imageToPlane * corners[i]);
    if (!(h[2] > 1e-9)) return false;  // the target crosses the camera's plane
    quad[i] = cv::Point2d(h[0] / h[2], h[1] / h[2]);
    x0 = std::min(x0, quad[i].x), x1 = std::max(x1, quad[i].x);
    y0 = std::min(y0, quad[i].y), y1 = std::max(y1, quad[i].y);
  }
  // The keyframe's whole area in the level (shoelace), in or out of view.
  out.area = 0;
  for (std::size_t i = 0; i < 4; ++i) out.area += quad[i].x * quad[(i + 1) % 4].y - quad[(i + 1) % 4].x * quad[i].y;
  out.area = 0.5 * std::abs(out.area);
  x0 = std::max(x0, 1.0), y0 = std::max(y0, 1.0);
  x1 = std::min(x1, out.frame.width - 2.0), y1 = std::min(y1, out.frame.height - 2.0);
  if (!(x1 - x0 >= 4) || !(y1 - y0 >= 4)) return false;
  // The keyframe level whose pixels are about the frame level's (no aliasing, no waste).
  cv::Matx33d frameToPlane;
  if (!invertHomography(g, frameToPlane)) return false;
  const cv::Matx33d frameToKeyframe0 = target.planeToImage * frameToPlane;
  const double scale = homographyScaleAt(frameToKeyframe0, cv::Point2f(static_cast<float>(0.5 * (x0 + x1)),
                                                                       static_cast<float>(0.5 * (y0 + y1))));
  if (!std::isfinite(scale) || !(scale > 0)) return false;
  int kl = 0;
  while (kl + 1 < static_cast<int>(target.levels.size()) && scale / (1 << kl) > 1.5) ++kl;
  out.keyframeLevel = kl;
  out.planeToKeyframe = baseToLevel(kl) * target.planeToImage;
  out.keyframe = viewOf(target.levels[static_cast<std::size_t>(kl)]);
  // Samples on a grid, as many as params.maxSamples allows.
  const double area = (x1 - x0 + 1) * (y1 - y0 + 1);
  const std::size_t most = std::min(capacity_, static_cast<std::size_t>(std::max(16, params.maxSamples)));
  out.stride = std::max(1.0, std::ceil(std::sqrt(area / static_cast<double>(most))));
  const double fx = out.k(0, 0), fy = out.k(1, 1), cx = out.k(0, 2), cy = out.k(1, 2);
  const PlaneInCamera plane(pose);
  out.count = 0;
  for (double y = y0; y <= y1 && static_cast<std::size_t>(out.count) < capacity_; y += out.stride)
    for (double x = x0; x <= x1 && static_cast<std::size_t>(out.count) < capacity_; x += out.stride) {
      Sample& sm = samples_[static_cast<std::size_t>(out.count)];
      const int xi = static_cast<int>(std::lround(x)), yi = static_cast<int>(std::lround(y));
      sm.x = static_cast<float>(xi);
      sm.y = static_cast<float>(yi);
      sm.frame = out.frame.row(yi)[xi];
      // The plane point seen here, at depth Z: a turn w moves its pixel by
      // fx (-x y, 1 + x^2, -y) w, fy (-(1 + y^2), x y, x) w (normalized x, y), a move v by
      // fx (1, 0, -x) v / Z, fy (0, 1, -y) v / Z.
      const double nx = (xi - cx) / fx, ny = (yi - cy) / fy;
      const double z = plane.depth(nx, ny);
      if (!(z > 1e-6)) continue;
      sm.motion = {static_cast<float>(-fx * nx * ny), static_cast<float>(fx * (1 + nx * nx)), static_cast<float>(-fx * ny),
                   static_cast<float>(fx / z), 0.0f, static_cast<float>(-fx * nx / z),
                   static_cast<float>(-fy * (1 + ny * ny)), static_cast<float>(fy * nx * ny), static_cast<float>(fy * nx),
                   0.0f, static_cast<float>(fy / z), static_cast<float>(-fy * ny / z)};
      ++out.count;
    }
  return out.count >= 16;
}

int DenseAligner::render(const Level& level, const PlanarPose& pose, const cv::Vec<double, 6>& smear, int maxTaps,
                         bool wide) noexcept {
  cv::Matx33d frameToPlane;
  if (!invertHomography(planeToImage(level.k, pose), frameToPlane)) return 0;
  const cv::Matx33d a = level.planeToKeyframe * frameToPlane;  // frame-level pixel -> keyframe-level pixel
  const GreyLevel& t = level.keyframe;
  const float umax = static_cast<float>(t.width - 3), vmax = static_cast<float>(t.height - 3);
  int valid = 0;
  float w[6];
  for (int i = 0; i < 6; ++i) w[i] = static_cast<float>(smear[i]);
  SmearTaps group;
  for (int first = 0; first < level.count; first += SmearTaps::kLanes) {
    group.count = std::min(SmearTaps::kLanes, level.count - first);
    for (int lane = 0; lane < group.count; ++lane) {
      Sample& sm = samples_[static_cast<std::size_t>(first + lane)];
      sm.valid = false;
      sm.dx = sm.dy = 0;
      for (std::size_t k = 0; k < 6; ++k) sm.dx += sm.motion[k] * w[k], sm.dy += sm.motion[6 + k] * w[k];
      const double length = std::min(4096.0, static_cast<double>(std::hypot(sm.dx, sm.dy)));
      // A tap every 1.5 px of the level: the keyframe's level is about as sharp as the frame's,
      // and the line's box filter smooths more than that spacing loses.
      const int taps = length < 0.5 ? 1 : std::clamp(static_cast<int>(std::ceil(length / 1.5)) + 1, 2, std::max(2, maxTaps));
      // The taps lie on a line, so their homogeneous images do too: the first tap's, then a
      // constant step (one division a tap).
      const double step = 1.0 / taps;
      const double x0 = sm.x + (0.5 * step - 0.5) * sm.dx, y0 = sm.y + (0.5 * step - 0.5) * sm.dy;
      const double sx = step * sm.dx, sy = step * sm.dy;
      group.taps[lane] = taps;
      group.step[lane] = step;
      group.hx[lane] = a(0, 0) * x0 + a(0, 1) * y0 + a(0, 2);
      group.hy[lane] = a(1, 0) * x0 + a(1, 1) * y0 + a(1, 2);
      group.hw[lane] = a(2, 0) * x0 + a(2, 1) * y0 + a(2, 2);
      group.dhx[lane] = a(0, 0) * sx + a(0, 1) * sy;
      group.dhy[lane] = a(1, 0) * sx + a(1, 1) * sy;
      group.dhw[lane] = a(2, 0) * sx + a(2, 1) * sy;
    }
    walkSmearTaps(t, umax, vmax, group, wide);
    for (int lane = 0; lane < group.count; ++lane) {
      if (!group.inside[lane]) continue;
      Sample& sm = samples_[static_cast<std::size_t>(first + lane)];
      const float inv = 1.0f / static_cast<float>(group.taps[lane]);
      sm.model = group.sum[lane] * inv;
      const float gu = group.gu[lane] * inv, gv = group.gv[lane] * inv, mu = group.mu[lane] * inv, mv = group.mv[lane] * inv;
      // Through the mapping's Jacobian at the pixel: the gradient per frame-level pixel.
      const double px = a(0, 0) * sm.x + a(0, 1) * sm.y + a(0, 2), py = a(1, 0) * sm.x + a(1, 1) * sm.y + a(1, 2);
      const double hz = a(2, 0) * sm.x + a(2, 1) * sm.y + a(2, 2);
      const double u = px / hz, v = py / hz;
      const double dudx = (a(0, 0) - u * a(2, 0)) / hz, dudy = (a(0, 1) - u * a(2, 1)) / hz;
      const double dvdx = (a(1, 0) - v * a(2, 0)) / hz, dvdy = (a(1, 1) - v * a(2, 1)) / hz;
      sm.gx = static_cast<float>(gu * dudx + gv * dvdx);
      sm.gy = static_cast<float>(gu * dudy + gv * dvdy);
      sm.mx = static_cast<float>(mu * dudx + mv * dvdx);
      sm.my = static_cast<float>(mu * dudy + mv * dvdy);
      sm.valid = true;
      ++valid;
    }
  }
  return valid;
}

bool DenseAligner::searchShift(const Level& level, int radius, PlanarPose& pose, double& score) noexcept {
  score = -2;
  if (radius <= 0) return true;
  const GreyLevel& f = level.frame;
  constexpr int g = DenseAlignment::kPartGrid;
  double best = -2, cx = 0, cy = 0;
  int bestX = 0, bestY = 0, n = 0;
  for (int i = 0; i < level.count; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.valid) cx += s.x, cy += s.y, ++n;
  }
  if (n < 16) return false;
  cx /= n, cy /= n;
  // Scored by parts, not as a whole: a hand over a third of the target pulls the whole's ZNCC
  // under any threshold while the parts it leaves still peak at the true shift. The score is
  // the mean of the better half of the textured parts' ZNCC (the whole's where parts are few).
  const DensePartGrid grid = partGridOf(samples_.data(), level.count);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      Moments moments;
      std::array<Moments, g * g> parts{};
      for (int i = 0; i < level.count; ++i) {
        const Sample& s = samples_[static_cast<std::size_t>(i)];
        if (!s.valid) continue;
        const int x = static_cast<int>(s.x) + dx, y = static_cast<int>(s.y) + dy;
        if (x < 0 || y < 0 || x >= f.width || y >= f.height) continue;
        const double v = f.row(y)[x];
        moments.add(s.model, v);
        parts[grid.of(s.x, s.y)].add(s.model, v);
      }
      if (4 * moments.n < 3 * n || !moments.textured()) continue;  // most of the target must stay in the frame
      std::array<double, g * g> scores{};
      int textured = 0;
      for (const Moments& m : parts)
        if (m.n >= 8 && m.textured()) scores[static_cast<std::size_t>(textured++)] = m.zncc();
      double shiftScore = moments.zncc();
      if (textured >= 4) {
        const int half = (textured + 1) / 2;
        std::partial_sort(scores.begin(), scores.begin() + half, scores.begin() + textured, std::greater<>());
        shiftScore = 0;
        for (int k = 0; k < half; ++k) shiftScore += scores[static_cast<std::size_t>(k)];
        shiftScore /= half;
      }
      // Ties go to the smaller shift (the start's).
      if (shiftScore > best + 1e-9 ||
          (std::abs(shiftScore - best) <= 1e-9 && dx * dx + dy * dy < bestX * bestX + bestY * bestY))
        best = shiftScore, bestX = dx, bestY = dy;
    }
  score = best;
  if (!(best > 0.3)) return false;
  if (bestX == 0 && bestY == 0) return true;
  // The turn about the camera's centre that moves the samples' centre by the shift.
  const cv::Matx33d kInverse = level.k.inv();
  const cv::Vec3d a = cv::normalize(kInverse * cv::Vec3d(cx, cy, 1));
  const cv::Vec3d b = cv::normalize(kInverse * cv::Vec3d(cx + bestX, cy + bestY, 1));
  const cv::Vec3d axis = a.cross(b);
  const double angle = std::atan2(cv::norm(axis), a.dot(b));
  if (!(cv::norm(axis) > 1e-12)) return true;
  const cv::Matx33d turn = rotationFromRodrigues(axis * (angle / cv::norm(axis)));
  pose.rvec = rodriguesFromRotation(turn * rotationFromRodrigues(pose.rvec));
  pose.tvec = turn * pose.tvec;
  return true;
}

namespace {

// The fit of the frame by gain * model + bias over the valid samples, the residuals' robust
// standard deviation, and the Huber cost at `sigmaForCost` (or at the new sigma when 0).
struct Fit {
  double gain = 1, bias = 0, sigma = 0, cost = 0, zncc = 0;
  int valid = 0;
};

}  // namespace

double DenseAligner::meanSmearOf(const Level& level) const noexcept {
  double sum = 0;
  int n = 0;
  for (int i = 0; i < level.count; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.valid) sum += std::hypot(s.dx, s.dy), ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

void DenseAligner::noteCoverage(const Level& level, int samples, DenseAlignment& out) noexcept {
  const double covered = samples * level.stride * level.stride;  // level pixels
  out.visibleShare = std::min(1.0, covered / std::max(level.area, 1.0));
  out.frameShare = std::min(1.0, covered / (static_cast<double>(level.frame.width) * level.frame.height));
}

void DenseAligner::judgeParts(const Level& level, const DensePartGrid& grid, DenseAlignment& out,
                              DensePartMask* agreeing) const noexcept {
  constexpr int g = DenseAlignment::kPartGrid;
  // A part's ZNCC past which its texture is taken as aligned, and the least it must hold: a few
  // samples correlate by chance, a flat part (sky of a poster, a smear along its only edge) not at all.
  constexpr double kPartAgreement = 0.85;
  constexpr int kMinPartSamples = 12;
  constexpr double kMinPartModelStd = 3.0;  // grey levels
  out.parts = out.agreeingParts = 0;
  out.agreeingSpan = 0;
  if (agreeing) agreeing->fill(false);
  if (!grid.valid) return;
  std::array<Moments, g * g> parts{};
  for (int i = 0; i < level.count; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.valid) parts[grid.of(s.x, s.y)].add(s.model, s.frame);
  }
  int ax0 = g, ax1 = -1, ay0 = g, ay1 = -1;
  for (int py = 0; py < g; ++py)
    for (int px = 0; px < g; ++px) {
      const Moments& m = parts[static_cast<std::size_t>(py * g + px)];
      if (m.n < kMinPartSamples || m.varianceM() < kMinPartModelStd * kMinPartModelStd * m.n) continue;
      ++out.parts;
      if (!m.textured() || m.zncc() < kPartAgreement) continue;
      ++out.agreeingParts;
      if (agreeing) (*agreeing)[static_cast<std::size_t>(py * g + px)] = true;
      ax0 = std::min(ax0, px), ax1 = std::max(ax1, px), ay0 = std::min(ay0, py), ay1 = std::max(ay1, py);
    }
  if (out.agreeingParts > 0) out.agreeingSpan = std::min(ax1 - ax0 + 1, ay1 - ay0 + 1) / static_cast<double>(g);
}

bool DenseAligner::align(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame,
                         const cv::Vec3d& smearTurn, const PlanarPose& start, const DenseAlignmentOptions& params,
                         DenseAlignment& out) noexcept {
  if (capacity_ == 0 || params.fineLevel < 0 || params.coarseLevel < params.fineLevel) return false;
  constexpr int kAll = 12;
  using Vec12 = cv::Vec<double, kAll>;
  using Mat12 = cv::Matx<double, kAll, kAll>;
  PlanarPose pose = start;
  out.renders = 0;
  const double startTurn = cv::norm(smearTurn);
  const double turnScale = startTurn > params.maxSmearTurn ? params.maxSmearTurn / startTurn : 1.0;
  cv::Vec<double, 6> turn(smearTurn[0] * turnScale, smearTurn[1] * turnScale, smearTurn[2] * turnScale, 0, 0, 0);
  bool searched = false;
  // A sharp start stays sharp: the model's derivative along a smear of zero is zero.
  const int parameters = cv::norm(smearTurn) > 0 && params.fitSmear ? kAll : 6;

  auto fitOf = [&](const Level& lv, double sigmaForCost, Fit& f) {
    const Moments moments = momentsOf(samples_.data(), lv.count);
    const int n = moments.n;
    f.valid = n;
    if (n < 16 || !moments.textured()) return false;  // too few samples, a flat model or frame
    f.gain = moments.covariance() / moments.varianceM();
    f.bias = (moments.f - f.gain * moments.m) / n;
    f.zncc = moments.zncc();
    std::size_t m = 0;
    for (int i = 0; i < lv.count; ++i) {
      const Sample& s = samples_[static_cast<std::size_t>(i)];
      if (s.valid) scratch_[m++] = static_cast<float>(std::abs(s.frame - f.gain * s.model - f.bias));
    }
    std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(m / 2),
                     scratch_.begin() + static_cast<std::ptrdiff_t>(m));
    f.sigma = std::max(0.5, 1.4826 * scratch_[m / 2]);
    const double threshold = params.huber * (sigmaForCost > 0 ? sigmaForCost : f.sigma);
    double cost = 0;
    for (int i = 0; i < lv.count; ++i) {
      const Sample& s = samples_[static_cast<std::size_t>(i)];
      if (s.valid) cost += huberLoss(s.frame - f.gain * s.model - f.bias, threshold);
    }
    f.cost = cost / n;
    return f.gain > 0;
  };

  // The normal equations at the rendered pose. The residual r = frame - gain model - bias; a
  // pose step moves a plane point's pixel by J_pix step, so the model by -gradient . that; a
  // change of the turn moves a tap at offset c along the smear by c J_turn change.
  // Over every valid sample, or (with `only`) over those in the marked parts of `grid`.
  auto normalEquations = [&](const Level& lv, const PlanarPose& p, const Fit& f, Mat12& h, Vec12& b, int& inliers,
                             const DensePartMask* only = nullptr, const DensePartGrid* grid = nullptr) {
    h = Mat12::zeros();
    b = Vec12::all(0);
    inliers = 0;
    const PlaneInCamera plane(p);
    const double fx = lv.k(0, 0), fy = lv.k(1, 1), cx = lv.k(0, 2), cy = lv.k(1, 2);
    const double threshold = params.huber * f.sigma;
    for (int i = 0; i < lv.count; ++i) {
      const Sample& s = samples_[static_cast<std::size_t>(i)];
      if (!s.valid || (only && !(*only)[grid->of(s.x, s.y)])) continue;
      const double rx = (s.x - cx) / fx, ry = (s.y - cy) / fy;
      const double Z = plane.depth(rx, ry);
      if (!(Z > 1e-6)) continue;
      const double X = Z * rx, Y = Z * ry;
      // d(pixel)/d(X_c), then d(X_c)/d(w, v) = [-[X]x | I].
      const double iz = 1 / Z;
      const double ux = fx * iz, uz = -fx * X * iz * iz, vy = fy * iz, vz = -fy * Y * iz * iz;
      const double gx = f.gain * s.gx, gy = f.gain * s.gy;
      const double ex = gx * ux, ey = gy * vy, ez = gx * uz + gy * vz;
      Vec12 j = Vec12::all(0);
      j[0] = -ey * Z + ez * Y, j[1] = ex * Z - ez * X, j[2] = -ex * Y + ey * X, j[3] = ex, j[4] = ey, j[5] = ez;
      if (parameters == kAll) {
        const double mx = -f.gain * s.mx, my = -f.gain * s.my;
        for (std::size_t a = 0; a < 6; ++a) j[static_cast<int>(6 + a)] = mx * s.motion[a] + my * s.motion[6 + a];
      }
      const double res = s.frame - f.gain * s.model - f.bias;
      const double w = std::abs(res) <= threshold ? 1.0 : threshold / std::abs(res);
      if (std::abs(res) <= threshold) ++inliers;
      for (int a = 0; a < parameters; ++a) {
        b[a] += w * j[a] * res;
        for (int c = a; c < parameters; ++c) h(a, c) += w * j[a] * j[c];
      }
    }
    for (int a = 0; a < kAll; ++a)
      for (int c = 0; c < a; ++c) h(a, c) = h(c, a);
    // Unused parameters: an identity block, so that the system stays solvable.
    for (int a = parameters; a < kAll; ++a) h(a, a) = 1;
  };

  Level lv;
  Fit fit;
  Mat12 h;
  Vec12 b;
  int inliers = 0;
  for (int level = params.coarseLevel; level >= params.fineLevel; --level) {
    if (level > frame.levels()) continue;
    if (!prepareLevel(K, target, frame, pose, level, params, lv)) {
      if (level == params.fineLevel) return false;
      continue;
    }
    if ((++out.renders, render(lv, pose, turn, params.maxTaps, params.wide)) < 16) return false;
    if (!searched) {  // the first level that shows the target
      searched = true;
      double score = 0;
      if (!searchShift(lv, params.searchRadius, pose, score)) return false;
      if ((++out.renders, render(lv, pose, turn, params.maxTaps, params.wide)) < 16) return false;
    }
    if (!fitOf(lv, 0, fit)) return false;
    double mu = 1e-3;
    for (int it = 0; it < params.iterations; ++it) {
      normalEquations(lv, pose, fit, h, b, inliers);
      const double previousCost = fit.cost;
      double acceptedCost = previousCost;
      bool accepted = false;
      Vec12 step;
      for (int attempt = 0; attempt < 4 && !accepted; ++attempt) {
        Mat12 damped = h;
        for (int a = 0; a < parameters; ++a) damped(a, a) += mu * std::max(h(a, a), 1e-12);
        bool solved = false;
        const Mat12 dampedInverse = damped.inv(cv::DECOMP_CHOLESKY, &solved);
        if (!solved) {
          mu *= 10;
          continue;
        }
        // The residual grows with the model's drop: r(step) = r + J step, so the step is -H^-1 b.
        step = -(dampedInverse * b);
        const PlanarPose candidate = applyStep(pose, cv::Vec<double, 6>(step.val));
        const cv::Vec<double, 6> candidateTurn = turn + cv::Vec<double, 6>(step.val + 6);
        Fit trial;
        // The move is bounded as the turn is (a move v smears a plane at distance Z about as a
        // turn v / Z does): otherwise the smear's bound could be dodged through the move.
        if (cv::norm(cv::Vec3d(candidateTurn[0], candidateTurn[1], candidateTurn[2])) <= params.maxSmearTurn &&
            cv::norm(cv::Vec3d(candidateTurn[3], candidateTurn[4], candidateTurn[5])) <=
                params.maxSmearTurn * cv::norm(candidate.tvec) &&
            (++out.renders, render(lv, candidate, candidateTurn, params.maxTaps, params.wide)) >= 16 && fitOf(lv, fit.sigma, trial) &&
            trial.cost < fit.cost) {
          pose = candidate;
          turn = candidateTurn;
          acceptedCost = trial.cost;
          mu = std::max(mu * 0.1, 1e-7);
          (void)fitOf(lv, 0, fit);  // the weights follow the new residuals
          accepted = true;
        } else {
          mu *= 10;
        }
      }
      if (!accepted) {
        // The samples hold the last rejected candidate: render the pose again.
        if ((++out.renders, render(lv, pose, turn, params.maxTaps, params.wide)) < 16 || !fitOf(lv, 0, fit)) return false;
        break;
      }
      const double rotation = std::sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
      const double translation = std::sqrt(step[3] * step[3] + step[4] * step[4] + step[5] * step[5]);
      // Converged: the pose moves by less than a hundredth of a level pixel, or the cost by
      // less than 0.1 %.
      const double pixel = (1 << level) / K(0, 0);
      if ((rotation < 0.01 * pixel && translation < 0.01 * pixel * cv::norm(pose.tvec)) ||
          previousCost - acceptedCost < 1e-3 * previousCost)
        break;
    }
  }
  if (lv.count == 0 || fit.valid < 16) return false;
  // The evidence and the covariance at the final pose (the samples hold its render).
  normalEquations(lv, pose, fit, h, b, inliers);
  bool invertible = false;
  const Mat12 hInverse = h.inv(cv::DECOMP_CHOLESKY, &invertible);
  if (!invertible) return false;
  const double meanSmear = meanSmearOf(lv);
  // Neighbouring samples see much the same pixels: along the smear over its length, across it
  // over the pyramid's smoothing (about 2 level pixels).
  const double along = std::max(1.0, (meanSmear + 1.0) / lv.stride);
  const double across = std::max(1.0, 2.0 / lv.stride);
  const double scale = fit.sigma * fit.sigma * along * across;
  const cv::Matx33d r = rotationFromRodrigues(pose.rvec);
  const cv::Matx33d rt = r.t();
  // The pose block of the inverse (the turn marginalized), in world axes: the orientation error
  // is R^T w, the camera centre's -R^T v (first order).
  const auto toWorld = [&](const Mat12& inverse, std::array<double, 36>& covariance) {
    for (int bi = 0; bi < 2; ++bi)
      for (int bj = 0; bj < 2; ++bj) {
        cv::Matx33d block;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) block(i, j) = inverse(bi * 3 + i, bj * 3 + j) * scale;
        const cv::Matx33d world = rt * block * r;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) covariance[static_cast<std::size_t>((bi * 3 + i) * 6 + bj * 3 + j)] = world(i, j);
      }
  };
  toWorld(hInverse, out.covariance);
  out.pose = pose;
  out.smearTurn = cv::Vec3d(turn[0], turn[1], turn[2]);
  out.zncc = fit.zncc;
  out.sigma = fit.sigma;
  out.samples = fit.valid;
  noteCoverage(lv, fit.valid, out);
  out.inlierShare = static_cast<double>(inliers) / fit.valid;
  const DensePartGrid grid = partGridOf(samples_.data(), lv.count);
  DensePartMask agreeing{};
  judgeParts(lv, grid, out, &agreeing);
  out.haveAgreeingCovariance = false;
  if (out.agreeingParts > 0) {
    Mat12 hAgreeing;
    Vec12 bAgreeing;
    int agreeingInliers = 0;
    normalEquations(lv, pose, fit, hAgreeing, bAgreeing, agreeingInliers, &agreeing, &grid);
    bool agreeingInvertible = false;
    const Mat12 agreeingInverse = hAgreeing.inv(cv::DECOMP_CHOLESKY, &agreeingInvertible);
    if (agreeingInvertible) {
      toWorld(agreeingInverse, out.agreeingCovariance);
      out.haveAgreeingCovariance = true;
      for (const double v : out.agreeingCovariance) out.haveAgreeingCovariance = out.haveAgreeingCovariance && std::isfinite(v);
    }
  }
  out.smearPx = meanSmear * (1 << lv.index);
  covarianceSigmas(out.covariance.data(), out.positionSigma, out.rotationSigmaDeg);
  for (const double v : out.covariance)
    if (!std::isfinite(v)) return false;
  return std::isfinite(pose.rvec[0] + pose.rvec[1] + pose.rvec[2] + pose.tvec[0] + pose.tvec[1] + pose.tvec[2] +
                       cv::norm(turn));
}

bool DenseAligner::verify(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame,
                          const cv::Vec3d& smearTurn, const PlanarPose& pose, const DenseAlignmentOptions& params,
                          DenseAlignment& out) noexcept {
  if (capacity_ == 0 || params.fineLevel < 0 || params.fineLevel > frame.levels()) return false;
  Level lv;
  if (!prepareLevel(K, target, frame, pose, params.fineLevel, params, lv)) return false;
  const cv::Vec<double, 6> smear(smearTurn[0], smearTurn[1], smearTurn[2], 0, 0, 0);
  out = DenseAlignment{};
  out.renders = 1;
  if (render(lv, pose, smear, params.maxTaps, params.wide) < 16) return false;
  const Moments moments = momentsOf(samples_.data(), lv.count);
  if (moments.n < 16 || !moments.textured()) return false;
  out.pose = pose;
  out.smearTurn = smearTurn;
  out.zncc = moments.zncc();
  out.samples = moments.n;
  noteCoverage(lv, moments.n, out);
  out.smearPx = meanSmearOf(lv) * (1 << lv.index);
  judgeParts(lv, partGridOf(samples_.data(), lv.count), out);
  return std::isfinite(out.zncc);
}

bool DenseAligner::probe(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame,
                         const cv::Vec3d& smearTurn, const PlanarPose& start, const DenseAlignmentOptions& params,
                         PlanarPose& shifted, double& score) noexcept {
  score = -2;
  if (capacity_ == 0 || params.searchRadius <= 0 || params.coarseLevel < 0) return false;
  Level lv;
  if (!prepareLevel(K, target, frame, start, std::min(params.coarseLevel, frame.levels()), params, lv)) return false;
  const cv::Vec<double, 6> smear(smearTurn[0], smearTurn[1], smearTurn[2], 0, 0, 0);
  if (render(lv, start, smear, params.maxTaps, params.wide) < 16) return false;
  shifted = start;
  return searchShift(lv, params.searchRadius, shifted, score);
}

cv::Vec3d smearTurnFromMotion(const cv::Matx33d& K, const cv::Matx33d& imageMotion, double exposure) noexcept {
  const cv::Matx33d m = K.inv() * imageMotion * K;
  const double det = cv::determinant(m);
  if (!std::isfinite(det) || !(std::abs(det) > 1e-12)) return {0, 0, 0};
  // Scaled to unit determinant, then the nearest rotation.
  const cv::Vec3d w = rodriguesFromRotation(nearestRotation(m * (1.0 / std::cbrt(det))));
  return std::isfinite(w[0] + w[1] + w[2]) ? w * exposure : cv::Vec3d(0, 0, 0);
}

}  // namespace marionette::ar
