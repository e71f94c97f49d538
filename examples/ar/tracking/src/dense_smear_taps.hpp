// The dense alignment's render, the inner part: each sample's smear is a line of taps through
// the keyframe (its homogeneous image stepped along the line), and each tap a bilinear sample
// of the keyframe and its gradient. Eight samples walk their lines together: in AVX2 lanes
// where the CPU has it, else one after another; the same operations per sample either way, so
// the same bits (tracking_primitives_test compares them).
#pragma once
#include <cstdint>

#include "lucas_kanade.hpp"  // GreyLevel

namespace marionette::ar {

struct SmearTaps {
  static constexpr int kLanes = 8;
  int count = 0;  // samples in use, 1..kLanes
  // In: the first tap's homogeneous keyframe position, the step between taps, the taps, and
  // the step as a fraction of the line (1 / taps).
  double hx[kLanes]{}, hy[kLanes]{}, hw[kLanes]{}, dhx[kLanes]{}, dhy[kLanes]{}, dhw[kLanes]{}, step[kLanes]{};
  int taps[kLanes]{};
  // Out: the sums over the taps of the value, of its gradient (u, v) and of the gradient times
  // the tap's offset along the line, (k + 0.5) step - 0.5; inside: every tap fell within the
  // keyframe, [1, umax] x [1, vmax], in front of the camera (else the sums are not used).
  float sum[kLanes]{}, gu[kLanes]{}, gv[kLanes]{}, mu[kLanes]{}, mv[kLanes]{};
  bool inside[kLanes]{};
};

// Taps within [1, umax] x [1, vmax], which are held to width - 3 and height - 3 (the gathers read
// 4 bytes from a tap's first pixel, on its row and the next). wide: AVX2 where the CPU has it;
// false: the scalar loop.
void walkSmearTaps(const GreyLevel& keyframe, float umax, float vmax, SmearTaps& taps, bool wide = true) noexcept;

}  // namespace marionette::ar
