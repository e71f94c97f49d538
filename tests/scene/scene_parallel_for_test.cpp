// Scene::setParallelFor: the characters' chunks on an engine's job system. Buffers
// bit-identical to one thread and to the scene's pool, every frame, with hooks that run
// the chunks in reverse on threads of their own (rounding differently) or serially;
// listener calls serialized; small scenes; switching between the hook and the pool;
// a hook that breaks the contract is reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cfenv>
#include <chrono>
#include <cstring>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"
#include "behavior_request.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

// What a hook saw: calls, chunks run, and whether an engine thread's own rounding mode
// survived the tasks it ran.
struct HookLog {
  std::atomic<int> calls{0}, tasks{0}, roundingLost{0};
  std::set<std::thread::id> threads;  // written after the joins only
};

// An engine's job system, roughly: `workers` threads of its own (rounding toward zero, as
// an engine's thread may), taking the chunks from the last to the first.
template <int kWorkers>
void reverseOnThreads(void* user, Scene::ParallelTask task, void* context, int chunkCount) {
  HookLog& log = *static_cast<HookLog*>(user);
  ++log.calls;
  std::atomic<int> next{0};
  std::vector<std::thread> threads;
  std::vector<std::thread::id> ids;
  for (int w = 0; w < kWorkers; ++w)
    threads.emplace_back([&] {
      std::fesetround(FE_TOWARDZERO);
      for (int k = next++; k < chunkCount; k = next++) {
        task(context, chunkCount - 1 - k);
        ++log.tasks;
        if (std::fegetround() != FE_TOWARDZERO) ++log.roundingLost;
      }
    });
  for (std::thread& t : threads) {
    ids.push_back(t.get_id());
    t.join();
  }
  log.threads.insert(ids.begin(), ids.end());
}

// The simplest correct hook: every chunk in order on the calling thread.
void serially(void* user, Scene::ParallelTask task, void* context, int chunkCount) {
  HookLog& log = *static_cast<HookLog*>(user);
  ++log.calls;
  for (int i = 0; i < chunkCount; ++i) {
    task(context, i);
    ++log.tasks;
  }
}

// `count` characters in real motion: RobotExpressive with two clip layers (some additive),
// a gaze at another character, nods, a face expression, some walking to a point or to a
// character; every fourth the 4-joint synthetic rig walking with root motion. Two skeleton
// sizes, so that every chunk's scratch must fit the larger.
void buildScene(Scene& scene, int count, const std::string& prefix = "") {
  const auto robot = robotRig();
  const auto synthetic = makeSyntheticRig();
  for (int i = 0; i < count; ++i) {
    const float x = static_cast<float>(i % 8) * 1.5f, z = static_cast<float>(i / 8) * 1.5f;
    if (i % 4 == 3) {
      Character* c = scene.addCharacter(prefix + "s" + std::to_string(i), synthetic);
      c->setPosition({x, 0.0f, z});
      c->play(0, "walk", {.speed = 0.9f + 0.01f * static_cast<float>(i % 7), .rootMotion = true});
      c->play(1, "wave", {.weight = 0.5f, .additive = i % 8 == 3, .jointMask = {0, 0, 1, 1}});
      continue;
    }
    Character* c = scene.addCharacter(prefix + "r" + std::to_string(i), robot);
    c->setPosition({x, 0.0f, z});
    c->setHeading(0.4f * static_cast<float>(i % 5));
    c->play(0, "Idle", {.weight = 0.8f, .startTime = 0.03 * i});
    c->play(1, i % 3 == 0 ? "Walking" : "Running", {.weight = 0.4f, .fadeIn = 0.3f});
    if (i % 5 == 0) c->play(2, "Yes", {.weight = 0.6f, .additive = true});
    const BehaviorTarget target = i < 4 ? BehaviorTarget::at({2.0f, 1.5f, 3.0f})
                                        : BehaviorTarget::of(prefix + "r" + std::to_string(i - 4));
    EXPECT_TRUE(c->addBehavior(request("gaze", BehaviorKind::Gaze, GazeParameters{target, GazeInfluence::Neck},
                                       {{"start", 0.05}, {"ready", 0.4}, {"relax", 2.5}, {"end", 3.0}}))
                    .realized);
    const double s = 0.2 + 0.01 * (i % 13);
    EXPECT_TRUE(c->addBehavior(request("nod", BehaviorKind::Head, HeadParameters{HeadLexeme::Nod},
                                       {{"start", s}, {"ready", s + .1}, {"strokeStart", s + .2}, {"stroke", s + .3},
                                        {"strokeEnd", s + .5}, {"relax", s + .8}, {"end", s + 1}}))
                    .realized);
    EXPECT_TRUE(c->addBehavior(request("face", BehaviorKind::FaceLexeme, FaceParameters{i % 2 ? "ANGER" : "SURPRISE", 0.7f},
                                       {{"start", 0.1}, {"attackPeak", 0.4}, {"relax", 1.8}, {"end", 2.2}}))
                    .realized);
    if (i % 5 == 2) {
      LocomotionParameters where;
      if (i % 10 == 2) where.waypoints = {{x + 3.0f, z - 2.0f}};
      else where.targetCharacter = prefix + "r0";
      where.manner = i % 4 ? LocomotionManner::Walk : LocomotionManner::Run;
      EXPECT_TRUE(c->addBehavior(request("walk", BehaviorKind::Locomotion, where, {{"start", 0.3}, {"end", 4.0}}))
                      .realized);
    }
  }
}

