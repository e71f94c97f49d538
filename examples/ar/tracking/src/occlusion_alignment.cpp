// Steps 2 and 3 of the occlusion mask (target_occlusion.hpp): the pose's residual error as a shift
// field, searched part by part of the target's image, and the frame's motion blur, matched by
// blurring the reference along a line where that makes the two agree better.
#include "target_occlusion_impl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace marionette::ar {

namespace {

// The shift search: a part's best correlation must reach this to set its own shift (the whole's
// to set any), over at least this many pixels with at least kPartSigma grey levels of texture.
constexpr double kPartNcc = 0.4, kWholeNcc = 0.3, kPartSigma = 4.0;
constexpr int kPartMinPixels = 30;
// The blur's direction counts where the normalised tensors differ by this much along it, and
// the blur is kept where it raises the agreeing parts' correlation by this much.
constexpr double kMinAnisotropy = 0.04, kMinBlurGain = 0.01;

// Sub-pixel offset of a parabola's peak through (-1, a), (0, b), (1, c), within +-0.5.
double parabolaPeak(double a, double b, double c) noexcept {
  const double d = a - 2 * b + c;
  if (!(d < -1e-12)) return 0.0;
  return std::clamp(0.5 * (a - c) / d, -0.5, 0.5);
}

}  // namespace

