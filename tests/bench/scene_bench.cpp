// marionette_bench: Scene::update spread over threads.
//   Scene/Update1000/threads:N  1000 RobotExpressive characters (one shared rig),
//                               each with the Idle clip, a gaze at a point, a head
//                               NOD and a face expression, updated on N threads.
//   Scene/Update1000Locomotion/threads:N  the same, each also walking (walk and run
//                               blended by speed, root motion, feet planted): issue 4's load.
// Counters: us_per_char (wall-clock microseconds per character per frame, all
// threads together) and, for N > 1, speedup: median one-thread frame time over
// median N-thread frame time, measured in this run on the same scene in
// alternating blocks of frames, so that a noisy machine slows both alike.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "bench_behaviors.hpp"
#include "marionette/scene/scene.hpp"
#include "test_paths.hpp"

using namespace marionette;

namespace {

constexpr int kSceneCharacters = 1000;

// RobotExpressive without meshes, once per program (as runtime_bench.cpp loads it).
std::shared_ptr<const Rig> sceneBenchRig(std::string& error) {
  static std::string loadError;
  static const std::shared_ptr<const Rig> rig = [] {
    ImportOptions noMesh;
    noMesh.loadMeshes = false;
    ImportResult r = importAsset(::marionette::test::sharedDir() + "/assets/characters/RobotExpressive.glb", noMesh);
    if (!r.ok()) {
      loadError = r.diagnostics.format();
      return std::shared_ptr<const Rig>();
    }
    return std::shared_ptr<const Rig>(std::make_shared<Rig>(*r.asset));
  }();
  error = loadError;
  return rig;
}

// The Behaviors/IdleGazeNodFace load (and IdleLocomotionGazeNodFace with
// `walking`): every controller that exists runs every frame.
bool fillBehaviorScene(Scene& scene, const std::shared_ptr<const Rig>& rig, bool walking) {
  for (int i = 0; i < kSceneCharacters; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->setPosition({static_cast<float>(i % 40), 0.0f, static_cast<float>(i / 40)});
    c->play(0, "Idle", {.startTime = 0.013 * i});  // each at its own time
    if (!test::addGazeNodFace(*c, i) || (walking && !test::addMidSpeedWalk(*c, i)))
      return false;
  }
  return true;
}

double secondsOf(Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  scene.update(1.0 / 60.0);
  benchmark::DoNotOptimize(scene.characters().front()->transformBuffer().skinning().data());
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// One-thread frame time over `threads`-thread frame time, median of each, in
// alternating blocks of frames on the same scene: the same memory and caches,
// and the machine's noise in the same stretch of time for both. (Two scenes
// updated in turn would evict each other's characters from the caches.)
double measureSpeedup(Scene& scene, int threads) {
  std::vector<double> one, many;
  for (int block = 0; block < 20; ++block) {
    const bool serial = block % 2 == 0;
    scene.setThreadCount(serial ? 1 : threads);
    scene.update(1.0 / 60.0);  // the first frame after a switch is not counted
    for (int f = 0; f < 10; ++f) (serial ? one : many).push_back(secondsOf(scene));
  }
  return median(one) / median(many);
}

void sceneUpdateBench(benchmark::State& state, bool walking) {
  const int threads = static_cast<int>(state.range(0));
  std::string error;
  const auto rig = sceneBenchRig(error);
  if (!rig) {
    state.SkipWithError(("cannot load test data: " + error).c_str());
    return;
  }
  Scene scene;
  if (!fillBehaviorScene(scene, rig, walking)) {
    state.SkipWithError("RobotExpressive's guessed profile does not support gaze, nod, ANGER or walking");
    return;
  }
  scene.setThreadCount(threads);
  for (int warmUp = 0; warmUp < 60; ++warmUp) scene.update(1.0 / 60.0);  // walkers up to speed
  double timed = 0.0;
  for (auto _ : state) timed += secondsOf(scene);
  state.counters["us_per_char"] = timed * 1e6 / (static_cast<double>(state.iterations()) * kSceneCharacters);
  state.counters["threads"] = scene.threadCount();
  if (threads > 1) state.counters["speedup"] = measureSpeedup(scene, threads);
}

}  // namespace

BENCHMARK_CAPTURE(sceneUpdateBench, idle, false)->Name("Scene/Update1000")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(sceneUpdateBench, walking, true)->Name("Scene/Update1000Locomotion")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
