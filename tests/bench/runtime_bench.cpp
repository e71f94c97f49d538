// marionette_bench: per-character cost of the runtime on real skeletons.
//   Runtime/Sample1/<asset>  one clip + local-to-model + palette, 1000 characters
//   Runtime/Blend3/<asset>   three clips blended + local-to-model + palette, 1000 characters
//   Baseline/Memcpy/<asset>  copying the bytes the palette writes (a floor, in the style of ACL)
//   Scaling/Joints/N         synthetic chain of N joints, 100 characters
//   Scaling/Characters/N     RobotExpressive, N characters
//   Behaviors/IdleGazeNodFace/RobotExpressive  Idle clip + gaze (NECK, tracking) + a
//                            repeated head nod + a face expression, 1000 characters
//   Behaviors/IdleLocomotionGazeNodFace/RobotExpressive  the same plus locomotion (walk and
//                            run blended by speed, root motion, two-leg foot planting)
// Counter us_per_char: microseconds per character per frame (one core).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstring>
#include <map>
#include <memory>

#include "marionette/scene/scene.hpp"
#include "bench_assets.hpp"
#include "bench_behaviors.hpp"
#include "synthetic.hpp"
#include "test_paths.hpp"

using namespace marionette;
using test::BenchAsset;
using test::loadBenchAsset;

namespace {

void fillScene(Scene& scene, const std::shared_ptr<const Rig>& rig, const std::vector<std::string>& clips, int count,
               int layers) {
  const float weights[3] = {0.5f, 0.3f, 0.2f};
  for (int i = 0; i < count; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    for (int l = 0; l < layers; ++l) {
      PlayOptions o;
      o.weight = layers == 1 ? 1.0f : weights[l];
      o.startTime = 0.013 * i;  // each character at its own time: no shared cache lines
      c->play(l, clips[l], o);
    }
  }
  scene.update(1.0 / 60.0);  // warm-up
}

// Times the benchmark loop itself so that the counter is a plain number of
// microseconds (Google Benchmark's rate counters print with a seconds suffix).
template <class F>
void timedLoop(benchmark::State& state, int characters, F&& body) {
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) body();
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  state.counters["us_per_char"] = us / (static_cast<double>(state.iterations()) * characters);
}

void runtimeBench(benchmark::State& state, const std::string& which, int layers) {
  const BenchAsset& b = loadBenchAsset(which);
  if (!b.rig) {
    state.SkipWithError(("cannot load test data: " + b.error).c_str());
    return;
  }
  constexpr int kCharacters = 1000;
  Scene scene;
  fillScene(scene, b.rig, b.clips, kCharacters, layers);
  timedLoop(state, kCharacters, [&] {
    scene.update(1.0 / 60.0);
    benchmark::DoNotOptimize(scene.characters().front()->transformBuffer().skinning().data());
  });
  state.counters["joints"] = static_cast<double>(b.rig->skeleton().jointCount());
}

void memcpyBaseline(benchmark::State& state, const std::string& which) {
  const BenchAsset& b = loadBenchAsset(which);
  if (!b.rig) {
    state.SkipWithError(("cannot load test data: " + b.error).c_str());
    return;
  }
  constexpr int kCharacters = 1000;
  const std::size_t bytes = b.rig->skeleton().jointCount() * sizeof(glm::mat4) * 2;  // model + palette
  std::vector<char> src(bytes * kCharacters, 1), dst(bytes * kCharacters);
  timedLoop(state, kCharacters, [&] {
    std::memcpy(dst.data(), src.data(), dst.size());
    benchmark::ClobberMemory();
  });
}