void TargetOcclusion::Impl::searchShift(const Box& t, const Box& w) noexcept {
  // Parts: kParts x kParts over the target's box (edges in partEdges: x then y).
  for (int k = 0; k <= kParts; ++k) {
    partEdges[static_cast<std::size_t>(k)] = t.x0 + (t.x1 - t.x0) * k / kParts;
    partEdges[static_cast<std::size_t>(kParts + 1 + k)] = t.y0 + (t.y1 - t.y0) * k / kParts;
  }
  const int r = s.searchRadius, side = 2 * r + 1, shifts = side * side;
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) shiftX[at(x, y)] = shiftY[at(x, y)] = 0;
  mask.shiftX = mask.shiftY = 0;
  if (r == 0) return;
  partSums.fill({});
  // Every pixel, or every other one both ways on a large target (a part then still has hundreds).
  const int stride = static_cast<long>(t.x1 - t.x0) * (t.y1 - t.y0) > kDenseBoxPixels ? 2 : 1;
  for (int py = 0; py < kParts; ++py)
    for (int px = 0; px < kParts; ++px) {
      const int part = py * kParts + px;
      for (int y = partEdges[static_cast<std::size_t>(kParts + 1 + py)];
           y < partEdges[static_cast<std::size_t>(kParts + 2 + py)]; y += stride)
        for (int x = partEdges[static_cast<std::size_t>(px)]; x < partEdges[static_cast<std::size_t>(px + 1)]; x += stride) {
          const std::size_t i = at(x, y);
          if (cover[i] < kInside || clipped(F[i])) continue;
          const double f = F[i] - kGreyBias;
          for (int dy = -r; dy <= r; ++dy) {
            const int yy = y + dy;
            if (yy < w.y0 || yy >= w.y1) continue;
            for (int dx = -r; dx <= r; ++dx) {
              const int xx = x + dx;
              if (xx < w.x0 || xx >= w.x1) continue;
              const float rv = R0[at(xx, yy)];
              if (std::isnan(rv)) continue;
              partSums[static_cast<std::size_t>(part * kMaxShifts + (dy + r) * side + (dx + r))].add(f, rv - kGreyBias);
            }
          }
        }
    }
  // The best shift of a set of sums (one part's, or the whole's), sub-pixel; false when nothing
  // correlates enough.
  auto best = [&](const Sums* at, double minNcc, double& sx, double& sy) {
    const Sums& centre = at[r * side + r];
    if (centre.n < kPartMinPixels || std::sqrt(centre.varR()) < kPartSigma) return false;
    int bi = r * side + r;
    double bn = centre.ncc();
    for (int k = 0; k < shifts; ++k)
      if (at[k].n >= kPartMinPixels && at[k].ncc() > bn) bn = at[k].ncc(), bi = k;
    if (bn < minNcc) return false;
    const int bx = bi % side - r, by = bi / side - r;
    sx = bx, sy = by;
    if (bx > -r && bx < r) sx += parabolaPeak(at[bi - 1].ncc(), bn, at[bi + 1].ncc());
    if (by > -r && by < r) sy += parabolaPeak(at[bi - side].ncc(), bn, at[bi + side].ncc());
    return true;
  };
  std::array<Sums, kMaxShifts> whole{};
  for (int part = 0; part < kParts * kParts; ++part)
    for (int k = 0; k < shifts; ++k) whole[static_cast<std::size_t>(k)] += partSums[static_cast<std::size_t>(part * kMaxShifts + k)];
  double wx = 0, wy = 0;
  if (!best(whole.data(), kWholeNcc, wx, wy)) return;  // nothing correlates: no shift at all
  std::array<double, kParts * kParts> px{}, py{};
  for (int part = 0; part < kParts * kParts; ++part) {
    double sx = wx, sy = wy;
    if (!best(&partSums[static_cast<std::size_t>(part * kMaxShifts)], kPartNcc, sx, sy)) sx = wx, sy = wy;
    px[static_cast<std::size_t>(part)] = sx, py[static_cast<std::size_t>(part)] = sy;
  }
  mask.shiftX = wx, mask.shiftY = wy;
  // The field: bilinear between the parts' centres, constant beyond them.
  const double cw = (t.x1 - t.x0) / double(kParts), chh = (t.y1 - t.y0) / double(kParts);
  for (int y = w.y0; y < w.y1; ++y) {
    const double fy = std::clamp((y - t.y0 + 0.5) / chh - 0.5, 0.0, kParts - 1.0);
    const int y0 = std::min(static_cast<int>(fy), kParts - 2);
    const double ay = fy - y0;
    for (int x = w.x0; x < w.x1; ++x) {
      const double fx = std::clamp((x - t.x0 + 0.5) / cw - 0.5, 0.0, kParts - 1.0);
      const int x0 = std::min(static_cast<int>(fx), kParts - 2);
      const double ax = fx - x0;
      auto field = [&](const std::array<double, kParts * kParts>& f) {
        const auto k = [](int a, int b) { return static_cast<std::size_t>(b * kParts + a); };
        return (f[k(x0, y0)] * (1 - ax) + f[k(x0 + 1, y0)] * ax) * (1 - ay) +
               (f[k(x0, y0 + 1)] * (1 - ax) + f[k(x0 + 1, y0 + 1)] * ax) * ay;
      };
      shiftX[at(x, y)] = static_cast<float>(field(px));
      shiftY[at(x, y)] = static_cast<float>(field(py));
    }
  }
}

void TargetOcclusion::Impl::shiftReference(const Box& w) noexcept {
  // R(p) = R0(p + shift(p)), bilinear in R0's grid (its own pixel where a tap has no value).
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      R[i] = R0[i];
      if (std::isnan(R0[i]) || (shiftX[i] == 0 && shiftY[i] == 0)) continue;
      const float sx = static_cast<float>(x) + shiftX[i], sy = static_cast<float>(y) + shiftY[i];
      const int x0 = static_cast<int>(std::floor(sx)), y0 = static_cast<int>(std::floor(sy));
      if (x0 < w.x0 || y0 < w.y0 || x0 + 1 >= w.x1 || y0 + 1 >= w.y1) continue;
      const std::size_t j = at(x0, y0), row = static_cast<std::size_t>(mw);
      const float ax = sx - static_cast<float>(x0), ay = sy - static_cast<float>(y0);
      const float value = (R0[j] * (1 - ax) + R0[j + 1] * ax) * (1 - ay) + (R0[j + row] * (1 - ax) + R0[j + row + 1] * ax) * ay;
      if (!std::isnan(value)) R[i] = value;
    }
}

