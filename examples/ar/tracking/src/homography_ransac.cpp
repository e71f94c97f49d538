#include "homography_ransac.hpp"

#include "marionette/core/split_mix.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>

namespace marionette::ar {

bool symmetricEigen(int n, const double* a, double* values, double* vectors) noexcept {
  if (n < 1 || n > 9) return false;
  double m[81], v[81];
  for (int i = 0; i < n * n; ++i) {
    if (!std::isfinite(a[i])) return false;
    m[i] = a[i];
    v[i] = (i / n == i % n) ? 1.0 : 0.0;
  }
  // Cyclic Jacobi: each rotation zeroes one off-diagonal pair; converges quadratically.
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0, diag = 0;
    for (int p = 0; p < n; ++p) {
      diag += m[p * n + p] * m[p * n + p];
      for (int q = p + 1; q < n; ++q) off += m[p * n + q] * m[p * n + q];
    }
    if (off <= 1e-30 * diag || off == 0) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = m[p * n + q];
        if (apq == 0) continue;
        const double theta = (m[q * n + q] - m[p * n + p]) / (2 * apq);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p, q
          const double kp = m[k * n + p], kq = m[k * n + q];
          m[k * n + p] = c * kp - s * kq;
          m[k * n + q] = s * kp + c * kq;
        }
        for (int k = 0; k < n; ++k) {  // rows p, q
          const double pk = m[p * n + k], qk = m[q * n + k];
          m[p * n + k] = c * pk - s * qk;
          m[q * n + k] = s * pk + c * qk;
        }
        for (int k = 0; k < n; ++k) {
          const double kp = v[k * n + p], kq = v[k * n + q];
          v[k * n + p] = c * kp - s * kq;
          v[k * n + q] = s * kp + c * kq;
        }
      }
  }
  int order[9];
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order, order + n, [&](int x, int y) { return m[x * n + x] < m[y * n + y] || (m[x * n + x] == m[y * n + y] && x < y); });
  for (int i = 0; i < n; ++i) {
    values[i] = m[order[i] * n + order[i]];
    for (int k = 0; k < n; ++k) vectors[i * n + k] = v[k * n + order[i]];
  }
  return true;
}

bool dampedStep(int n, const double* jtj, const double* jtr, double lambda, double tiny, double* step) noexcept {
  if (n < 1 || n > 9) return false;
  double a[81];
  for (int k = 0; k < n * n; ++k) a[k] = jtj[k];
  for (int p = 0; p < n; ++p) {
    a[p * n + p] += lambda * std::max(jtj[p * n + p], 1e-12);
    step[p] = -jtr[p];
  }
  return solveLinear(n, a, step, tiny);
}

bool solveLinear(int n, double* a, double* b, double tiny) noexcept {
  if (n < 1 || n > 9) return false;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    double column = 0;
    for (int r = c; r < n; ++r) {
      column = std::max(column, std::abs(a[r * n + c]));
      if (std::abs(a[r * n + c]) > std::abs(a[pivot * n + c])) pivot = r;
    }
    if (!(std::abs(a[pivot * n + c]) > tiny * column) || column == 0) return false;
    if (pivot != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[pivot * n + k]);
      std::swap(b[c], b[pivot]);
    }
    const double inv = 1 / a[c * n + c];
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] * inv;
      if (f == 0) continue;
      for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < n; ++k) s -= a[r * n + k] * b[k];
    b[r] = s / a[r * n + r];
    if (!std::isfinite(b[r])) return false;
  }
  return true;
}

