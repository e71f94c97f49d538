// Steps 4 and 5 of the occlusion mask (target_occlusion.hpp): the window sums the comparison
// reads, the frame's gain and bias against the reference, each mask pixel's verdict, and the
// cleaning that turns the verdicts into the mask.
#include "target_occlusion_impl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace marionette::ar {

namespace {

// The photometric fit: windows whose correlation reaches this, with texture, not saturated.
constexpr double kFitNcc = 0.8;
// A textured window's verdict of hidden is weakened for a pixel whose own value agrees with the
// reference's (within kOwnLow of the intensity tolerance; not from kOwnHigh), unless the window
// correlates kOwnNcc below hiddenNcc: a window that straddles the edge of a hand correlates
// poorly on both sides of it.
constexpr float kOwnLow = 0.25f, kOwnHigh = 0.5f, kOwnNcc = 0.2f;
// A pixel's own disagreement is hidden from kPixelTol of the intensity tolerance plus kEdgeTol
// times the reference's gradient (grey levels per mask pixel: a mask pixel's misalignment), in full
// from kPixelRamp times that.
constexpr float kPixelTol = 0.7f, kEdgeTol = 1.0f, kPixelRamp = 1.5f;

inline float ramp(float v, float lo, float hi) noexcept { return clamp01((v - lo) / (hi - lo)); }

// The median of nine values (a sorting network's exchanges, branch-free).
inline float median9(float* p) noexcept {
  auto s = [p](int a, int b) {
    const float lo = std::min(p[a], p[b]), hi = std::max(p[a], p[b]);
    p[a] = lo, p[b] = hi;
  };
  s(1, 2), s(4, 5), s(7, 8), s(0, 1), s(3, 4), s(6, 7), s(1, 2), s(4, 5), s(7, 8), s(0, 3), s(5, 8), s(4, 7), s(3, 6),
      s(1, 4), s(2, 5), s(4, 7), s(4, 2), s(6, 4), s(4, 2);
  return p[4];
}

}  // namespace

void TargetOcclusion::Impl::windowSums(const Box& w) noexcept {
  // Separable box sums over the window of the weight (wholly on the target, not clipped), and the
  // weighted frame, reference and their products; centred on kGreyBias for float's sake. The
  // same over 3 x 3 (inner): the finer of the two verdicts.
  for (int y = w.y0; y < w.y1; ++y)
    for (int x = w.x0; x < w.x1; ++x) {
      const std::size_t i = at(x, y);
      const bool on = cover[i] >= kInside && !std::isnan(Rb[i]) && !clipped(F[i]);
      const float f = on ? F[i] - kGreyBias : 0.0f, rv = on ? Rb[i] - kGreyBias : 0.0f;
      sums[0][i] = on ? 1.0f : 0.0f;
      sums[1][i] = f, sums[2][i] = rv, sums[3][i] = f * f, sums[4][i] = rv * rv, sums[5][i] = f * rv;
    }
  // Rows of shifted copies added (contiguous: the compiler's vectors), then rows added.
  auto box = [&](const std::vector<float>& q, std::vector<float>& dst, int r) {
    for (int y = w.y0; y < w.y1; ++y) {
      const float* in = q.data() + at(0, y);
      float* row = tmp.data() + at(0, y);
      std::fill(row + w.x0, row + w.x1, 0.0f);
      for (int d = -r; d <= r; ++d)
        for (int x = std::max(w.x0, w.x0 - d); x < std::min(w.x1, w.x1 - d); ++x) row[x] += in[x + d];
    }
    for (int y = w.y0; y < w.y1; ++y) {
      float* row = dst.data() + at(0, y);
      std::fill(row + w.x0, row + w.x1, 0.0f);
      for (int d = std::max(w.y0, y - r); d <= std::min(w.y1 - 1, y + r); ++d) {
        const float* in = tmp.data() + at(0, d);
        for (int x = w.x0; x < w.x1; ++x) row[x] += in[x];
      }
    }
  };
  for (std::size_t k = 0; k < sums.size(); ++k) {
    if (s.fineWeight > 0) box(sums[k], inner[k], 1);
    box(sums[k], sums[k], s.window / 2);
  }
}

