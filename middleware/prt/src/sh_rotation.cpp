#include "marionette/prt/sh_rotation.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/prt/sphere_sampling.hpp"

namespace marionette::prt {

namespace {
// Solves the symmetric positive definite system G X = B in place (Cholesky), G n x n, B n x k.
void choleskySolve(std::vector<double>& g, std::vector<double>& b, int n, int k) {
  for (int j = 0; j < n; ++j) {
    double d = g[j * n + j];
    for (int p = 0; p < j; ++p) d -= g[j * n + p] * g[j * n + p];
    d = std::sqrt(std::max(d, 1e-300));
    g[j * n + j] = d;
    for (int i = j + 1; i < n; ++i) {
      double s = g[i * n + j];
      for (int p = 0; p < j; ++p) s -= g[i * n + p] * g[j * n + p];
      g[i * n + j] = s / d;
    }
  }
  for (int c = 0; c < k; ++c) {  // L y = b, then L^T x = y, column by column
    for (int i = 0; i < n; ++i) {
      double s = b[i * k + c];
      for (int p = 0; p < i; ++p) s -= g[i * n + p] * b[p * k + c];
      b[i * k + c] = s / g[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = b[i * k + c];
      for (int p = i + 1; p < n; ++p) s -= g[p * n + i] * b[p * k + c];
      b[i * k + c] = s / g[i * n + i];
    }
  }
}
}  // namespace

ShRotation::ShRotation(int bands) : bands_(std::clamp(bands, kMinShBands, kMaxShBands)) {
  const int k = 2 * shCount(bands_) + 2;
  directions_ = fibonacciSphere(k);
  std::vector<ShBasis> y(directions_.size());
  for (std::size_t i = 0; i < directions_.size(); ++i) shBasis(bands_, directions_[i], y[i]);
  for (int l = 0; l < bands_; ++l) {
    const int n = 2 * l + 1, first = shIndex(l, -l);
    // Normal equations: (Y^T Y) P = Y^T, so P = (Y^T Y)^-1 Y^T is the pseudo-inverse.
    std::vector<double> g(static_cast<std::size_t>(n * n), 0.0), p(static_cast<std::size_t>(n * k), 0.0);
    for (int a = 0; a < n; ++a)
      for (int kk = 0; kk < k; ++kk) {
        const double ya = y[static_cast<std::size_t>(kk)][static_cast<std::size_t>(first + a)];
        p[static_cast<std::size_t>(a * k + kk)] = ya;
        for (int b = 0; b < n; ++b) g[static_cast<std::size_t>(a * n + b)] += ya * y[static_cast<std::size_t>(kk)][static_cast<std::size_t>(first + b)];
      }
    choleskySolve(g, p, n, k);
    bandOffset_.push_back(pseudoInverse_.size());
    pseudoInverse_.insert(pseudoInverse_.end(), p.begin(), p.end());
  }
}

void ShRotation::rotate(const glm::dmat3& rotation, const ShCoefficients& in, ShCoefficients& out) const noexcept {
  const int bands = std::min(bands_, in.bands);
  const int k = static_cast<int>(directions_.size());
  ShCoefficients result;
  result.bands = bands;
  const glm::dmat3 inverse = glm::transpose(rotation);
  for (int kk = 0; kk < k; ++kk) {
    ShBasis y{};
    shBasis(bands, inverse * directions_[static_cast<std::size_t>(kk)], y);
    for (int l = 0; l < bands; ++l) {
      // g = f_l(R^-1 d_k), then out_l += P_l[:, k] g.
      glm::dvec3 g(0.0);
      for (int m = -l; m <= l; ++m) g += in.c[shIndex(l, m)] * y[shIndex(l, m)];
      const double* p = pseudoInverse_.data() + bandOffset_[static_cast<std::size_t>(l)];
      for (int a = 0; a < 2 * l + 1; ++a) result.c[shIndex(l, -l) + a] += p[a * k + kk] * g;
    }
  }
  out = result;
}

}  // namespace marionette::prt