double stepOf(int f) {
  constexpr double kSteps[] = {1.0 / 60, 1.0 / 30, 0.0, 1.0 / 240, 0.1, 1.0 / 60, 0.5, 1.0 / 144};
  return kSteps[f % 8];
}

// Every array of the buffer, byte for byte (the hash is checked every frame; this at the end).
bool sameBytes(const TransformBuffer& a, const TransformBuffer& b) {
  const auto same = [](std::span<const float> x, std::span<const float> y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size_bytes()) == 0;
  };
  return same(a.skinning(), b.skinning()) && same(a.model(), b.model()) && same(a.morphWeights(), b.morphWeights()) &&
         std::memcmp(a.world(), b.world(), 16 * sizeof(float)) == 0;
}

}  // namespace

// The main check: 41 characters (three chunks, the last of 9), 200 frames of varying dt,
// commands between frames (a character removed, two added: a fourth chunk while hooked),
// every character's buffer equal after every frame in the four scenes.
TEST(SceneParallelFor, BuffersAreBitIdenticalToOneThreadAndToThePool) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  ASSERT_TRUE(robotRig());
  Scene serial, pool, reversed, inOrder;
  HookLog reverseLog, serialLog;
  reversed.setParallelFor(&reverseOnThreads<3>, &reverseLog);  // before the characters: scratch grows with them
  Scene* scenes[] = {&serial, &pool, &reversed, &inOrder};
  for (Scene* s : scenes) buildScene(*s, 41);
  pool.setThreadCount(3);
  inOrder.setParallelFor(&serially, &serialLog);  // after: scratch for the chunks there are
  EXPECT_EQ(reversed.threadCount(), 1);  // the scene owns no thread while hooked
  for (int f = 0; f < 200; ++f) {
    for (Scene* s : scenes) {
      if (f == 50) {
        EXPECT_TRUE(s->removeCharacter("r9"));
      }
      if (f == 80) {
        s->addCharacter("late1", makeSyntheticRig())->play(0, "walk", {.rootMotion = true});
        s->addCharacter("late2", robotRig())->play(0, "Dance");
        s->addCharacter("late3", robotRig())->play(0, "Jump", {.speed = 1.3f});
        s->addCharacter("late4", robotRig())->play(0, "Walking");
        s->addCharacter("late5", makeSyntheticRig())->play(0, "wave");
        s->addCharacter("late6", robotRig())->play(0, "Punch");
        s->addCharacter("late7", robotRig())->play(0, "ThumbsUp");
        s->addCharacter("late8", makeSyntheticRig())->play(0, "walk");
      }
      s->update(stepOf(f));
    }
    for (std::size_t i = 0; i < serial.characters().size(); ++i) {
      const std::uint64_t expected = serial.characters()[i]->transformBuffer().hash();
      ASSERT_EQ(pool.characters()[i]->transformBuffer().hash(), expected) << "pool, frame " << f << ", " << i;
      ASSERT_EQ(reversed.characters()[i]->transformBuffer().hash(), expected) << "reversed, frame " << f << ", " << i;
      ASSERT_EQ(inOrder.characters()[i]->transformBuffer().hash(), expected) << "serial hook, frame " << f << ", " << i;
    }
  }
  ASSERT_EQ(serial.characters().size(), 48u);  // three chunks, then 48: exactly three again
  for (std::size_t i = 0; i < serial.characters().size(); ++i) {
    const TransformBuffer& expected = serial.characters()[i]->transformBuffer();
    EXPECT_EQ(expected.frame(), serial.frame() - (i >= 40 ? 80 : 0)) << i;
    EXPECT_TRUE(sameBytes(pool.characters()[i]->transformBuffer(), expected)) << i;
    EXPECT_TRUE(sameBytes(reversed.characters()[i]->transformBuffer(), expected)) << i;
    EXPECT_TRUE(sameBytes(inOrder.characters()[i]->transformBuffer(), expected)) << i;
  }
  // Each frame one call with every chunk (3, then 40 characters: 3, then 48: 3).
  EXPECT_EQ(reverseLog.calls.load(), 200);
  EXPECT_EQ(reverseLog.tasks.load(), 600);
  EXPECT_EQ(serialLog.tasks.load(), 600);
  EXPECT_EQ(reverseLog.roundingLost.load(), 0) << "a task left the engine thread with the caller's rounding";
  EXPECT_GE(reverseLog.threads.size(), 3u);
}