namespace {

using marionette::SplitMix64;  // the same sequence on every platform

double cross(const cv::Point2d& o, const cv::Point2d& a, const cv::Point2d& b) noexcept {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// A sample a homography can map: no three points (nearly) collinear in either set, and every
// triple turning the same way in both sets or every one the other way (a homography keeping
// the four on one side of its horizon keeps or flips all orientations together).
bool sampleIsUsable(const cv::Point2d* s[4], const cv::Point2d* d[4]) noexcept {
  constexpr int kTriples[4][3] = {{0, 1, 2}, {1, 2, 3}, {2, 3, 0}, {3, 0, 1}};
  int flipped = 0;
  for (const auto& t : kTriples) {
    const double cs = cross(*s[t[0]], *s[t[1]], *s[t[2]]), cd = cross(*d[t[0]], *d[t[1]], *d[t[2]]);
    const double ns = cv::norm(*s[t[1]] - *s[t[0]]) * cv::norm(*s[t[2]] - *s[t[0]]);
    const double nd = cv::norm(*d[t[1]] - *d[t[0]]) * cv::norm(*d[t[2]] - *d[t[0]]);
    if (!(std::abs(cs) > 1e-3 * ns) || !(std::abs(cd) > 1e-3 * nd)) return false;
    flipped += (cs < 0) != (cd < 0);
  }
  return flipped == 0 || flipped == 4;
}

// The homography through 4 pairs: 8 equations, h33 = 1 (in normalized coordinates the
// sample's points are near the origin, which no usable homography sends to infinity).
bool solveMinimal(const cv::Point2d* s[4], const cv::Point2d* d[4], cv::Matx33d& h) noexcept {
  double a[64] = {}, b[8];
  for (int i = 0; i < 4; ++i) {
    const double x = s[i]->x, y = s[i]->y, u = d[i]->x, v = d[i]->y;
    double* r0 = a + (2 * i) * 8;
    double* r1 = r0 + 8;
    r0[0] = x, r0[1] = y, r0[2] = 1, r0[6] = -u * x, r0[7] = -u * y;
    r1[3] = x, r1[4] = y, r1[5] = 1, r1[6] = -v * x, r1[7] = -v * y;
    b[2 * i] = u;
    b[2 * i + 1] = v;
  }
  if (!solveLinear(8, a, b, 1e-10)) return false;
  h = cv::Matx33d(b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], 1.0);
  return true;
}

// Squared distance from h(s) to d; infinite when s maps to (or beyond) the horizon.
double transferError2(const cv::Matx33d& h, const cv::Point2d& s, const cv::Point2d& d) noexcept {
  const double w = h(2, 0) * s.x + h(2, 1) * s.y + h(2, 2);
  if (!(std::abs(w) > 1e-12)) return HUGE_VAL;
  const double u = (h(0, 0) * s.x + h(0, 1) * s.y + h(0, 2)) / w - d.x;
  const double v = (h(1, 0) * s.x + h(1, 1) * s.y + h(1, 2)) / w - d.y;
  return u * u + v * v;
}

// OpenCV's rule: enough iterations to draw one all-inlier sample with `confidence`.
int iterationsNeeded(double confidence, double inlierShare, int maxIterations) noexcept {
  const double num = std::log(std::max(1 - confidence, DBL_MIN));
  const double allInliers = std::pow(inlierShare, 4);
  const double denom = 1 - allInliers;
  if (denom < DBL_MIN) return 0;
  const double logDenom = std::log(denom);
  if (logDenom >= 0 || -num >= maxIterations * -logDenom) return maxIterations;
  return static_cast<int>(std::lround(num / logDenom));
}

}  // namespace

void HomographyRansac::reserve(std::size_t maxPoints) {
  capacity_ = maxPoints;
  src_.resize(maxPoints);
  dst_.resize(maxPoints);
  index_.resize(maxPoints);
  best_.resize(maxPoints);
  current_.resize(maxPoints);
}

std::size_t HomographyRansac::normalize(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst,
                                        std::span<const std::uint8_t> mask) noexcept {
  std::size_t n = 0;
  cv::Point2d cs(0, 0), cd(0, 0);
  for (std::size_t i = 0; i < src.size(); ++i) {
    if (!mask.empty() && !mask[i]) continue;
    const cv::Point2f& s = src[i];
    const cv::Point2f& d = dst[i];
    if (!std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(d.x) || !std::isfinite(d.y)) continue;
    src_[n] = cv::Point2d(s.x, s.y);
    dst_[n] = cv::Point2d(d.x, d.y);
    index_[n++] = i;
    cs += src_[n - 1];
    cd += dst_[n - 1];
  }
  if (n == 0) return 0;
  cs *= 1.0 / static_cast<double>(n);
  cd *= 1.0 / static_cast<double>(n);
  double ms = 0, md = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ms += cv::norm(src_[i] - cs);
    md += cv::norm(dst_[i] - cd);
  }
  const double ss = ms > 0 ? std::sqrt(2.0) * static_cast<double>(n) / ms : 1.0;
  const double sd = md > 0 ? std::sqrt(2.0) * static_cast<double>(n) / md : 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    src_[i] = (src_[i] - cs) * ss;
    dst_[i] = (dst_[i] - cd) * sd;
  }
  srcToNormal_ = cv::Matx33d(ss, 0, -ss * cs.x, 0, ss, -ss * cs.y, 0, 0, 1);
  dstToNormal_ = cv::Matx33d(sd, 0, -sd * cd.x, 0, sd, -sd * cd.y, 0, 0, 1);
  dstScale_ = sd;
  return n;
}

