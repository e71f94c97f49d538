// The engine hooks through marionette.h alone: mn_scene_set_parallel_for gives palettes
// bit-identical to one thread (chunks in reverse on threads of the engine's, or serially),
// with clip callbacks serialized; mn_set_allocator sees the scene and character handles,
// gets every block back, and is refused while handles are alive.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "marionette/marionette.h"
#include "test_data.hpp"

namespace {

const std::string kRobot = marionette::test::sharedAsset("characters/RobotExpressive.glb");
const std::string kRobotProfile = marionette::test::sourceFile("assets/profiles/RobotExpressive.json");
constexpr int kCharacters = 20;  // two chunks: 16 and 4

struct Engine {
  std::atomic<int> calls{0}, tasks{0};
};

// The engine's job system: three threads of its own, the chunks from last to first.
void reverseOnThreads(void* user, mn_parallel_task_fn task, void* context, int chunk_count) {
  Engine& engine = *static_cast<Engine*>(user);
  ++engine.calls;
  std::atomic<int> next{0};
  std::vector<std::thread> threads;
  for (int w = 0; w < 3; ++w)
    threads.emplace_back([&] {
      for (int k = next++; k < chunk_count; k = next++) {
        task(context, chunk_count - 1 - k);
        ++engine.tasks;
      }
    });
  for (std::thread& t : threads) t.join();
}

void serially(void* user, mn_parallel_task_fn task, void* context, int chunk_count) {
  Engine& engine = *static_cast<Engine*>(user);
  ++engine.calls;
  for (int i = 0; i < chunk_count; ++i) {
    task(context, i);
    ++engine.tasks;
  }
}

struct ClipEvents {
  std::atomic<int> inside{0};
  int overlaps = 0, stopped = 0;
};
void onClip(void* user, const mn_clip_event* e) {
  ClipEvents& c = *static_cast<ClipEvents*>(user);
  if (c.inside.fetch_add(1) != 0) ++c.overlaps;
  c.stopped += e->kind == MN_CLIP_STOPPED;
  c.inside.fetch_sub(1);
}

// A scene of kCharacters robots, each playing clips of its own choosing.
mn_scene* robotScene(ClipEvents& events) {
  mn_scene* scene = nullptr;
  EXPECT_EQ(mn_scene_create(&scene), MN_OK);
  EXPECT_EQ(mn_scene_set_clip_callback(scene, &onClip, &events), MN_OK);
  const char* clips[] = {"Idle", "Walking", "Running", "Dance", "Wave", "Yes"};
  for (int i = 0; i < kCharacters; ++i) {
    mn_character* c = nullptr;
    const std::string name = "robot" + std::to_string(i);
    EXPECT_EQ(mn_scene_add_character(scene, name.c_str(), kRobot.c_str(), kRobotProfile.c_str(), &c), MN_OK)
        << mn_scene_last_error(scene);
    if (!c) continue;
    mn_character_set_position(c, static_cast<float>(i % 5), 0.0f, static_cast<float>(i / 5));
    mn_play_options o = mn_play_options_default();
    o.speed = 0.8f + 0.05f * static_cast<float>(i % 6);
    o.root_motion = i % 3 == 0;
    o.start_time = 0.1 * i;
    EXPECT_EQ(mn_character_play(c, 0, clips[i % 6], &o), MN_OK) << mn_scene_last_error(scene);
    mn_play_options over = mn_play_options_default();
    over.weight = 0.4f;
    over.additive = i % 2;
    over.fade_in = 0.2f;
    EXPECT_EQ(mn_character_play(c, 1, clips[(i + 2) % 6], &over), MN_OK);
    EXPECT_EQ(mn_character_stop(c, 1, 0.5f + 0.05f * static_cast<float>(i)), MN_OK);  // clip stops mid-update
  }
  return scene;
}

std::vector<float> palettes(mn_scene* scene) {
  std::vector<float> all;
  for (size_t i = 0; i < mn_scene_character_count(scene); ++i) {
    mn_character* c = mn_scene_character_at(scene, i);
    std::vector<float> p(mn_character_joint_count(c) * 16);
    EXPECT_EQ(mn_character_palette(c, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, p.data(), p.size()), MN_OK);
    all.insert(all.end(), p.begin(), p.end());
    float world[16];
    EXPECT_EQ(mn_character_world_matrix(c, world), MN_OK);
    all.insert(all.end(), world, world + 16);
  }
  return all;
}

// An engine's allocator with a ledger of what it gave.
struct Ledger {
  std::mutex mutex;
  std::map<const void*, std::pair<size_t, size_t>> live;
  long allocations = 0, frees = 0, foreign = 0, mismatched = 0;
  bool failAll = false;
  bool owns(const void* p) {
    const std::lock_guard lock(mutex);
    return live.count(p) != 0;
  }
};
void* ledgerAlloc(void* user, size_t size, size_t alignment) {
  Ledger& l = *static_cast<Ledger*>(user);
  const std::lock_guard lock(l.mutex);
  if (l.failAll) return nullptr;
  void* p = std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
  ++l.allocations;
  l.live[p] = {size, alignment};
  return p;
}
void ledgerFree(void* user, void* block, size_t size, size_t alignment) {
  Ledger& l = *static_cast<Ledger*>(user);
  const std::lock_guard lock(l.mutex);
  ++l.frees;
  const auto it = l.live.find(block);
  if (it == l.live.end()) {
    ++l.foreign;
    return;
  }
  if (it->second != std::make_pair(size, alignment)) ++l.mismatched;
  l.live.erase(it);
  std::free(block);
}

}  // namespace