// The caller's rounding mode reaches the chunks on the engine's threads (which round
// toward zero), as it reaches the pool's workers.
TEST(SceneParallelFor, ChunksRunUnderTheCallersFloatingPointEnvironment) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  Scene serial, hooked;
  HookLog log;
  buildScene(serial, 33);
  buildScene(hooked, 33);
  hooked.setParallelFor(&reverseOnThreads<2>, &log);
  std::fenv_t saved;
  std::fegetenv(&saved);
  std::fesetround(FE_UPWARD);
  bool same = true;
  for (int f = 0; f < 40 && same; ++f) {
    serial.update(stepOf(f));
    hooked.update(stepOf(f));
    for (std::size_t i = 0; i < serial.characters().size(); ++i)
      same = same && serial.characters()[i]->transformBuffer().hash() == hooked.characters()[i]->transformBuffer().hash();
  }
  std::fesetenv(&saved);
  EXPECT_TRUE(same);
  EXPECT_EQ(log.roundingLost.load(), 0);
}

// Every listener call made during a hooked update arrives, one at a time, from the
// engine's threads; a callback that logs through the scene does not deadlock.
TEST(SceneParallelFor, ListenerCallsStaySerialized) {
  Scene scene;
  const auto rig = makeSyntheticRig();
  constexpr int kCharacters = 96;
  for (int i = 0; i < kCharacters; ++i) scene.addCharacter("c" + std::to_string(i), rig)->play(0, "walk");
  struct Counter : SceneListener {
    Scene* scene = nullptr;
    std::atomic<int> inside{0};
    int overlaps = 0, stopped = 0, logs = 0;
    std::set<std::thread::id> threads;
    void onCharacterChanged(const Character& c, ChangeKind kind, std::string_view) override {
      if (inside.fetch_add(1) != 0) ++overlaps;
      if (kind == ChangeKind::ClipStopped) {
        ++stopped;
        threads.insert(std::this_thread::get_id());
        scene->log(LogLevel::Info, c.name());  // re-enters the fan-out on this thread
        const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(20);
        while (std::chrono::steady_clock::now() < until) {
        }
      }
      inside.fetch_sub(1);
    }
    void onLog(LogLevel, std::string_view) override { ++logs; }
  } listener;
  listener.scene = &scene;
  scene.addListener(&listener);
  HookLog log;
  scene.setParallelFor(&reverseOnThreads<4>, &log);
  for (const auto& c : scene.characters()) {
    c->play(1, "wave", {.weight = 0.5f});
    c->stop(1, 0.1f);
  }
  for (int f = 0; f < 12; ++f) scene.update(1.0 / 60);
  EXPECT_EQ(listener.overlaps, 0);
  EXPECT_EQ(listener.stopped, kCharacters);
  EXPECT_EQ(listener.logs, kCharacters);
  EXPECT_FALSE(listener.threads.count(std::this_thread::get_id()));  // all from the engine's threads
  EXPECT_GE(listener.threads.size(), 1u);
  scene.removeListener(&listener);
}