std::shared_ptr<const Rig> chainRig(int joints) {
  auto asset = std::make_shared<Asset>();
  asset->skeleton = test::makeChain(joints, 0.01f);
  Clip c;
  c.name = "bend";
  for (int j = 0; j < joints; ++j) {
    std::vector<float> times, angles;
    for (int k = 0; k < 30; ++k) {
      times.push_back(static_cast<float>(k) / 30.0f);
      angles.push_back(0.01f * static_cast<float>((k * 7 + j) % 13));
    }
    c.tracks.push_back(test::rotationTrack(j, times, angles));
  }
  c.updateDuration();
  asset->clips.push_back(std::move(c));
  return std::make_shared<Rig>(*asset);
}

void jointScaling(benchmark::State& state) {
  const int joints = static_cast<int>(state.range(0));
  constexpr int kCharacters = 100;
  Scene scene;
  fillScene(scene, chainRig(joints), {"bend"}, kCharacters, 1);
  timedLoop(state, kCharacters, [&] { scene.update(1.0 / 60.0); });
}

void characterScaling(benchmark::State& state) {
  const BenchAsset& b = loadBenchAsset("RobotExpressive");
  if (!b.rig) {
    state.SkipWithError(("cannot load test data: " + b.error).c_str());
    return;
  }
  const int count = static_cast<int>(state.range(0));
  Scene scene;
  fillScene(scene, b.rig, b.clips, count, 1);
  timedLoop(state, count, [&] { scene.update(1.0 / 60.0); });
}

// The controllers that exist (issue 4 in progress) on top of the Idle clip.
void behaviorsBench(benchmark::State& state) {
  const BenchAsset& b = loadBenchAsset("RobotExpressive");
  if (!b.rig) {
    state.SkipWithError(("cannot load test data: " + b.error).c_str());
    return;
  }
  constexpr int kCharacters = 1000;
  Scene scene;
  fillScene(scene, b.rig, b.clips, kCharacters, 1);
  for (int i = 0; i < kCharacters; ++i) {
    Character* c = scene.characters()[static_cast<std::size_t>(i)].get();
    if (!test::addGazeNodFace(*c, i)) {
      state.SkipWithError("RobotExpressive's guessed profile does not support gaze, nod and ANGER");
      return;
    }
    if (state.range(0) == 0) continue;
    if (!test::addMidSpeedWalk(*c, i)) {
      state.SkipWithError("RobotExpressive cannot walk (its profile's walk and run clips)");
      return;
    }
  }
  for (int warmUp = 0; warmUp < 60; ++warmUp) scene.update(1.0 / 60.0);  // up to speed
  timedLoop(state, kCharacters, [&] {
    scene.update(1.0 / 60.0);
    benchmark::DoNotOptimize(scene.characters().front()->transformBuffer().skinning().data());
  });
}

}  // namespace
BENCHMARK(behaviorsBench)->Name("Behaviors/IdleGazeNodFace/RobotExpressive")->Arg(0)->Unit(benchmark::kMicrosecond);
BENCHMARK(behaviorsBench)->Name("Behaviors/IdleLocomotionGazeNodFace/RobotExpressive")->Arg(1)->Unit(benchmark::kMicrosecond);

BENCHMARK_CAPTURE(runtimeBench, Pab_Sample1, std::string("Pab"), 1)->Name("Runtime/Sample1/Pab")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(runtimeBench, Pab_Blend3, std::string("Pab"), 3)->Name("Runtime/Blend3/Pab")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(runtimeBench, Robot_Sample1, std::string("RobotExpressive"), 1)->Name("Runtime/Sample1/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(runtimeBench, Robot_Blend3, std::string("RobotExpressive"), 3)->Name("Runtime/Blend3/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(memcpyBaseline, Pab, std::string("Pab"))->Name("Baseline/Memcpy/Pab")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(memcpyBaseline, Robot, std::string("RobotExpressive"))->Name("Baseline/Memcpy/RobotExpressive")->Unit(benchmark::kMicrosecond);
BENCHMARK(jointScaling)->Name("Scaling/Joints")->RangeMultiplier(10)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(characterScaling)->Name("Scaling/Characters")->Arg(1)->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
// main() is in bench_main.cpp: it fails the run when any benchmark reports an error.
