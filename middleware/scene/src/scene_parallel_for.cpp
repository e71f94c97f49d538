// Scene::setParallelFor: the characters' chunks run on an engine's job system instead of
// the scene's pool (scene.hpp states the contract). Chunk i is characters
// [16 i, 16 i + 16), each chunk with scratch of its own, so that neither the order nor
// the threads the engine picks can change a result.
#include <algorithm>
#include <atomic>
#include <cfenv>

#include "character_state.hpp"
#include "frame_scratch.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette {
namespace {

// One update's context for the tasks, on the updating thread's stack.
struct HookedFrame {
  Scene* scene = nullptr;
  double dt = 0.0;
  std::size_t chunks = 0;
  std::fenv_t env{};                // the updating thread's: every chunk runs under it
  std::atomic<std::size_t> done{0};  // chunks run, to catch a hook that returns early
};

constexpr std::size_t kChunk = Scene::kCharactersPerChunk;

std::size_t chunksFor(std::size_t characters) noexcept { return (characters + kChunk - 1) / kChunk; }

}  // namespace

void Scene::setParallelFor(ParallelFor hook, void* user) {
  if (hook) reserveChunkScratch();  // first: out of memory leaves the scene as it was
  parallelFor_ = hook;
  parallelForUser_ = hook ? user : nullptr;
  if (!hook) {
    chunkScratch_.clear();  // the pool's threads have scratch of their own
    chunkScratch_.shrink_to_fit();
  }
  // With a hook: joins the scene's workers (the engine's threads replace them); without:
  // the scene's own threads again, as many as setThreadCount last asked for.
  setThreadCount(threadsWanted_);
}

void Scene::reserveChunkScratch() {
  const std::size_t chunks = chunksFor(characters_.size());
  if (chunkScratch_.size() < chunks) chunkScratch_.reserve(chunks);
  while (chunkScratch_.size() < chunks) chunkScratch_.push_back(std::make_unique<FrameScratch>());
  // Every chunk's scratch fits the largest skeleton the scene has had (scratch_ grows to it).
  for (auto& s : chunkScratch_) s->reserve(scratch_->pose.size());
}

void Scene::updateHooked(double dt) noexcept {
  HookedFrame frame;
  frame.scene = this;
  frame.dt = dt;
  frame.chunks = chunksFor(characters_.size());
  if (chunkScratch_.size() < frame.chunks) {  // addCharacter ran out of memory for it: on the caller
    for (auto& c : characters_) updateCharacter(*c, *scratch_, dt);
    return;
  }
  std::fegetenv(&frame.env);
  lockListeners_ = true;  // listener calls from the engine's threads are serialized
  parallelFor_(parallelForUser_, &Scene::updateHookedChunk, &frame, static_cast<int>(frame.chunks));
  lockListeners_ = false;
  if (frame.done.load(std::memory_order_acquire) != frame.chunks)
    log(LogLevel::Error,
        "Scene::update: the parallel-for hook did not run every chunk once before returning; characters of a "
        "chunk not run kept their last frame (setParallelFor: call task(context, i) once for each i, then return)");
}

void Scene::updateHookedChunk(void* context, int chunk) noexcept {
  HookedFrame& frame = *static_cast<HookedFrame*>(context);
  Scene& s = *frame.scene;
  if (chunk < 0 || static_cast<std::size_t>(chunk) >= frame.chunks) return;  // not a chunk of this update
  // The engine's thread may round differently (its own MXCSR or rounding mode): run this
  // chunk as the updating thread would, then give the thread its own environment back.
  std::fenv_t own;
  std::fegetenv(&own);
  std::fesetenv(&frame.env);
  FrameScratch& scratch = *s.chunkScratch_[static_cast<std::size_t>(chunk)];
  const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
  const std::size_t end = std::min(s.characters_.size(), begin + kChunk);
  for (std::size_t i = begin; i < end; ++i) s.updateCharacter(*s.characters_[i], scratch, frame.dt);
  std::fesetenv(&own);
  frame.done.fetch_add(1, std::memory_order_release);
}

}  // namespace marionette
