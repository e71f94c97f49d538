// Which build of the 4-wide pose code runs (pose.cpp; setSimdPath in pose.hpp).
//
// The hot loops are compiled up to three times from one source: for the SSE2 baseline,
// for AVX (broadcasts become single loads; add and multiply round as SSE2's, so the
// same bits) and for AVX2 + FMA (multiply-adds fused: one rounding instead of two,
// so the bits differ from the baseline's in the last place). The CPU is asked once.
#pragma once

namespace marionette::simd {

enum class Build { Sse2, Avx, Fma };

// The build to run now: the fastest the CPU has, limited by setSimdPath.
[[nodiscard]] Build activeBuild() noexcept;

}  // namespace marionette::simd

// The attribute of a function compiled as the FMA build. GCC fuses a multiply and the
// add that takes it only when contraction is allowed; it is allowed here, per function,
// so the rest of the library (and the baseline, whatever -march says) keeps ISO rounding.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define MARIONETTE_HAS_WIDE_BUILDS 1
#define MARIONETTE_AVX_BUILD [[gnu::target("avx")]]
#define MARIONETTE_FMA_BUILD [[gnu::target("avx2,fma"), gnu::optimize("fp-contract=fast")]]
#elif defined(__clang__) && defined(__x86_64__)
// Clang has no per-function contraction switch, and its default fuses only within one
// expression, which the intrinsics' separate multiplies and adds are not: its "FMA" build
// is an AVX2 build of the same operations (the library is built with GCC; clang builds
// only the fuzz targets).
#define MARIONETTE_HAS_WIDE_BUILDS 1
#define MARIONETTE_AVX_BUILD [[gnu::target("avx")]]
#define MARIONETTE_FMA_BUILD [[gnu::target("avx2,fma")]]
#endif

// Defines `void name(const Args& args) noexcept`, which runs body(args) (an always_inline
// function) as compiled for the build activeBuild() names: one source, three builds.
#if MARIONETTE_HAS_WIDE_BUILDS
#define MARIONETTE_SIMD_KERNEL(name, Args, body)                                         \
  void name##Sse2(const Args& a) noexcept { body(a); }                                    \
  MARIONETTE_AVX_BUILD void name##Avx(const Args& a) noexcept { body(a); }               \
  MARIONETTE_FMA_BUILD void name##Fma(const Args& a) noexcept { body(a); }               \
  void name(const Args& a) noexcept {                                                     \
    switch (::marionette::simd::activeBuild()) {                                          \
      case ::marionette::simd::Build::Fma: return name##Fma(a);                           \
      case ::marionette::simd::Build::Avx: return name##Avx(a);                           \
      default: return name##Sse2(a);                                                      \
    }                                                                                     \
  }
#else
#define MARIONETTE_SIMD_KERNEL(name, Args, body) \
  void name(const Args& a) noexcept { body(a); }
#endif
