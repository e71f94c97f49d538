// marionette_bench: the bridge's per-frame palette copy.
//   Bridge/PaletteCopy/layout:L/inverse_bind:B   1000 characters of 68 joints (Godette's
//     count), each TransformBuffer filled with distinct non-trivial matrices, every
//     palette copied through an identity PaletteBinding into one engine array per
//     iteration. layout 0 = Mat4ColumnMajor, 1 = Mat4RowMajor, 2 = Mat3x4RowMajor.
//     In the same run, std::memcpy of as many bytes as the copy writes, from one
//     contiguous source, times the hardware's best: counter memcpy_ratio = copy
//     bandwidth / memcpy bandwidth (target >= 0.5 for layout 0 with inverse bind).
//     The iteration time is the copy's alone (manual time); bytes = bytes written.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include "marionette/bridge/palette_binding.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::bridge;

namespace {

constexpr std::size_t kCharacters = 1000;
constexpr int kJoints = 68;

struct Data {
  Skeleton skeleton = test::makeChain(kJoints);
  std::vector<TransformBuffer> buffers;
  PaletteBinding binding{skeleton};
};

const Data& data() {
  static const Data d = [] {
    Data out;
    out.buffers.resize(kCharacters);
    for (std::size_t c = 0; c < kCharacters; ++c) {
      TransformBuffer& b = out.buffers[c];
      b.resize(kJoints, 0);
      for (int j = 0; j < kJoints; ++j) {
        const float a = 0.01f * static_cast<float>(c * kJoints + static_cast<std::size_t>(j));
        glm::mat4 m = glm::mat4_cast(glm::angleAxis(a, glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f + 0.001f * a))));
        m[3] = glm::vec4(std::sin(a), 1.0f + 0.01f * static_cast<float>(j), std::cos(a), 1.0f);
        b.writeModel()[static_cast<std::size_t>(j)] = m;
        b.writeSkinning()[static_cast<std::size_t>(j)] = m * out.skeleton.inverseBind[static_cast<std::size_t>(j)];
      }
      b.finishFrame();
    }
    return out;
  }();
  return d;
}

void BM_PaletteCopy(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const Data& d = data();
  const PaletteFormat format{static_cast<PaletteLayout>(state.range(0)), state.range(1) != 0};
  const std::size_t perCharacter = d.binding.floatCount(format.layout);
  std::vector<float> engine(kCharacters * perCharacter, 0.0f);
  const std::vector<float> contiguous(engine.size(), 0.5f);  // the memcpy reference's source
  const std::size_t bytes = engine.size() * sizeof(float);
  double copySeconds = 0.0, memcpySeconds = 0.0;
  bool ok = true;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (std::size_t c = 0; c < kCharacters; ++c)
      ok &= d.binding.copy(d.buffers[c], std::span<float>(engine.data() + c * perCharacter, perCharacter), format);
    benchmark::ClobberMemory();
    const auto t1 = Clock::now();
    std::memcpy(engine.data(), contiguous.data(), bytes);
    benchmark::ClobberMemory();
    const auto t2 = Clock::now();
    const double copy = std::chrono::duration<double>(t1 - t0).count();
    copySeconds += copy;
    memcpySeconds += std::chrono::duration<double>(t2 - t1).count();
    state.SetIterationTime(copy);
  }
  if (!ok) state.SkipWithError("PaletteBinding::copy refused a buffer");
  benchmark::DoNotOptimize(engine.data());
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes));
  state.counters["memcpy_ratio"] = copySeconds > 0.0 ? memcpySeconds / copySeconds : 0.0;  // same bytes: bandwidth ratio
  state.counters["us_per_char"] = 1e6 * copySeconds / (static_cast<double>(state.iterations()) * kCharacters);
}

}  // namespace

BENCHMARK(BM_PaletteCopy)
    ->Name("Bridge/PaletteCopy")
    ->ArgNames({"layout", "inverse_bind"})
    ->ArgsProduct({{0, 1, 2}, {1, 0}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);
