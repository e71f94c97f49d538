// marionette_bench: per-character cost of a blend-space layer against one clip layer
// (docs/benchmarks.md), 1000 characters, one core, each frame a full update (layers,
// local-to-model, palette):
//   BlendSpace/Clip/<asset>        the walk clip alone on a layer (the baseline)
//   BlendSpace/1D/<asset>          a phase-aligned walk-run space at x = 0.5 (2 clips sampled)
//   BlendSpace/1DMoving/<asset>    the same, its parameter moved every frame (setBlendParameter)
//   BlendSpace/2D/<asset>          idle, walk and run in a triangle, the point inside (3 clips)
// Counter us_per_char: microseconds per character per frame.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

#include "bench_assets.hpp"
#include "marionette/scene/scene.hpp"

using namespace marionette;
using test::BenchAsset;
using test::loadBenchAsset;

namespace {

enum class Kind { Clip, OneD, OneDMoving, TwoD };

std::shared_ptr<const BlendSpace> makeSpace(const Rig& rig, const std::vector<std::string>& clips, bool twoD,
                                            std::string& error) {
  BlendSpaceFeet feet;
  feet.left = rig.joints().leftLeg.end;
  feet.right = rig.joints().rightLeg.end;
  // clips: idle-like, walk, run (bench_assets.hpp's order for RobotExpressive; Pab: walk, jog, crossarms)
  const bool pab = clips[0] == "walk";
  auto walk = rig.findClip(pab ? clips[0] : clips[1]), run = rig.findClip(pab ? clips[1] : clips[2]);
  auto other = rig.findClip(pab ? clips[2] : clips[0]);
  if (!twoD) return BlendSpace::make("walk-run", 1, {{walk, 0.0f}, {run, 1.0f}}, rig.skeleton(), feet, true, error);
  return BlendSpace::make("triangle", 2, {{other, 0.0f, 0.0f}, {walk, 1.0f, 0.0f}, {run, 0.5f, 1.0f}}, rig.skeleton(),
                          feet, true, error);
}

void blendSpaceBench(benchmark::State& state, const std::string& which, Kind kind) {
  const BenchAsset& b = loadBenchAsset(which);
  if (!b.rig) {
    state.SkipWithError(("cannot load test data: " + b.error).c_str());
    return;
  }
  std::string error;
  auto space = kind == Kind::Clip ? nullptr : makeSpace(*b.rig, b.clips, kind == Kind::TwoD, error);
  if (kind != Kind::Clip && !space) {
    state.SkipWithError(("cannot make the blend space: " + error).c_str());
    return;
  }
  constexpr int kCharacters = 1000;
  Scene scene;
  std::vector<Character*> characters;
  const std::string walk = b.clips[0] == "walk" ? b.clips[0] : b.clips[1];
  for (int i = 0; i < kCharacters; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), b.rig);
    PlayOptions o;
    o.startTime = kind == Kind::Clip ? 0.013 * i : 0.011 * i;  // each at its own time (seconds, or phase)
    if (kind == Kind::Clip) c->play(0, walk, o);
    else c->playBlend(0, space, o, kind == Kind::TwoD ? 0.5f : 0.5f, kind == Kind::TwoD ? 0.3f : 0.0f);
    characters.push_back(c);
  }
  scene.update(1.0 / 60.0);  // warm-up
  int frame = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (kind == Kind::OneDMoving) {
      const float x = 0.5f + 0.4f * std::sin(0.05f * static_cast<float>(frame));
      for (Character* c : characters) c->setBlendParameter(0, x);
    }
    ++frame;
    scene.update(1.0 / 60.0);
    benchmark::DoNotOptimize(scene.characters().front()->transformBuffer().skinning().data());
  }
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  state.counters["us_per_char"] = us / (static_cast<double>(state.iterations()) * kCharacters);
  state.counters["joints"] = static_cast<double>(b.rig->skeleton().jointCount());
}

}  // namespace

BENCHMARK_CAPTURE(blendSpaceBench, RobotClip, std::string("RobotExpressive"), Kind::Clip)
    ->Name("BlendSpace/Clip/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, Robot1D, std::string("RobotExpressive"), Kind::OneD)
    ->Name("BlendSpace/1D/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, Robot1DMoving, std::string("RobotExpressive"), Kind::OneDMoving)
    ->Name("BlendSpace/1DMoving/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, Robot2D, std::string("RobotExpressive"), Kind::TwoD)
    ->Name("BlendSpace/2D/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, PabClip, std::string("Pab"), Kind::Clip)
    ->Name("BlendSpace/Clip/Pab")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, Pab1D, std::string("Pab"), Kind::OneD)
    ->Name("BlendSpace/1D/Pab")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(blendSpaceBench, Pab2D, std::string("Pab"), Kind::TwoD)
    ->Name("BlendSpace/2D/Pab")->Unit(benchmark::kMicrosecond);
