// Rotation of SH coefficient vectors by any 3D rotation, for every band up to kMaxShBands.
//
// A rotated band-l function is again a band-l function, so its coefficients are fixed by its
// values at any 2l + 1 directions in general position. ShRotation evaluates the rotated
// function at a fixed Fibonacci set of K = 2 n^2 + 2 directions and fits each band by least
// squares with a pseudo-inverse computed once; the fit is exact to rounding (the residual is
// zero) and, with twice as many directions as unknowns spread evenly, well conditioned.
// Per call: K basis evaluations and two small products per band, no allocation, noexcept.
// (Closed-form recurrences exist, Ivanic and Ruedenberg 1996; this is shorter, exact and fast
// enough: the timing is in docs/benchmarks.md.)
#pragma once
#include <glm/mat3x3.hpp>

#include <vector>

#include "marionette/prt/sh_lighting.hpp"

namespace marionette::prt {

class ShRotation {
 public:
  explicit ShRotation(int bands = kMaxShBands);
  [[nodiscard]] int bands() const noexcept { return bands_; }

  // `out` = the coefficients of the function turned by `rotation` (a proper orthonormal
  // matrix): f'(w) = f(R^-1 w). Bands above bands() are dropped (out.bands = min of both).
  void rotate(const glm::dmat3& rotation, const ShCoefficients& in, ShCoefficients& out) const noexcept;
  [[nodiscard]] ShCoefficients rotate(const glm::dmat3& rotation, const ShCoefficients& in) const noexcept {
    ShCoefficients out;
    rotate(rotation, in, out);
    return out;
  }

 private:
  int bands_;
  std::vector<glm::dvec3> directions_;  // K fitting directions
  // Per band, the (2l + 1) x K pseudo-inverse of the K x (2l + 1) basis matrix, row-major,
  // bands one after another.
  std::vector<double> pseudoInverse_;
  std::vector<std::size_t> bandOffset_;
};

}  // namespace marionette::prt
