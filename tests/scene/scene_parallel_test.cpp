// Scene::update on several threads: bit-identical to one thread, every frame,
// with clips on layers, cross-character gaze, head nods, face expressions, clip
// behaviors and locomotion; listener calls serialized; thread count changed between
// frames; tiny scenes; the caller's floating-point environment.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cfenv>
#include <chrono>
#include <functional>
#include <iostream>
#include <set>
#include <string>
#include <thread>

#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"
#include "behavior_request.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

// `count` characters: three of four are RobotExpressive (two clip layers, some
// additive, a gaze at another character, nods, a face expression, a gesture
// clip, some walking to a point or a character), every fourth the 4-joint synthetic rig (walk with root motion, masked
// wave). Two skeleton sizes, so each thread's scratch must fit the larger.
void buildScene(Scene& scene, int count) {
  const auto robot = robotRig();
  const auto synthetic = makeSyntheticRig();
  for (int i = 0; i < count; ++i) {
    const float x = static_cast<float>(i % 10) * 1.5f, z = static_cast<float>(i / 10) * 1.5f;
    if (i % 4 == 3) {
      Character* c = scene.addCharacter("s" + std::to_string(i), synthetic);
      c->setPosition({x, 0.0f, z});
      c->play(0, "walk", {.speed = 0.9f + 0.01f * static_cast<float>(i % 7), .rootMotion = true});
      c->play(1, "wave", {.weight = 0.5f, .additive = i % 8 == 3, .jointMask = {0, 0, 1, 1}});
      continue;
    }
    Character* c = scene.addCharacter("r" + std::to_string(i), robot);
    c->setPosition({x, 0.0f, z});
    c->setHeading(0.3f * static_cast<float>(i % 5));
    c->play(0, "Idle", {.weight = 0.7f, .startTime = 0.05 * i});
    c->play(1, i % 3 == 0 ? "Walking" : "Running", {.weight = 0.3f, .fadeIn = 0.4f});
    if (i % 5 == 0) c->play(2, "Yes", {.weight = 0.6f, .additive = true});
    // Gaze at a character added earlier (or, for the first ones, at a point);
    // every other one at a joint of a synthetic character.
    const BehaviorTarget target = i < 4      ? BehaviorTarget::at({2.0f, 1.5f, 3.0f})
                                  : i % 2 == 0 ? BehaviorTarget::of("s" + std::to_string((i / 4) * 4 - 1), "j3")
                                               : BehaviorTarget::of("r" + std::to_string(i - 1));
    const double t0 = 0.02 * (i % 11);
    EXPECT_TRUE(c->addBehavior(request("gaze", BehaviorKind::Gaze, GazeParameters{target, GazeInfluence::Neck},
                                       {{"start", t0}, {"ready", t0 + 0.3}, {"relax", 2.5}, {"end", 3.0}}))
                    .realized)
        << c->name();
    for (int k = 0; k < 3; ++k) {
      const double s = 0.2 + 0.9 * k + 0.01 * (i % 13);
      EXPECT_TRUE(c->addBehavior(request("nod" + std::to_string(k), BehaviorKind::Head, HeadParameters{HeadLexeme::Nod},
                                         {{"start", s}, {"ready", s + .1}, {"strokeStart", s + .2},
                                          {"stroke", s + .3}, {"strokeEnd", s + .5}, {"relax", s + .8},
                                          {"end", s + 1}}))
                      .realized);
    }
    EXPECT_TRUE(c->addBehavior(request("face", BehaviorKind::FaceLexeme,
                                       FaceParameters{i % 2 ? "ANGER" : "SURPRISE", 0.7f},
                                       {{"start", 0.1}, {"attackPeak", 0.4}, {"relax", 1.8}, {"end", 2.2}}))
                    .realized);
    if (i % 5 == 2) {
      // Locomotion to a point, or to a character (whose position the serial pass reads).
      LocomotionParameters where;
      if (i % 10 == 2) where.waypoints = {{x + 3.0f, z - 2.0f}};
      else where.targetCharacter = "r0";
      where.manner = i % 4 ? LocomotionManner::Walk : LocomotionManner::Run;
      const BehaviorResult walk = c->addBehavior(request(
          "walk", BehaviorKind::Locomotion, where,
          {{"start", 0.3}, {"end", 4.0}}));
      EXPECT_TRUE(walk.realized) << c->name() << ": " << walk.message;
    }
    BehaviorRequest wave = request("wave", BehaviorKind::Gesture, {}, {{"start", 0.5}, {"end", 1.7}});
    wave.clip = "Wave";
    EXPECT_TRUE(c->addBehavior(wave).realized);
  }
}