TEST(CHooks, ParallelForGivesThePalettesOfOneThread) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  ClipEvents serialEvents, reversedEvents, inOrderEvents;
  mn_scene* serial = robotScene(serialEvents);
  mn_scene* reversed = robotScene(reversedEvents);
  mn_scene* inOrder = robotScene(inOrderEvents);
  Engine reverseEngine, serialEngine;
  ASSERT_EQ(mn_scene_set_parallel_for(reversed, &reverseOnThreads, &reverseEngine), MN_OK);
  ASSERT_EQ(mn_scene_set_parallel_for(inOrder, &serially, &serialEngine), MN_OK);
  const double steps[] = {1.0 / 60, 1.0 / 30, 0.0, 0.1, 1.0 / 144, 0.5};
  for (int f = 0; f < 120; ++f) {
    for (mn_scene* s : {serial, reversed, inOrder}) ASSERT_EQ(mn_scene_update(s, steps[f % 6]), MN_OK);
    const std::vector<float> expected = palettes(serial);
    const std::vector<float> a = palettes(reversed), b = palettes(inOrder);
    ASSERT_EQ(a.size(), expected.size());
    ASSERT_EQ(std::memcmp(a.data(), expected.data(), a.size() * sizeof(float)), 0) << "reversed, frame " << f;
    ASSERT_EQ(std::memcmp(b.data(), expected.data(), b.size() * sizeof(float)), 0) << "serial hook, frame " << f;
  }
  EXPECT_EQ(reverseEngine.calls.load(), 120);
  EXPECT_EQ(reverseEngine.tasks.load(), 240);
  EXPECT_EQ(serialEngine.tasks.load(), 240);
  // Every character's layer 1 faded out during an update: one stop each, never two callbacks at once.
  EXPECT_EQ(reversedEvents.stopped, kCharacters);
  EXPECT_EQ(reversedEvents.stopped, serialEvents.stopped);
  EXPECT_EQ(reversedEvents.overlaps, 0);
  // NULL gives the library's own thread back; a bad handle is refused.
  EXPECT_EQ(mn_scene_set_parallel_for(reversed, nullptr, nullptr), MN_OK);
  EXPECT_EQ(mn_scene_update(reversed, 1.0 / 60), MN_OK);
  EXPECT_EQ(reverseEngine.calls.load(), 120);
  EXPECT_EQ(mn_scene_set_parallel_for(nullptr, &serially, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_scene_set_parallel_for: scene is NULL"),
            std::string::npos);
  for (mn_scene* s : {serial, reversed, inOrder}) mn_scene_destroy(s);
}

