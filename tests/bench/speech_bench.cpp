// marionette_bench: lip-sync curves (speech/lipsync.hpp).
//   Speech/BuildCurves10s   buildVisemeCurves on 10 s of real phoneme timing (the
//                           CMU ARCTIC arctic_a0009 alignment tiled back to back,
//                           ../shared/assets/speech), default settings; counter us.
//   Speech/EvaluateCurves   one VisemeCurves::evaluate per iteration, at times that
//                           step by about a 60 Hz frame through those curves (Time, ns).
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <string>
#include <vector>

#include "lipsync_measure.hpp"
#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/lipsync.hpp"
#include "test_paths.hpp"

using namespace marionette;
using namespace marionette::speech;

namespace {

const std::vector<Phoneme>* tenSecondsOfSpeech(benchmark::State& state) {
  static const Alignment a = readAlignment(::marionette::test::sharedDir() + "/assets/speech/arctic_a0009.phones.txt");
  static const std::vector<Phoneme> tiled = test::tiledTo(a.phonemes, 10.0);
  if (!a.error.empty() || tiled.empty()) {
    state.SkipWithError(("arctic_a0009 alignment: " + a.error).c_str());
    return nullptr;
  }
  return &tiled;
}

void BM_BuildCurves10s(benchmark::State& state) {
  const std::vector<Phoneme>* ps = tenSecondsOfSpeech(state);
  if (!ps) return;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    VisemeCurves c = buildVisemeCurves(*ps, 10.0);
    benchmark::DoNotOptimize(c.values.data());
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["us"] = 1e6 * seconds / static_cast<double>(state.iterations());
}
BENCHMARK(BM_BuildCurves10s)->Name("Speech/BuildCurves10s")->Unit(benchmark::kMicrosecond);

void BM_EvaluateCurves(benchmark::State& state) {
  const std::vector<Phoneme>* ps = tenSecondsOfSpeech(state);
  if (!ps) return;
  const VisemeCurves c = buildVisemeCurves(*ps, 10.0);
  std::array<float, kLipChannelCount> w{};
  double t = 0.0;
  for (auto _ : state) {
    c.evaluate(t, w);
    benchmark::DoNotOptimize(w.data());
    benchmark::ClobberMemory();
    t += 0.0167;
    if (t > 10.0) t -= 10.0;
  }
}
BENCHMARK(BM_EvaluateCurves)->Name("Speech/EvaluateCurves")->Unit(benchmark::kNanosecond);

}  // namespace
