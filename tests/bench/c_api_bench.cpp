// marionette_bench: what the C API's handle check costs. Every entry point asks the
// handle registry (bridge/c_api/src/handles.cpp: a mutex and a hash lookup) whether
// its handle is live, so that a destroyed one is refused instead of used.
//   CApi/JointCount      mn_character_joint_count: the check and almost nothing else.
//   CApi/Palette         mn_character_palette of RobotExpressive (mat4, inverse bind):
//                        the check beside a real per-frame call; counter check_share =
//                        JointCount's time / this one's, measured in the same run.
#include <benchmark/benchmark.h>

#include <chrono>
#include <vector>

#include "marionette/marionette.h"
#include "test_data.hpp"

namespace {

struct Robot {
  mn_scene* scene = nullptr;
  mn_character* character = nullptr;
  Robot() {
    if (mn_scene_create(&scene) != MN_OK) return;
    const std::string asset = marionette::test::sharedAsset("characters/RobotExpressive.glb");
    if (mn_scene_add_character(scene, "robot", asset.c_str(), nullptr, &character) != MN_OK) character = nullptr;
    if (character) mn_scene_update(scene, 1.0 / 60.0);
  }
  ~Robot() { mn_scene_destroy(scene); }
};

Robot& robot() {
  static Robot r;
  return r;
}

double secondsPerCall(int calls, void (*call)(mn_character*), mn_character* c) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < calls; ++i) call(c);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / calls;
}

void jointCount(mn_character* c) { benchmark::DoNotOptimize(mn_character_joint_count(c)); }

void BM_JointCount(benchmark::State& state) {
  mn_character* c = robot().character;
  if (!c) return state.SkipWithError("cannot load ../shared/assets/characters/RobotExpressive.glb");
  for (auto _ : state) jointCount(c);
}
BENCHMARK(BM_JointCount)->Name("CApi/JointCount")->Unit(benchmark::kNanosecond);

void BM_Palette(benchmark::State& state) {
  mn_character* c = robot().character;
  if (!c) return state.SkipWithError("cannot load ../shared/assets/characters/RobotExpressive.glb");
  const std::size_t floats = mn_character_joint_count(c) * mn_palette_floats_per_joint(MN_PALETTE_MAT4_COLUMN_MAJOR);
  std::vector<float> palette(floats);
  for (auto _ : state)
    if (mn_character_palette(c, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette.data(), floats) != MN_OK)
      return state.SkipWithError("mn_character_palette failed");
  const auto t0 = std::chrono::steady_clock::now();
  constexpr int kCalls = 20000;
  for (int i = 0; i < kCalls; ++i) mn_character_palette(c, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette.data(), floats);
  const double palette1 = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / kCalls;
  state.counters["check_share"] = secondsPerCall(kCalls, jointCount, c) / palette1;
  state.counters["joints"] = static_cast<double>(mn_character_joint_count(c));
}
BENCHMARK(BM_Palette)->Name("CApi/Palette")->Unit(benchmark::kMicrosecond);

}  // namespace