TEST(CHooks, AllocatorSeesTheHandlesAndGetsEveryBlockBack) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  // One function alone is refused.
  Ledger ledger;
  EXPECT_EQ(mn_set_allocator(&ledgerAlloc, nullptr, &ledger), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("both"), std::string::npos);
  ASSERT_EQ(mn_set_allocator(&ledgerAlloc, &ledgerFree, &ledger), MN_OK) << mn_scene_last_error(nullptr);
  {
    mn_scene* scene = nullptr;
    ASSERT_EQ(mn_scene_create(&scene), MN_OK);
    EXPECT_TRUE(ledger.owns(scene)) << "the scene handle (and the Scene inside it)";
    std::vector<mn_character*> characters;
    for (int i = 0; i < 3; ++i) {
      mn_character* c = nullptr;
      const std::string name = "robot" + std::to_string(i);
      ASSERT_EQ(mn_scene_add_character(scene, name.c_str(), kRobot.c_str(), kRobotProfile.c_str(), &c), MN_OK)
          << mn_scene_last_error(scene);
      EXPECT_TRUE(ledger.owns(c)) << "the character handle";
      EXPECT_EQ(mn_character_play(c, 0, "Walking", nullptr), MN_OK);
      characters.push_back(c);
    }
    const char* bones[] = {"Head", "Torso", "Hips"};
    const mn_engine_skeleton engine{bones, nullptr, 3, nullptr, 0};
    mn_binding* binding = nullptr;
    ASSERT_EQ(mn_binding_create(characters[0], &engine, nullptr, &binding), MN_OK) << mn_scene_last_error(scene);
    EXPECT_TRUE(ledger.owns(binding));
    for (int f = 0; f < 30; ++f) ASSERT_EQ(mn_scene_update(scene, 1.0 / 60), MN_OK);
    // Refused while handles are alive.
    EXPECT_EQ(mn_set_allocator(nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("alive"), std::string::npos)
        << mn_scene_last_error(nullptr);
    EXPECT_EQ(mn_scene_remove_character(scene, characters[2]), MN_OK);
    mn_binding_destroy(binding);
    mn_scene_destroy(scene);
  }
  // The handles' memory is held back after destroy (stale handles stay refused); with no
  // handle alive, changing the allocator gives it back first.
  ASSERT_EQ(mn_set_allocator(nullptr, nullptr, nullptr), MN_OK) << mn_scene_last_error(nullptr);
  {
    const std::lock_guard lock(ledger.mutex);
    EXPECT_TRUE(ledger.live.empty()) << ledger.live.size() << " block(s) not given back";
    EXPECT_EQ(ledger.allocations, ledger.frees);
    EXPECT_GT(ledger.allocations, 3 * 5);
    EXPECT_EQ(ledger.foreign, 0);
    EXPECT_EQ(ledger.mismatched, 0);
  }
  // An allocator out of memory: MN_ERROR_OUT_OF_MEMORY, not a crash.
  Ledger empty;
  empty.failAll = true;
  ASSERT_EQ(mn_set_allocator(&ledgerAlloc, &ledgerFree, &empty), MN_OK);
  mn_scene* none = nullptr;
  EXPECT_EQ(mn_scene_create(&none), MN_ERROR_OUT_OF_MEMORY);
  EXPECT_EQ(none, nullptr);
  ASSERT_EQ(mn_set_allocator(nullptr, nullptr, nullptr), MN_OK) << mn_scene_last_error(nullptr);
}
