// marionette_bench: PRT at run time, per frame.
//   Prt/Relight/<bands>        E_v = sum_i L_i T_v,i for 10,000 vertices (RGB). Target: at most
//                              0.1 ms per 10k vertices at 4 bands.
//   Prt/RelightMemcpy/<bands>  a memcpy of the same transfer bytes: the trivial baseline
//   Prt/ShRotation/<bands>     the environment's lighting turned into a character's frame
#include <benchmark/benchmark.h>

#include <cstring>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette/prt/relight.hpp"
#include "marionette/prt/sh_rotation.hpp"

using namespace marionette::prt;

namespace {
constexpr std::size_t kVertices = 10000;

VertexTransfer randomTransfer(int bands) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  VertexTransfer t;
  t.bands = bands;
  t.coefficients.resize(kVertices * static_cast<std::size_t>(shCount(bands)));
  for (float& c : t.coefficients) c = u(rng);
  t.occluded.assign(kVertices, 0.0f);
  return t;
}

ShCoefficients randomLighting(int bands) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoefficients l;
  l.bands = bands;
  for (int i = 0; i < shCount(bands); ++i) l.c[i] = {u(rng), u(rng), u(rng)};
  return l;
}

void relight(benchmark::State& state) {
  const int bands = static_cast<int>(state.range(0));
  const TransferRelighter relighter(randomTransfer(bands));
  const ShCoefficients lighting = randomLighting(bands);
  std::vector<glm::vec3> out(kVertices);
  for (auto _ : state) {
    relighter.relight(lighting, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kVertices));
}

void relightMemcpy(benchmark::State& state) {
  const VertexTransfer t = randomTransfer(static_cast<int>(state.range(0)));
  std::vector<float> copy(t.coefficients.size());
  for (auto _ : state) {
    std::memcpy(copy.data(), t.coefficients.data(), copy.size() * sizeof(float));
    benchmark::DoNotOptimize(copy.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kVertices));
}

void rotation(benchmark::State& state) {
  const int bands = static_cast<int>(state.range(0));
  const ShRotation rotation(bands);
  const ShCoefficients lighting = randomLighting(bands);
  ShCoefficients out;
  double angle = 0.0;
  for (auto _ : state) {
    angle += 0.01;
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), angle, glm::dvec3(0.3, 1.0, 0.2)));
    rotation.rotate(r, lighting, out);
    benchmark::DoNotOptimize(out.c.data());
  }
}
}  // namespace

BENCHMARK(relight)->Name("Prt/Relight")->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Arg(8)->Unit(benchmark::kMicrosecond);
BENCHMARK(relightMemcpy)->Name("Prt/RelightMemcpy")->Arg(4)->Arg(8)->Unit(benchmark::kMicrosecond);
BENCHMARK(rotation)->Name("Prt/ShRotation")->Arg(3)->Arg(4)->Arg(5)->Arg(8)->Unit(benchmark::kMicrosecond);
