#include "simd_dispatch.hpp"

#include <atomic>

#include "marionette/animation/pose.hpp"
#include "simd4.hpp"

namespace marionette {

namespace {

std::atomic<SimdPath> requestedPath{SimdPath::Auto};

simd::Build bestBuild() noexcept {
#if MARIONETTE_HAS_WIDE_BUILDS
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return simd::Build::Fma;
  if (__builtin_cpu_supports("avx")) return simd::Build::Avx;
#endif
  return simd::Build::Sse2;
}

}  // namespace

simd::Build simd::activeBuild() noexcept {
  static const Build best = bestBuild();
  switch (requestedPath.load(std::memory_order_relaxed)) {
    case SimdPath::Baseline: return Build::Sse2;
    case SimdPath::Portable: return best == Build::Fma ? Build::Avx : best;
    default: return best;
  }
}

void setSimdPath(SimdPath path) noexcept { requestedPath.store(path, std::memory_order_relaxed); }

const char* activeSimdPath() noexcept {
#if MARIONETTE_SIMD4
  switch (simd::activeBuild()) {
    case simd::Build::Fma: return "avx2+fma";
    case simd::Build::Avx: return "avx";
    default: return "sse2";
  }
#else
  return "scalar";
#endif
}

}  // namespace marionette