void TargetOcclusion::Impl::photometricModel(const Box& t, double& gain, double& bias) noexcept {
  // The frame's grey as gain x reference + bias, from the windows that clearly show the target
  // (textured, correlating, not saturated): a least-squares line through their means (means do
  // not suffer from a blur that contrasts do), refitted without the residuals past 3 MADs; with
  // too narrow a range of means, the contrast ratio and the mean offset.
  const float area = static_cast<float>(s.window * s.window);
  fitR.clear(), fitF.clear(), fitSigmaF.clear(), fitSigmaR.clear();
  double allN = 0, allF = 0, allR = 0, allFF = 0, allRR = 0;
  const int stride = static_cast<long>(t.x1 - t.x0) * (t.y1 - t.y0) > kDenseBoxPixels ? 2 : 1;
  for (int y = t.y0; y < t.y1; y += stride)
    for (int x = t.x0; x < t.x1; x += stride) {
      const std::size_t i = at(x, y);
      const float n = sums[0][i];
      if (cover[i] < kInside || n < 0.6f * area) continue;
      const double mf = sums[1][i] / n, mr = sums[2][i] / n;
      const double vf = std::max(0.0, sums[3][i] / n - mf * mf), vr = std::max(0.0, sums[4][i] / n - mr * mr);
      const double c = sums[5][i] / n - mf * mr;
      allN += 1, allF += mf, allR += mr, allFF += vf, allRR += vr;
      if (std::sqrt(vr) < s.texturedSigma || !(vf > 1e-6)) continue;
      if (c / std::sqrt(vf * vr) < kFitNcc) continue;
      const double mF = mf + kGreyBias;
      if (mF < 8 || mF > 247) continue;
      fitR.push_back(mr), fitF.push_back(mf), fitSigmaF.push_back(std::sqrt(vf)), fitSigmaR.push_back(std::sqrt(vr));
    }
  gain = 1, bias = 0;
  if (fitR.size() < 8) {
    // Nothing clearly visible to measure by: the target's means and contrasts as a whole.
    if (allN > 0 && allRR > 0) {
      gain = std::clamp(std::sqrt(allFF / allRR), 0.25, 4.0);
      bias = (allF - gain * allR) / allN + kGreyBias * (1 - gain);
    }
    return;
  }
  auto fit = [&](double maxResidual) {
    double n = 0, sr = 0, sf = 0, srr = 0, srf = 0, ssf = 0, ssr = 0;
    for (std::size_t k = 0; k < fitR.size(); ++k) {
      if (maxResidual > 0 && std::abs(fitF[k] - (gain * (fitR[k] + kGreyBias) + bias - kGreyBias)) > maxResidual) continue;
      n += 1, sr += fitR[k], sf += fitF[k], srr += fitR[k] * fitR[k], srf += fitR[k] * fitF[k];
      ssf += fitSigmaF[k], ssr += fitSigmaR[k];
    }
    if (n < 4) return;
    const double mr = sr / n, mf = sf / n, vr = srr / n - mr * mr;
    double g = vr >= 144.0 ? (srf / n - mr * mf) / vr : ssf / ssr;
    g = std::clamp(g, 0.25, 4.0);
    gain = g;
    bias = (mf - g * mr) + kGreyBias * (1 - g);  // back to uncentred grey levels
  };
  fit(0);
  // The residuals' median absolute deviation.
  fitResidual.clear();
  for (std::size_t k = 0; k < fitR.size(); ++k)
    fitResidual.push_back(std::abs(fitF[k] - (gain * (fitR[k] + kGreyBias) + bias - kGreyBias)));
  const auto mid = fitResidual.begin() + static_cast<std::ptrdiff_t>(fitResidual.size() / 2);
  std::nth_element(fitResidual.begin(), mid, fitResidual.end());
  const double mad = *mid;
  fit(std::max(3.0 * 1.4826 * mad, 2.0));
}