void TargetOcclusion::Impl::partSumsOf(const std::vector<float>& ref, std::array<Sums, kParts * kParts>& parts) const noexcept {
  parts.fill({});
  for (int py = 0; py < kParts; ++py)
    for (int px = 0; px < kParts; ++px) {
      Sums& sum = parts[static_cast<std::size_t>(py * kParts + px)];
      for (int y = partEdges[static_cast<std::size_t>(kParts + 1 + py)];
           y < partEdges[static_cast<std::size_t>(kParts + 2 + py)]; ++y)
        for (int x = partEdges[static_cast<std::size_t>(px)]; x < partEdges[static_cast<std::size_t>(px + 1)]; ++x) {
          const std::size_t i = at(x, y);
          if (cover[i] >= kInside && !std::isnan(ref[i]) && !clipped(F[i])) sum.add(F[i] - kGreyBias, ref[i] - kGreyBias);
        }
    }
}

double TargetOcclusion::Impl::betterHalfNcc(const std::array<Sums, kParts * kParts>& parts) noexcept {
  std::array<double, kParts * kParts> ncc{};
  int k = 0;
  for (const Sums& p : parts)
    if (p.n >= kPartMinPixels && std::sqrt(p.varR()) >= kPartSigma) ncc[static_cast<std::size_t>(k++)] = p.ncc();
  if (k == 0) return -1;
  std::sort(ncc.begin(), ncc.begin() + k, std::greater<>());
  const int half = (k + 1) / 2;
  double sum = 0;
  for (int j = 0; j < half; ++j) sum += ncc[static_cast<std::size_t>(j)];
  return sum / half;
}

namespace {
// `row`: the grid's width (the taps' offsets in it).
void makeLineKernel(double length, double angle, int row, LineKernel& k) noexcept {
  // Taps a pixel apart at most along the line, centred; each tap's bilinear weights land on the
  // same four neighbours for every pixel (their offsets are the same): one small kernel.
  constexpr int side = 2 * LineKernel::kRadius + 1;
  std::array<float, side * side> grid{};
  const int taps = std::max(2, static_cast<int>(std::ceil(length)) + 1);
  const double dx = std::cos(angle) * length / (taps - 1), dy = std::sin(angle) * length / (taps - 1);
  for (int j = 0; j < taps; ++j) {
    const double o = j - 0.5 * (taps - 1);
    const double tx = o * dx, ty = o * dy;
    const int x0 = static_cast<int>(std::floor(tx)), y0 = static_cast<int>(std::floor(ty));
    const float ax = static_cast<float>(tx - x0), ay = static_cast<float>(ty - y0);
    const float weights[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
    for (int c = 0; c < 4; ++c) {
      const int gx = std::clamp(x0 + (c & 1) + LineKernel::kRadius, 0, side - 1);
      const int gy = std::clamp(y0 + (c >> 1) + LineKernel::kRadius, 0, side - 1);
      grid[static_cast<std::size_t>(gy * side + gx)] += weights[c] / static_cast<float>(taps);
    }
  }
  k.n = 0, k.reach = 0;
  for (int gy = 0; gy < side; ++gy)
    for (int gx = 0; gx < side; ++gx) {
      const float wgt = grid[static_cast<std::size_t>(gy * side + gx)];
      if (wgt <= 0) continue;
      const auto e = static_cast<std::size_t>(k.n++);
      k.dx[e] = gx - LineKernel::kRadius, k.dy[e] = gy - LineKernel::kRadius, k.w[e] = wgt;
      k.offset[e] = static_cast<std::ptrdiff_t>(k.dy[e]) * row + k.dx[e];
      k.reach = std::max({k.reach, std::abs(k.dx[e]), std::abs(k.dy[e])});
    }
}
}  // namespace

float TargetOcclusion::Impl::applyKernel(const LineKernel& k, const std::vector<float>& g, const Box& w, int x,
                                         int y) const noexcept {
  float sum = 0;
  if (x - k.reach >= w.x0 && x + k.reach < w.x1 && y - k.reach >= w.y0 && y + k.reach < w.y1) {
    const float* c = g.data() + at(x, y);  // every tap inside w: no clamping
    for (int e = 0; e < k.n; ++e) sum += k.w[static_cast<std::size_t>(e)] * c[k.offset[static_cast<std::size_t>(e)]];
    return sum;
  }
  for (int e = 0; e < k.n; ++e) {
    const auto j = static_cast<std::size_t>(e);
    sum += k.w[j] * g[at(std::clamp(x + k.dx[j], w.x0, w.x1 - 1), std::clamp(y + k.dy[j], w.y0, w.y1 - 1))];
  }
  return sum;
}

void TargetOcclusion::Impl::lineBlur(const Box& w, const LineKernel& k, std::vector<float>& dst) const noexcept {
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      dst[i] = std::isnan(dst[i]) ? kNaN : applyKernel(k, R, w, x, y);  // dst keeps R's NaNs (matchBlur)
    }
}