namespace {

// Normalized DLT over the used pairs: the eigenvector of A^T A with the smallest eigenvalue.
// Degenerate (false) when a second eigenvalue is near zero too: the pairs fit a family.
bool leastSquares(const cv::Point2d* src, const cv::Point2d* dst, const std::uint8_t* use, std::size_t n,
                  cv::Matx33d& h) noexcept {
  double ata[81] = {};
  int used = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (use && !use[i]) continue;
    ++used;
    const double x = src[i].x, y = src[i].y, u = dst[i].x, v = dst[i].y;
    const double r0[9] = {-x, -y, -1, 0, 0, 0, u * x, u * y, u};
    const double r1[9] = {0, 0, 0, -x, -y, -1, v * x, v * y, v};
    for (int p = 0; p < 9; ++p)
      for (int q = p; q < 9; ++q) ata[p * 9 + q] += r0[p] * r0[q] + r1[p] * r1[q];
  }
  if (used < 4) return false;
  for (int p = 0; p < 9; ++p)
    for (int q = 0; q < p; ++q) ata[p * 9 + q] = ata[q * 9 + p];
  double values[9], vectors[81];
  if (!symmetricEigen(9, ata, values, vectors)) return false;
  if (!(values[1] > 1e-9 * values[8])) return false;
  for (int i = 0; i < 9; ++i) h.val[i] = vectors[i];
  if (!(std::abs(h(2, 2)) > 1e-12)) return false;
  h *= 1.0 / h(2, 2);
  return true;
}

double cost(const cv::Matx33d& h, const cv::Point2d* src, const cv::Point2d* dst, const std::uint8_t* use,
            std::size_t n) noexcept {
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!use || use[i]) sum += transferError2(h, src[i], dst[i]);
  return sum;
}