// Small scenes do not call the hook; the hook and the pool replace each other; a hook
// that skips a chunk is reported and its characters keep their last frame.
TEST(SceneParallelFor, SmallScenesSwitchingAndABrokenHook) {
  Scene scene;
  const auto rig = makeSyntheticRig();
  for (int i = 0; i < 16; ++i) scene.addCharacter("c" + std::to_string(i), rig)->play(0, "walk");
  HookLog log;
  scene.setThreadCount(3);
  EXPECT_EQ(scene.threadCount(), 3);
  scene.setParallelFor(&serially, &log);
  EXPECT_EQ(scene.parallelFor(), &serially);
  EXPECT_EQ(scene.threadCount(), 1);
  scene.update(1.0 / 60);
  EXPECT_EQ(log.calls.load(), 0);  // one chunk: on the caller
  scene.addCharacter("c16", rig)->play(0, "walk");
  scene.update(1.0 / 60);
  EXPECT_EQ(log.calls.load(), 1);
  EXPECT_EQ(log.tasks.load(), 2);
  scene.setThreadCount(2);  // kept for later; the hook stays
  EXPECT_EQ(scene.parallelFor(), &serially);
  EXPECT_EQ(scene.threadCount(), 1);
  scene.setParallelFor(nullptr, nullptr);
  EXPECT_EQ(scene.threadCount(), 2);  // the scene's own threads, as last asked for
  scene.update(1.0 / 60);
  EXPECT_EQ(log.calls.load(), 1);

  struct Errors : SceneListener {
    int errors = 0;
    void onLog(LogLevel level, std::string_view) override { errors += level == LogLevel::Error; }
  } errors;
  scene.addListener(&errors);
  const auto firstOnly = [](void*, Scene::ParallelTask task, void* context, int) { task(context, 0); };
  scene.setParallelFor(firstOnly, nullptr);
  const std::uint64_t before = scene.characters()[16]->transformBuffer().frame();
  const std::uint64_t firstBefore = scene.characters()[0]->transformBuffer().frame();
  scene.update(1.0 / 60);
  EXPECT_EQ(errors.errors, 1);
  EXPECT_EQ(scene.characters()[16]->transformBuffer().frame(), before);  // its chunk did not run
  EXPECT_EQ(scene.characters()[0]->transformBuffer().frame(), firstBefore + 1);
  // Out-of-range chunks are ignored (and reported as not every chunk run once).
  const auto wild = [](void*, Scene::ParallelTask task, void* context, int n) {
    for (int i = -1; i <= n; ++i) task(context, i);
  };
  scene.setParallelFor(wild, nullptr);
  scene.update(1.0 / 60);
  EXPECT_EQ(errors.errors, 1);  // every real chunk once: no report
  EXPECT_EQ(scene.characters()[16]->transformBuffer().frame(), before + 1);
  scene.removeListener(&errors);
}