void TargetOcclusion::Impl::decide(const Box& t, double gain, double bias) noexcept {
  const float area = static_cast<float>(s.window * s.window);
  const float minN = std::max(4.0f, 0.2f * area);
  const float g = static_cast<float>(gain), b = static_cast<float>(bias);
  const float hiddenNcc = static_cast<float>(s.hiddenNcc), visibleNcc = static_cast<float>(s.visibleNcc);
  const float flat = static_cast<float>(s.flatSigma), textured = static_cast<float>(s.texturedSigma);
  const float tolBase = static_cast<float>(s.meanTolerance), tolShare = static_cast<float>(s.meanToleranceShare);
  const float texTol = static_cast<float>(s.textureTolerance);
  const float fine = static_cast<float>(s.fineWeight);
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      const std::size_t i = at(x, y);
      h[i] = -1;  // undecided: filled from the neighbours (clean)
      const float n = sums[0][i];
      if (cover[i] <= 0 || n < minN || clipped(F[i])) continue;
      const float mf = sums[1][i] / n, mr = sums[2][i] / n;
      const float vf = std::max(0.0f, sums[3][i] / n - mf * mf), vr = std::max(0.0f, sums[4][i] / n - mr * mr);
      const float c = sums[5][i] / n - mf * mr;
      const float sigmaF = std::sqrt(vf), sigmaR = std::sqrt(vr) * g;  // the reference's in frame levels
      const float texture = ramp(sigmaR, flat, textured);
      float hidden = 0;
      // Intensity: the pixel's own (its block is wholly on the target) or the window's mean
      // against the reference's.
      const bool whole = cover[i] >= kInside && !std::isnan(Rb[i]);
      const float frameValue = whole ? F[i] : mf + kGreyBias;
      const float refValue = whole ? Rb[i] : mr + kGreyBias;
      const float predicted = std::clamp(g * refValue + b, 0.0f, 255.0f);
      const float residual = std::abs(frameValue - predicted);
      const float tol = tolBase + tolShare * predicted;
      if (texture > 0) {
        // A window that straddles the edge of a hand correlates poorly on both sides of it: the
        // pixel's own agreement with the reference keeps the visible side visible.
        float ncc = vf > 1e-4f && vr > 1e-6f ? c / std::sqrt(vf * vr) : 0.0f;
        if (fine > 0 && inner[0][i] >= 4) {
          // The 3 x 3 window's, where it has texture of its own: finer, noisier.
          const float n3 = inner[0][i], mf3 = inner[1][i] / n3, mr3 = inner[2][i] / n3;
          const float vf3 = std::max(0.0f, inner[3][i] / n3 - mf3 * mf3), vr3 = std::max(0.0f, inner[4][i] / n3 - mr3 * mr3);
          const float c3 = inner[5][i] / n3 - mf3 * mr3;
          if (vr3 > 1.0f) ncc = (1 - fine) * ncc + fine * (vf3 > 1e-4f ? c3 / std::sqrt(vf3 * vr3) : 0.0f);
        }
        const float own = whole ? std::max(ramp(residual, kOwnLow * tol, kOwnHigh * tol),
                                           ramp(hiddenNcc - ncc, 0.0f, kOwnNcc)) : 1.0f;
        hidden += texture * ramp(visibleNcc - ncc, 0.0f, visibleNcc - hiddenNcc) * own;
      }
      // The pixel's own disagreement, past what a small misalignment explains where the reference
      // has an edge: a finger across a window that otherwise correlates.
      float byPixel = 0;
      if (whole && x > 0 && y > 0 && x + 1 < mw && y + 1 < mh) {
        const float ddx = Rb[i + 1] - Rb[i - 1], ddy = Rb[i + static_cast<std::size_t>(mw)] - Rb[i - static_cast<std::size_t>(mw)];
        const float grad = 0.5f * std::sqrt(ddx * ddx + ddy * ddy);
        if (!std::isnan(grad)) {
          const float tolP = kPixelTol * tol + kEdgeTol * g * grad;
          byPixel = ramp(residual, tolP, kPixelRamp * tolP);
        }
      }
      if (texture < 1) {
        // And texture where the reference has none.
        const float byMean = ramp(residual, 0.5f * tol, tol);
        const float byTexture = ramp(sigmaF - sigmaR, 0.5f * texTol, texTol);
        hidden += (1 - texture) * std::max(byMean, byTexture);
      }
      h[i] = std::max(hidden, byPixel);
    }
}

