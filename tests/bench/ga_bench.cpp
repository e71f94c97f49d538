// GA rotors (examples/ar/authoring): one authoring step, a local or a global turn plus the
// renormalization policy, as docs/authoring.md reports it; and the policies against each other
// (the work-precision row with the drift test's figures).
//
//   GA/RotorStep         turn(): the step + exact renormalization (the authoring path's)
//   GA/RotorStepCheap    the step + the square-root-free Newton renormalization
//   GA/RotorStepNone     the step alone
#include <benchmark/benchmark.h>

#include <array>
#include <random>

#include "marionette_ar/authoring/rotor.hpp"

namespace {

using namespace marionette::ar::ga;

constexpr int kAngles = 1024;

std::array<float, kAngles> angles() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> d(-0.09f, 0.09f);
  std::array<float, kAngles> a{};
  for (float& x : a) x = d(rng);
  return a;
}

template <int kPolicy>
void rotorStep(benchmark::State& state) {
  const auto a = angles();
  const Bivector<float> planes[3] = {kPlaneX<float>, kPlaneY<float>, kPlaneZ<float>};
  Rotor r = Rotor::identity();
  int i = 0;
  for (auto _ : state) {
    const Axes axes = (i & 1) ? Axes::Global : Axes::Local;
    const Bivector<float>& plane = planes[i % 3];
    const float theta = a[static_cast<std::size_t>(i & (kAngles - 1))];
    if constexpr (kPolicy == 0) {
      r = turn(r, axes, plane, theta);
    } else {
      r = axes == Axes::Local ? rotateLocal(r, plane, theta) : rotateGlobal(r, plane, theta);
      if constexpr (kPolicy == 1) r = r.renormalizedCheaply();
    }
    benchmark::DoNotOptimize(r);
    ++i;
  }
  state.counters["norm"] = r.norm();
}

}  // namespace

BENCHMARK(rotorStep<0>)->Name("GA/RotorStep");
BENCHMARK(rotorStep<1>)->Name("GA/RotorStepCheap");
BENCHMARK(rotorStep<2>)->Name("GA/RotorStepNone");