// Frame f's step: usual rates, a paused frame, a long hitch.
double stepOf(int f) {
  constexpr double kSteps[] = {1.0 / 60, 1.0 / 30, 0.0, 1.0 / 240, 0.1, 1.0 / 60, 0.5, 1.0 / 144};
  return kSteps[f % 8];
}

// Between frames the engine does things at command time: cancels, stops,
// removes a character (with a gaze on it), adds one.
void commands(Scene& scene, int f) {
  if (f == 60)
    for (const auto& c : scene.characters()) c->cancelBehaviors("nod", 0.2);
  if (f == 90)
    for (std::size_t i = 0; i < scene.characters().size(); i += 3) scene.characters()[i]->stop(1, 0.3f);
  if (f == 120) scene.removeCharacter("r8");
  if (f == 130) scene.addCharacter("late", makeSyntheticRig())->play(0, "walk");
}

// Fails at the first frame where a character's buffer differs.
void expectSameEveryFrame(Scene& serial, Scene& parallel, int frames, const std::function<void(int)>& before = {}) {
  ASSERT_EQ(serial.characters().size(), parallel.characters().size());
  for (int f = 0; f < frames; ++f) {
    if (before) before(f);
    commands(serial, f);
    commands(parallel, f);
    serial.update(stepOf(f));
    parallel.update(stepOf(f));
    ASSERT_EQ(serial.characters().size(), parallel.characters().size());
    for (std::size_t i = 0; i < serial.characters().size(); ++i) {
      const Character& a = *serial.characters()[i];
      const Character& b = *parallel.characters()[i];
      ASSERT_EQ(a.transformBuffer().hash(), b.transformBuffer().hash())
          << "frame " << f << ", character " << a.name() << ", " << parallel.threadCount() << " threads";
    }
  }
}

}  // namespace

TEST(SceneParallel, ThreadCountIsClampedAndDefaultsToOne) {
  Scene scene;
  EXPECT_EQ(scene.threadCount(), 1);
  scene.setThreadCount(3);
  EXPECT_EQ(scene.threadCount(), 3);
  scene.setThreadCount(-4);
  EXPECT_EQ(scene.threadCount(), 1);
  scene.setThreadCount(1000);
  EXPECT_EQ(scene.threadCount(), 64);
  scene.setThreadCount(0);
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  EXPECT_EQ(scene.threadCount(), std::clamp(hardware, 1, 64));
  scene.setThreadCount(2);
  scene.setThreadCount(2);  // the same count again changes nothing
  EXPECT_EQ(scene.threadCount(), 2);
}  // destroyed with live, idle workers: joins them

// The main check: 200 frames of varying dt, every character's buffer equal to
// the one-thread run after every frame, for 2, 3, hardware and 8 threads (more
// threads than cores). Threads set before adding characters too, so the
// workers' scratch must grow when characters arrive.
TEST(SceneParallel, EveryFrameIsBitIdenticalToOneThread) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  ASSERT_TRUE(robotRig());
  for (int threads : {2, 3, 0, 8}) {
    for (bool threadsFirst : {false, true}) {
      SCOPED_TRACE("threads " + std::to_string(threads) + (threadsFirst ? ", set before adding" : ""));
      Scene serial, parallel;
      if (threadsFirst) parallel.setThreadCount(threads);
      buildScene(serial, 100);
      buildScene(parallel, 100);
      if (!threadsFirst) parallel.setThreadCount(threads);
      expectSameEveryFrame(serial, parallel, 200);
      if (HasFatalFailure()) return;
    }
  }
}

// Thread counts changed between frames, stats on (per-character timing must
// still be filled in by whichever thread ran the character).
TEST(SceneParallel, ThreadCountChangesBetweenFramesAndStatsStillWork) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene serial, parallel;
  buildScene(serial, 60);
  buildScene(parallel, 60);
  parallel.setStatsEnabled(true);
  const int counts[] = {2, 1, 3, 4, 0, 2, 1, 5};
  expectSameEveryFrame(serial, parallel, 160, [&](int f) {
    if (f % 20 == 0) parallel.setThreadCount(counts[(f / 20) % 8]);
  });
  parallel.setThreadCount(3);
  parallel.update(1.0 / 60);
  for (const auto& c : parallel.characters()) EXPECT_GT(c->stats().lastUpdateMicros, 0.0) << c->name();
}