// Levenberg-Marquardt on the 8 free entries (h33 = 1) over the squared transfer error.
void levenbergMarquardt(const cv::Point2d* src, const cv::Point2d* dst, const std::uint8_t* use, std::size_t n,
                        int iterations, cv::Matx33d& h) noexcept {
  double lambda = 1e-3, current = cost(h, src, dst, use, n);
  for (int it = 0; it < iterations && std::isfinite(current); ++it) {
    double jtj[64] = {}, jtr[8] = {};
    for (std::size_t i = 0; i < n; ++i) {
      if (use && !use[i]) continue;
      const double x = src[i].x, y = src[i].y;
      const double w = h(2, 0) * x + h(2, 1) * y + h(2, 2);
      if (!(std::abs(w) > 1e-12)) continue;
      const double iw = 1 / w;
      const double u = (h(0, 0) * x + h(0, 1) * y + h(0, 2)) * iw, v = (h(1, 0) * x + h(1, 1) * y + h(1, 2)) * iw;
      const double ju[8] = {x * iw, y * iw, iw, 0, 0, 0, -u * x * iw, -u * y * iw};
      const double jv[8] = {0, 0, 0, x * iw, y * iw, iw, -v * x * iw, -v * y * iw};
      const double ru = u - dst[i].x, rv = v - dst[i].y;
      for (int p = 0; p < 8; ++p) {
        jtr[p] += ju[p] * ru + jv[p] * rv;
        for (int q = p; q < 8; ++q) jtj[p * 8 + q] += ju[p] * ju[q] + jv[p] * jv[q];
      }
    }
    for (int p = 0; p < 8; ++p)
      for (int q = 0; q < p; ++q) jtj[p * 8 + q] = jtj[q * 8 + p];
    bool improved = false;
    while (!improved && lambda < 1e10) {
      double step[8];
      if (!dampedStep(8, jtj, jtr, lambda, 1e-14, step)) {
        lambda *= 10;
        continue;
      }
      cv::Matx33d trial = h;
      for (int p = 0; p < 8; ++p) trial.val[p] += step[p];
      const double c = cost(trial, src, dst, use, n);
      if (c < current) {
        h = trial;
        current = c;
        lambda = std::max(lambda * 0.1, 1e-12);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;  // at the minimum (to rounding)
  }
}

}  // namespace

bool HomographyRansac::finish(const std::uint8_t* use, std::size_t n, int refineIterations, cv::Matx33d& h) noexcept {
  cv::Matx33d model;
  if (!leastSquares(src_.data(), dst_.data(), use, n, model)) return false;
  levenbergMarquardt(src_.data(), dst_.data(), use, n, refineIterations, model);
  // Back from normalized coordinates: dst = Tdst^-1 model Tsrc.
  const double sd = dstToNormal_(0, 0);
  const cv::Matx33d fromNormal(1 / sd, 0, -dstToNormal_(0, 2) / sd, 0, 1 / sd, -dstToNormal_(1, 2) / sd, 0, 0, 1);
  cv::Matx33d out = fromNormal * model * srcToNormal_;
  if (!(std::abs(out(2, 2)) > 1e-300)) return false;
  out *= 1.0 / out(2, 2);
  for (double v : out.val)
    if (!std::isfinite(v)) return false;
  h = out;
  return true;
}

bool HomographyRansac::estimate(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst,
                                const HomographyRansacOptions& params, cv::Matx33d& h, std::span<std::uint8_t> mask,
                                int& inliers) noexcept {
  inliers = 0;
  for (std::uint8_t& m : mask) m = 0;
  if (src.size() != dst.size() || mask.size() < src.size() || src.size() > capacity_ || src.size() < 4 ||
      !(params.thresholdPx > 0) || params.maxIterations < 1)
    return false;
  const std::size_t n = normalize(src, dst, {});
  if (n < 4) return false;
  const double threshold2 = params.thresholdPx * dstScale_ * params.thresholdPx * dstScale_;
  SplitMix64 rng{params.seed};
  int needed = params.maxIterations, bestCount = 0;
  constexpr int kMaxDraws = 1000;  // unusable samples in a row before giving up (all collinear)
  for (int iteration = 0; iteration < needed; ++iteration) {
    const cv::Point2d* s[4];
    const cv::Point2d* d[4];
    bool usable = false;
    for (int draw = 0; draw < kMaxDraws && !usable; ++draw) {
      std::size_t pick[4];
      for (int k = 0; k < 4; ++k) {
        bool repeated;
        do {
          pick[k] = static_cast<std::size_t>(rng.next() % n);
          repeated = false;
          for (int j = 0; j < k; ++j) repeated = repeated || pick[j] == pick[k];
        } while (repeated);
        s[k] = &src_[pick[k]];
        d[k] = &dst_[pick[k]];
      }
      usable = sampleIsUsable(s, d);
    }
    if (!usable) break;
    cv::Matx33d model;
    if (!solveMinimal(s, d, model)) continue;
    int count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const bool in = transferError2(model, src_[i], dst_[i]) <= threshold2;
      current_[i] = in;
      count += in;
    }
    if (count > bestCount) {
      bestCount = count;
      std::swap(best_, current_);
      needed = std::min(needed, iterationsNeeded(params.confidence, double(count) / double(n), params.maxIterations));
    }
  }
  if (bestCount < 4) return false;
  if (!finish(best_.data(), n, params.refineIterations, h)) return false;
  for (std::size_t i = 0; i < n; ++i) mask[index_[i]] = best_[i];
  inliers = bestCount;
  return true;
}

bool HomographyRansac::fit(std::span<const cv::Point2f> src, std::span<const cv::Point2f> dst,
                           std::span<const std::uint8_t> mask, int refineIterations, cv::Matx33d& h) noexcept {
  if (src.size() != dst.size() || src.size() > capacity_ || (!mask.empty() && mask.size() < src.size())) return false;
  const std::size_t n = normalize(src, dst, mask);
  return n >= 4 && finish(nullptr, n, refineIterations, h);
}

}  // namespace marionette::ar
