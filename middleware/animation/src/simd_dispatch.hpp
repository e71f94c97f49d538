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
// Clang has no per-function contraction switch; its FMA build contracts within expressions.
#define MARIONETTE_HAS_WIDE_BUILDS 1
#define MARIONETTE_AVX_BUILD [[gnu::target("avx")]]
#define MARIONETTE_FMA_BUILD [[gnu::target("avx2,fma")]]
#endif
