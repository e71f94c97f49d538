// marionette::setAllocator, counted: with a counting allocator installed, the objects the
// docs say it covers come from it (Scene, Character, its state, the transform buffer's
// arrays, the pose, blend and chunk scratch); every block it gave is given back to it at
// destroy; nothing it did not give is given to it; frames allocate nothing from it; it
// cannot be changed while the runtime holds its memory. In marionette_allocation_tests
// (a program of its own: the allocator is process-wide).
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "marionette/core/allocator.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;

namespace {

// An engine's allocator that keeps a ledger of what it gave.
struct Ledger {
  struct Block {
    std::size_t size = 0, alignment = 0;
  };
  std::mutex mutex;
  std::map<const void*, Block> live;
  long allocations = 0, frees = 0, foreignFrees = 0, mismatchedFrees = 0, misaligned = 0;
  bool failNext = false;

  [[nodiscard]] bool owns(const void* p) {
    const std::lock_guard lock(mutex);
    return live.count(p) != 0;
  }
  [[nodiscard]] long allocationCount() {
    const std::lock_guard lock(mutex);
    return allocations;
  }
  static void* allocate(void* user, std::size_t size, std::size_t alignment) {
    Ledger& l = *static_cast<Ledger*>(user);
    void* p = std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
    const std::lock_guard lock(l.mutex);
    if (l.failNext) {
      l.failNext = false;
      std::free(p);
      return nullptr;
    }
    ++l.allocations;
    if (reinterpret_cast<std::uintptr_t>(p) % alignment != 0 || alignment < kRuntimeMinAlignment) ++l.misaligned;
    l.live[p] = {size, alignment};
    return p;
  }
  static void release(void* user, void* block, std::size_t size, std::size_t alignment) {
    Ledger& l = *static_cast<Ledger*>(user);
    {
      const std::lock_guard lock(l.mutex);
      ++l.frees;
      const auto it = l.live.find(block);
      if (it == l.live.end()) {
        ++l.foreignFrees;  // not ours: must never happen (and must not be freed here)
        return;
      }
      if (it->second.size != size || it->second.alignment != alignment) ++l.mismatchedFrees;
      l.live.erase(it);
    }
    std::free(block);
  }
  [[nodiscard]] RuntimeAllocatorHooks hooks() { return {&Ledger::allocate, &Ledger::release, this}; }
};

void serially(void*, Scene::ParallelTask task, void* context, int chunkCount) {
  for (int i = 0; i < chunkCount; ++i) task(context, i);
}

bool install(const RuntimeAllocatorHooks& hooks) {
  Diagnostics d;
  const bool ok = setAllocator(hooks, d);
  EXPECT_TRUE(ok) << d.format();
  return ok;
}

}  // namespace