// The scene's clock and the caller's floating-point environment: workers round
// like the calling thread (an engine may set its own rounding or flush-to-zero).
TEST(SceneParallel, WorkersUseTheCallersFloatingPointEnvironment) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene serial, parallel;
  buildScene(serial, 60);
  buildScene(parallel, 60);
  parallel.setThreadCount(2);
  std::fenv_t saved;
  std::fegetenv(&saved);
  std::fesetround(FE_UPWARD);
  expectSameEveryFrame(serial, parallel, 40);
  std::fesetenv(&saved);
}

// Every listener call made during a parallel update arrives, one at a time;
// a callback that logs through the scene does not deadlock.
TEST(SceneParallel, ListenerCallsAreSerializedAndNoneIsLost) {
  Scene scene;
  const auto rig = makeSyntheticRig();
  constexpr int kCharacters = 96;
  for (int i = 0; i < kCharacters; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->play(0, "walk");
  }
  struct Counter : SceneListener {
    Scene* scene = nullptr;
    std::atomic<int> inside{0};
    int overlaps = 0, stopped = 0, logs = 0;
    std::set<std::string> names;
    std::set<std::thread::id> threads;
    void onCharacterChanged(const Character& c, ChangeKind kind, std::string_view) override {
      if (inside.fetch_add(1) != 0) ++overlaps;
      if (kind == ChangeKind::ClipStopped) {
        ++stopped;
        threads.insert(std::this_thread::get_id());
        scene->log(LogLevel::Info, c.name());  // re-enters the listener fan-out on this thread
        // Linger, so that an unserialized call from another thread would overlap.
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(20);
        while (std::chrono::steady_clock::now() < until) {
        }
      }
      inside.fetch_sub(1);
    }
    void onLog(LogLevel, std::string_view message) override {
      ++logs;
      names.insert(std::string(message));
    }
  } listener;
  listener.scene = &scene;
  scene.addListener(&listener);
  scene.setThreadCount(2);
  // Every character fades its wave layer out over 0.1 s: each sends one
  // ClipStopped from inside update(), wherever it is updated. Rounds repeat
  // until a worker has sent some (at most 20), so that the serialized path runs
  // even where workers wake slowly (ThreadSanitizer). Every round counts.
  int rounds = 0;
  while (rounds < 20 && (rounds == 0 || listener.threads.size() < 2)) {
    for (const auto& c : scene.characters()) {
      c->play(1, "wave", {.weight = 0.5f});
      c->stop(1, 0.1f);
    }
    for (int f = 0; f < 12; ++f) scene.update(1.0 / 60);
    ++rounds;
  }
  EXPECT_EQ(listener.overlaps, 0);
  EXPECT_EQ(listener.stopped, rounds * kCharacters);
  EXPECT_EQ(listener.logs, rounds * kCharacters);
  EXPECT_EQ(listener.names.size(), static_cast<std::size_t>(kCharacters));
  // Informational: on a busy machine the caller may do every chunk itself.
  std::cout << "ClipStopped arrived on " << listener.threads.size() << " thread(s) in " << rounds << " round(s)\n";
  // A log from the calling thread after the update still arrives.
  scene.log(LogLevel::Warning, "after");
  EXPECT_EQ(listener.logs, rounds * kCharacters + 1);
  scene.removeListener(&listener);
}

// Scenes of 0, 1 and a few characters with more threads than characters.
TEST(SceneParallel, TinyScenesWithManyThreads) {
  Scene scene;
  scene.setThreadCount(4);
  scene.update(1.0 / 60);
  EXPECT_EQ(scene.frame(), 1u);
  Scene reference;
  const auto rig = makeSyntheticRig();
  for (Scene* s : {&scene, &reference}) s->addCharacter("one", rig)->play(0, "walk", {.rootMotion = true});
  for (int f = 0; f < 30; ++f) {
    scene.update(stepOf(f));
    reference.update(stepOf(f));
    ASSERT_EQ(scene.characters()[0]->transformBuffer().hash(), reference.characters()[0]->transformBuffer().hash());
  }
  // Just over one chunk: two chunks between four threads.
  for (Scene* s : {&scene, &reference})
    for (int i = 0; i < 17; ++i) s->addCharacter("c" + std::to_string(i), rig)->play(0, "wave");
  for (int f = 0; f < 30; ++f) {
    scene.update(stepOf(f));
    reference.update(stepOf(f));
    for (std::size_t i = 0; i < scene.characters().size(); ++i)
      ASSERT_EQ(scene.characters()[i]->transformBuffer().hash(), reference.characters()[i]->transformBuffer().hash());
  }
  EXPECT_TRUE(scene.removeCharacter("one"));
  scene.update(1.0 / 60);
  scene.update(-1.0);  // rejected as in one thread
  EXPECT_EQ(scene.frame(), 62u);
}