void TargetOcclusion::Impl::matchBlur(const Box& w) noexcept {
  mask.blurLength = 0, mask.blurAngleRad = 0;
  std::copy(R.begin(), R.end(), Rb.begin());  // (the whole grid: cheap beside the rest, and simple)
  if (!s.matchBlur) return;
  // R (NaN-free over w where the ray meets the plane) with NaNs replaced for the blur's taps.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x)
      if (std::isnan(R[at(x, y)])) R[at(x, y)] = kGreyBias;
  // Which parts show the target (their correlation at the aligned pose): the statistics come
  // from them alone, so that a hand does not count as blur.
  std::array<Sums, kParts * kParts> parts{};
  partSumsOf(R, parts);
  std::array<bool, kParts * kParts> use{};
  int used = 0;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].n >= kPartMinPixels && std::sqrt(parts[k].varR()) >= kPartSigma && parts[k].ncc() >= 0.5)
      use[k] = true, ++used;
  if (used == 0) return;
  // The reference's gradient over w (0 off the target), and the gradient structure tensors of
  // the frame and the reference over the parts used.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      const bool interior = x > w.x0 && y > w.y0 && x + 1 < w.x1 && y + 1 < w.y1 && cover[i] >= kInside;
      gx[i] = interior ? 0.5f * (R[i + 1] - R[i - 1]) : 0.0f;
      gy[i] = interior ? 0.5f * (R[i + static_cast<std::size_t>(mw)] - R[i - static_cast<std::size_t>(mw)]) : 0.0f;
    }
  double tf[3] = {0, 0, 0}, tr[3] = {0, 0, 0};
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (!use[k]) continue;
    const int px = static_cast<int>(k) % kParts, py = static_cast<int>(k) / kParts;
    for (int y = std::max(partEdges[static_cast<std::size_t>(kParts + 1 + py)], w.y0 + 1);
         y < std::min(partEdges[static_cast<std::size_t>(kParts + 2 + py)], w.y1 - 1); ++y)
      for (int x = std::max(partEdges[static_cast<std::size_t>(px)], w.x0 + 1);
           x < std::min(partEdges[static_cast<std::size_t>(px + 1)], w.x1 - 1); ++x) {
        const std::size_t i = at(x, y);
        if (cover[i] < kInside || clipped(F[i])) continue;
        const double fx = 0.5 * (F[i + 1] - F[i - 1]), fy = 0.5 * (F[i + static_cast<std::size_t>(mw)] - F[i - static_cast<std::size_t>(mw)]);
        const double rx = 0.5 * (R[i + 1] - R[i - 1]), ry = 0.5 * (R[i + static_cast<std::size_t>(mw)] - R[i - static_cast<std::size_t>(mw)]);
        tf[0] += fx * fx, tf[1] += fx * fy, tf[2] += fy * fy;
        tr[0] += rx * rx, tr[1] += rx * ry, tr[2] += ry * ry;
      }
  }
  const double traceF = tf[0] + tf[2], traceR = tr[0] + tr[2];
  if (!(traceF > 1e-9) || !(traceR > 1e-9)) return;
  // The direction that lost the largest share of the gradient energy.
  const double a = tr[0] / traceR - tf[0] / traceF, b = tr[1] / traceR - tf[1] / traceF, c = tr[2] / traceR - tf[2] / traceF;
  const double lambda = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  if (lambda < kMinAnisotropy) return;
  const double angle = 0.5 * std::atan2(2 * b, a - c);
  const double ca = std::cos(angle), sa = std::sin(angle);
  const double targetShare = (ca * ca * tf[0] + 2 * ca * sa * tf[1] + sa * sa * tf[2]) / traceF;
  // The share along it of the reference's gradient blurred by a line of `length` (the blur of the
  // gradient, bilinear taps a pixel apart at most: every other pixel of the parts used both ways,
  // every fourth on a large target).
  const int stride = static_cast<long>(w.x1 - w.x0) * (w.y1 - w.y0) > 2 * kDenseBoxPixels ? 4 : 2;
  auto shareAt = [&](double length) {
    makeLineKernel(length, angle, mw, kernel);
    double t0 = 0, t1 = 0, t2 = 0;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (!use[k]) continue;
      const int px = static_cast<int>(k) % kParts, py = static_cast<int>(k) / kParts;
      for (int y = std::max(partEdges[static_cast<std::size_t>(kParts + 1 + py)], w.y0 + 1);
           y < std::min(partEdges[static_cast<std::size_t>(kParts + 2 + py)], w.y1 - 1); y += stride)
        for (int x = std::max(partEdges[static_cast<std::size_t>(px)], w.x0 + 1);
             x < std::min(partEdges[static_cast<std::size_t>(px + 1)], w.x1 - 1); x += stride) {
          if (cover[at(x, y)] < kInside) continue;
          // (Off the target the gradient is 0.)
          const float sx = applyKernel(kernel, gx, w, x, y), sy = applyKernel(kernel, gy, w, x, y);
          t0 += double(sx) * sx, t1 += double(sx) * sy, t2 += double(sy) * sy;
        }
    }
    const double trace = t0 + t2;
    return trace > 1e-12 ? (ca * ca * t0 + 2 * ca * sa * t1 + sa * sa * t2) / trace : 0.0;
  };
  if (shareAt(0) <= targetShare) return;
  double lo = 0, hi = kMaxBlurLength;
  if (shareAt(hi) > targetShare) {
    lo = hi;
  } else {
    for (int it = 0; it < 6; ++it) {
      const double mid = 0.5 * (lo + hi);
      (shareAt(mid) > targetShare ? lo : hi) = mid;
    }
  }
  const double length = 0.5 * (lo + hi);
  if (length < 1.0) return;
  makeLineKernel(length, angle, mw, kernel);
  lineBlur(w, kernel, Rb);
  // Kept only where it makes the parts that show the target agree better.
  std::array<Sums, kParts * kParts> blurred{};
  partSumsOf(Rb, blurred);
  if (betterHalfNcc(blurred) < betterHalfNcc(parts) + kMinBlurGain) {
    for (int y = w.y0; y < w.y1; ++y)  // back to R, the rays that miss the plane still NaN
      for (int x = w.x0; x < w.x1; ++x)
        if (!std::isnan(Rb[at(x, y)])) Rb[at(x, y)] = R[at(x, y)];
    return;
  }
  mask.blurLength = length, mask.blurAngleRad = angle;
}

}  // namespace marionette::ar
