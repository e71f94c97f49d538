// Whether the tracker's AVX2 loops are compiled and may run here. They are built per function
// ([[gnu::target("avx2")]], no FMA, so multiplies and adds round as the baseline's) on x86-64
// with GCC or clang, and chosen at run time: the baseline loops, which give the same bits, run
// elsewhere (the web build, other CPUs).
#pragma once

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MARIONETTE_TRACKING_AVX2 1
#else
#define MARIONETTE_TRACKING_AVX2 0
#endif

namespace marionette::ar {

// True where the AVX2 loops are compiled and the CPU has AVX2 (asked once).
[[nodiscard]] inline bool cpuHasAvx2() noexcept {
#if MARIONETTE_TRACKING_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
#else
  return false;
#endif
}

}  // namespace marionette::ar