void TargetOcclusion::Impl::clean(const Box& t, const Box& e) noexcept {
  // h over t (undecided, -1, elsewhere in e) -> undecided pixels take the largest of their decided
  // neighbours (three rounds: the filters below then see the target's verdicts continue past its
  // edge instead of zeros that would erode them) -> median 3x3 -> close -> feather -> times
  // coverage. Reads past e's border repeat its edge.
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x)
      if (x < t.x0 || x >= t.x1 || y < t.y0 || y >= t.y1) h[at(x, y)] = -1;
  const std::ptrdiff_t row = mw;
  // Offsets to the neighbours of (x, y) within e: left, right, up, down.
  auto offsets = [&](int x, int y, std::ptrdiff_t& l, std::ptrdiff_t& r, std::ptrdiff_t& u0, std::ptrdiff_t& d0) {
    l = x > e.x0 ? -1 : 0, r = x + 1 < e.x1 ? 1 : 0, u0 = y > e.y0 ? -row : 0, d0 = y + 1 < e.y1 ? row : 0;
  };
  for (int round = 0; round < 3; ++round) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        const std::size_t i = at(x, y);
        float m = h[i];
        if (m < 0) {
          std::ptrdiff_t l, r, up, dn;
          offsets(x, y, l, r, up, dn);
          const float* c = h.data() + i;
          m = std::max({c[up + l], c[up], c[up + r], c[l], c[r], c[dn + l], c[dn], c[dn + r]});
        }
        h2[i] = m;
      }
    std::swap(h, h2);
  }
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) h[at(x, y)] = std::max(h[at(x, y)], 0.0f);
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) {
      std::ptrdiff_t l, r, up, dn;
      offsets(x, y, l, r, up, dn);
      const float* c = h.data() + at(x, y);
      float p[9] = {c[up + l], c[up], c[up + r], c[l], c[0], c[r], c[dn + l], c[dn], c[dn + r]};
      h2[at(x, y)] = median9(p);
    }
  // 3 x 3 max (dilate) or min (erode), separable: src -> tmp -> dst.
  auto morph = [&](const std::vector<float>& src, std::vector<float>& dst, bool dilate) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = src.data() + at(x, y);
        tmp[at(x, y)] = dilate ? std::max({c[l], c[0], c[r]}) : std::min({c[l], c[0], c[r]});
      }
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = tmp.data() + at(x, y);
        dst[at(x, y)] = dilate ? std::max({c[up], c[0], c[dn]}) : std::min({c[up], c[0], c[dn]});
      }
  };
  // A closing fills the holes a hand's own texture leaves (where it happens to look like the
  // target). No opening: it would erase fingers, 3 to 4 mask pixels wide at arm's length.
  morph(h2, h, true);   // dilate ...
  morph(h, h2, false);  // ... then erode
  for (int pass = 0; pass < s.featherPasses; ++pass) {
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = h2.data() + at(x, y);
        tmp[at(x, y)] = 0.25f * (c[l] + 2 * c[0] + c[r]);
      }
    for (int y = e.y0; y < e.y1; ++y)
      for (int x = e.x0; x < e.x1; ++x) {
        std::ptrdiff_t l, r, up, dn;
        offsets(x, y, l, r, up, dn);
        const float* c = tmp.data() + at(x, y);
        h2[at(x, y)] = 0.25f * (c[up] + 2 * c[0] + c[dn]);
      }
  }
  double hidden = 0, onTarget = 0;
  for (int y = e.y0; y < e.y1; ++y)
    for (int x = e.x0; x < e.x1; ++x) {
      const std::size_t i = at(x, y);
      const float m = clamp01(h2[i]) * cover[i];
      out[i] = static_cast<std::uint8_t>(255.0f * m + 0.5f);
      hidden += out[i] / 255.0;
      onTarget += cover[i];
    }
  written = e;
  mask.targetPixels = onTarget;
  mask.hiddenShare = onTarget > 0 ? hidden / onTarget : 0.0;
}

}  // namespace marionette::ar
