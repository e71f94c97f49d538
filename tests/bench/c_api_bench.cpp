// marionette_bench: what the C API's handle check costs. Every entry point asks the
// handle registry (bridge/c_api/src/handles.cpp: a mutex and a hash lookup) whether
// its handle is live, so that a destroyed one is refused instead of used.
//   CApi/JointCount      mn_character_joint_count: the check and almost nothing else.
//   CApi/Palette         mn_character_palette of RobotExpressive (mat4, inverse bind):
//                        the check beside a real per-frame call; counter check_share =
//                        JointCount's time / this one's, measured in the same run.
//   CApi/LoadSharedAsset mn_asset_load_memory of RobotExpressive.glb and 100 characters added
//                        from it (the embedding issue's goal: <= 30 ms in all).
//   CApi/FrameVsCpp      a frame of 100 walking robots that share one asset: the C path
//                        (mn_scene_update, then mn_character_palette of each) against the C++
//                        path (Scene::update, then a copy of each TransformBuffer::skinning()),
//                        timed alternately in the same run; counter c_over_cpp (goal <= 1.15).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

#include "marionette/io/import.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/scene/scene.hpp"

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

constexpr int kCrowd = 100;

void BM_LoadSharedAsset(benchmark::State& state) {
  const std::string bytes = marionette::test::readFile(marionette::test::sharedAsset("characters/RobotExpressive.glb"));
  if (bytes.empty()) return state.SkipWithError("cannot read ../shared/assets/characters/RobotExpressive.glb");
  for (auto _ : state) {
    mn_asset* asset = nullptr;
    mn_scene* scene = nullptr;
    if (mn_asset_load_memory(bytes.data(), bytes.size(), "RobotExpressive.glb", nullptr, &asset) != MN_OK ||
        mn_scene_create(&scene) != MN_OK)
      return state.SkipWithError("mn_asset_load_memory failed");
    for (int i = 0; i < kCrowd; ++i)
      mn_scene_add_character_from_asset(scene, ("robot" + std::to_string(i)).c_str(), asset, nullptr);
    mn_asset_release(asset);
    state.PauseTiming();
    mn_scene_destroy(scene);
    state.ResumeTiming();
  }
}
BENCHMARK(BM_LoadSharedAsset)->Name("CApi/LoadSharedAsset")->Unit(benchmark::kMillisecond)->Iterations(10);

// One frame of the crowd through C, and the same through C++, each `frames` times.
struct Crowds {
  mn_scene* c = nullptr;
  marionette::Scene cpp;
  std::vector<float> palette;
  bool ok = false;
  Crowds() {
    const std::string path = marionette::test::sharedAsset("characters/RobotExpressive.glb");
    mn_asset* asset = nullptr;
    if (mn_asset_load_file(path.c_str(), nullptr, &asset) != MN_OK || mn_scene_create(&c) != MN_OK) return;
    marionette::ImportResult imported = marionette::importAsset(path, {.loadMeshes = false});
    if (!imported.ok()) return;
    auto rig = std::make_shared<marionette::Rig>(*imported.asset);
    const auto profile = marionette::loadCharacterProfile(
        marionette::test::sourceFile("assets/profiles/RobotExpressive.json"), *imported.asset);
    rig->setProfile(profile.profile);
    for (int i = 0; i < kCrowd; ++i) {
      const std::string name = "robot" + std::to_string(i);
      mn_character* ch = nullptr;
      mn_play_options play = mn_play_options_default();
      play.start_time = 0.013 * i;
      if (mn_scene_add_character_from_asset(c, name.c_str(), asset, &ch) != MN_OK ||
          mn_character_play(ch, 0, "Walking", &play) != MN_OK)
        return;
      marionette::Character* cc = cpp.addCharacter(name, rig);
      marionette::PlayOptions options;
      options.startTime = 0.013 * i;
      if (!cc || !cc->play(0, "Walking", options)) return;
    }
    mn_asset_release(asset);
    palette.resize(mn_character_joint_count(mn_scene_character_at(c, 0)) * 16);
    ok = true;
  }
  ~Crowds() { mn_scene_destroy(c); }
  void frameC() {
    mn_scene_update(c, 1.0 / 60.0);
    for (std::size_t i = 0; i < kCrowd; ++i)
      mn_character_palette(mn_scene_character_at(c, i), MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette.data(), palette.size());
    benchmark::DoNotOptimize(palette.data());
  }
  void frameCpp() {
    cpp.update(1.0 / 60.0);
    for (const auto& ch : cpp.characters()) {
      const auto skinning = ch->transformBuffer().skinning();
      std::copy(skinning.begin(), skinning.end(), palette.begin());
    }
    benchmark::DoNotOptimize(palette.data());
  }
};

void BM_FrameVsCpp(benchmark::State& state) {
  Crowds crowds;
  if (!crowds.ok) return state.SkipWithError("cannot set up the crowds (RobotExpressive.glb, its profile)");
  for (int i = 0; i < 30; ++i) crowds.frameC(), crowds.frameCpp();  // warm
  double cSeconds = 0.0, cppSeconds = 0.0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    crowds.frameC();
    auto t1 = std::chrono::steady_clock::now();
    crowds.frameCpp();
    auto t2 = std::chrono::steady_clock::now();
    cSeconds += std::chrono::duration<double>(t1 - t0).count();
    cppSeconds += std::chrono::duration<double>(t2 - t1).count();
  }
  const double frames = static_cast<double>(state.iterations());
  state.counters["c_us_per_character"] = cSeconds / frames / kCrowd * 1e6;
  state.counters["cpp_us_per_character"] = cppSeconds / frames / kCrowd * 1e6;
  state.counters["c_over_cpp"] = cSeconds / cppSeconds;
}
BENCHMARK(BM_FrameVsCpp)->Name("CApi/FrameVsCpp")->Unit(benchmark::kMillisecond);

}  // namespace