TEST(AllocatorHook, CoversTheRuntimeObjectsAndGetsEveryBlockBack) {
  ASSERT_EQ(runtimeBlocksHeld(), 0u) << "a runtime object outlived an earlier test";
  const auto rig = marionette::test::makeSyntheticRig();  // rigs are not covered: made before, freed after
  Ledger ledger;
  ASSERT_TRUE(install(ledger.hooks()));
  {
    auto scene = std::make_unique<Scene>();
    EXPECT_TRUE(ledger.owns(scene.get())) << "the Scene object";
    scene->setThreadCount(2);
    std::vector<Character*> characters;
    for (int i = 0; i < 40; ++i) {
      Character* c = scene->addCharacter("c" + std::to_string(i), rig);
      ASSERT_TRUE(c);
      c->play(0, "walk", {.speed = 1.0f + 0.01f * static_cast<float>(i), .rootMotion = true});
      if (i % 2) c->play(1, "wave", {.weight = 0.5f, .additive = i % 4 == 1});
      c->transformBuffer().setPacked3x4(i % 3 == 0);
      if (i % 4 == 0) {  // a behavior: the controller passes are reserved
        BehaviorRequest g;
        g.id = "g";
        g.kind = BehaviorKind::Gesture;
        g.clip = "wave";
        g.syncs = {{"start", 0.0}, {"ready", 0.2}, {"relax", 1.0}, {"end", 2.0}};
        EXPECT_TRUE(c->addBehavior(g).realized);
      }
      characters.push_back(c);
    }
    for (Character* c : characters) {
      EXPECT_TRUE(ledger.owns(c)) << "the Character object " << c->name();
      const TransformBuffer& b = c->transformBuffer();
      EXPECT_TRUE(ledger.owns(b.skinning().data())) << c->name();
      EXPECT_TRUE(ledger.owns(b.model().data())) << c->name();
      EXPECT_TRUE(ledger.owns(b.morphWeights().data())) << c->name();  // the synthetic rig has two morphs
      EXPECT_EQ(b.packed3x4Enabled(), ledger.owns(b.skinning3x4().data())) << c->name();
      EXPECT_TRUE(ledger.owns(c->localPose().data())) << "the pose of " << c->name();
    }
    // Changing the allocator now would hand the scene's blocks to another: refused.
    Diagnostics refused;
    EXPECT_FALSE(setAllocator({}, refused));
    EXPECT_NE(refused.format().find("still holds"), std::string::npos) << refused.format();
    EXPECT_EQ(currentAllocator().user, &ledger);
    {
      const std::lock_guard lock(ledger.mutex);
      EXPECT_EQ(runtimeBlocksHeld(), ledger.live.size());
    }
    // Frames: the pool, then the engine's hook (its chunk scratch comes from the ledger too).
    for (int f = 0; f < 3; ++f) scene->update(1.0 / 60);
    const long beforeHook = ledger.allocationCount();
    scene->setParallelFor(&serially, nullptr);
    EXPECT_GE(ledger.allocationCount() - beforeHook, 3 * 3) << "three chunks: three scratch objects and their arrays";
    scene->update(1.0 / 60);  // warm-up
    const long warm = ledger.allocationCount();
    for (int f = 0; f < 200; ++f) scene->update(f % 7 == 0 ? 0.25 : 1.0 / 60);
    EXPECT_EQ(ledger.allocationCount(), warm) << "frames allocate nothing";
    EXPECT_TRUE(scene->removeCharacter("c5"));
    // A character outside a scene blends in scratch of its own.
    auto standalone = std::make_unique<Character>("alone", rig);
    standalone->play(0, "walk");
    standalone->play(1, "wave", {.weight = 0.5f});
    standalone->update(0.1);
    EXPECT_TRUE(ledger.owns(standalone.get()));
  }
  {
    const std::lock_guard lock(ledger.mutex);
    EXPECT_TRUE(ledger.live.empty()) << ledger.live.size() << " block(s) not given back";
    EXPECT_EQ(ledger.allocations, ledger.frees);
    EXPECT_GT(ledger.allocations, 40 * 5);
    EXPECT_EQ(ledger.foreignFrees, 0);
    EXPECT_EQ(ledger.mismatchedFrees, 0);
    EXPECT_EQ(ledger.misaligned, 0);
  }
  EXPECT_EQ(runtimeBlocksHeld(), 0u);
  ASSERT_TRUE(install({}));  // the default again, now that nothing is held
  EXPECT_EQ(currentAllocator().allocate, nullptr);
}

// A block the runtime got from the default allocator is never given to a later one: the
// change is refused until it is freed.
TEST(AllocatorHook, NeverHandsOneAllocatorsBlocksToAnother) {
  ASSERT_EQ(runtimeBlocksHeld(), 0u);
  Ledger ledger;
  {
    Scene before;  // default allocator
    Diagnostics d;
    EXPECT_FALSE(setAllocator(ledger.hooks(), d));
    EXPECT_NE(d.format().find("block(s)"), std::string::npos) << d.format();
  }
  EXPECT_EQ(ledger.allocationCount(), 0);
  // One function without the other is refused too.
  Diagnostics half;
  EXPECT_FALSE(setAllocator({&Ledger::allocate, nullptr, &ledger}, half));
  EXPECT_NE(half.format().find("both"), std::string::npos) << half.format();
  EXPECT_EQ(currentAllocator().allocate, nullptr);
}

// An allocator out of memory: the command fails as with std::bad_alloc, nothing leaks.
TEST(AllocatorHook, AnAllocatorOutOfMemoryFailsTheCommandCleanly) {
  ASSERT_EQ(runtimeBlocksHeld(), 0u);
  Ledger ledger;
  ASSERT_TRUE(install(ledger.hooks()));
  {
    Scene scene;
    ledger.failNext = true;
    EXPECT_THROW(scene.addCharacter("c", marionette::test::makeSyntheticRig()), std::bad_alloc);
    EXPECT_EQ(scene.characters().size(), 0u);
    EXPECT_TRUE(scene.addCharacter("d", marionette::test::makeSyntheticRig()));
  }
  {
    const std::lock_guard lock(ledger.mutex);
    EXPECT_TRUE(ledger.live.empty());
    EXPECT_EQ(ledger.foreignFrees, 0);
  }
  ASSERT_TRUE(install({}));
}
