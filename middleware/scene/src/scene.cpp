#include "marionette/scene/scene.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include "character_state.hpp"
#include "frame_scratch.hpp"
#include "worker_pool.hpp"

namespace marionette {

namespace {
constexpr int kMaxThreads = 64;
// Characters taken at a time from the shared index: large enough that the atomic
// increment is lost in the work (16 RobotExpressive updates take ~25 us), small
// enough to balance a noisy machine. Scenes of one chunk run on the caller alone.
constexpr std::size_t kChunk = Scene::kCharactersPerChunk;  // the parallel-for hook's chunks too
}  // namespace

struct Scene::Parallel : RuntimeAllocated {
  // One scratch per worker (the caller uses Scene::scratch_), each reserved to
  // the largest skeleton, so that no two threads blend through the same memory.
  RuntimeVector<std::unique_ptr<FrameScratch>> scratch;
  std::atomic<std::size_t> next{0};  // first character of the next chunk to take
  double dt = 0.0;
  detail::WorkerPool pool;  // declared last: its workers are joined first
};

// No listener calls here: listeners are often declared after the scene and so
// destroyed before it (UBSan caught exactly that in the tests). parallel_'s
// destructor joins the (idle) workers.
Scene::Scene() : scratch_(std::make_unique<FrameScratch>()) {}
Scene::~Scene() = default;

int Scene::threadCount() const noexcept { return parallel_ ? parallel_->pool.participants() : 1; }

void Scene::setThreadCount(int n) {
  if (n == 0) n = static_cast<int>(std::thread::hardware_concurrency());  // 0 when unknown: clamped to 1
  n = std::clamp(n, 1, kMaxThreads);
  threadsWanted_ = n;
  if (parallelFor_) n = 1;  // the engine's hook runs the chunks: no worker; the count waits for its removal
  if (n == threadCount()) return;
  parallel_.reset();
  if (n == 1) return;
  auto p = std::make_unique<Parallel>();
  for (int k = 1; k < n; ++k) {
    p->scratch.push_back(std::make_unique<FrameScratch>());
    p->scratch.back()->reserve(scratch_->pose.size());
  }
  const int started = p->pool.resize(n);
  if (started < n)
    log(LogLevel::Warning, "setThreadCount: the system started only " + std::to_string(started) + " of " +
                               std::to_string(n) + " threads; updating with " + std::to_string(started));
  if (started > 1) parallel_ = std::move(p);
}

Character* Scene::addCharacter(std::string name, std::shared_ptr<const Rig> rig) {
  if (!rig) {
    log(LogLevel::Error, "addCharacter: no rig given");
    return nullptr;
  }
  if (findCharacter(name)) {
    log(LogLevel::Error, "addCharacter: a character of that name exists already");
    return nullptr;
  }
  characters_.push_back(std::make_unique<Character>(std::move(name), std::move(rig)));
  Character* c = characters_.back().get();
  c->state_->scene_ = this;
  c->state_->clock_ = time_;
  // Every thread's scratch fits every character; between updates a character
  // points at the caller's, which its command-time calls (play) use.
  scratch_->reserve(c->skeleton().jointCount());
  if (parallel_)
    for (auto& s : parallel_->scratch) s->reserve(c->skeleton().jointCount());
  if (parallelFor_) reserveChunkScratch();
  c->state_->scratch_ = scratch_.get();
  c->state_->startIdleLife();
  forEachListener([&](SceneListener& l) { l.onCharacterCreated(*c); });
  return c;
}

bool Scene::removeCharacter(std::string_view name) {
  auto it = std::find_if(characters_.begin(), characters_.end(), [&](const auto& c) { return c->name() == name; });
  if (it == characters_.end()) return false;
  forEachListener([&](SceneListener& l) { l.onCharacterRemoved(**it); });
  characters_.erase(it);
  return true;
}

bool Scene::setObject(std::string name, const glm::vec3& position) {
  if (name.empty() || !std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z)) {
    log(LogLevel::Error, "setObject: an object needs a name and a finite position ('" + name + "' was not set)");
    return false;
  }
  for (auto& [n, p] : objects_)
    if (n == name) {
      p = position;
      return true;
    }
  objects_.emplace_back(std::move(name), position);
  return true;
}

bool Scene::removeObject(std::string_view name) {
  const auto it = std::find_if(objects_.begin(), objects_.end(), [&](const auto& o) { return o.first == name; });
  if (it == objects_.end()) return false;
  objects_.erase(it);
  return true;
}

std::optional<glm::vec3> Scene::findObject(std::string_view name) const noexcept {
  for (const auto& [n, p] : objects_)
    if (n == name) return p;
  return std::nullopt;
}

Character* Scene::findCharacter(std::string_view name) noexcept {
  for (auto& c : characters_)
    if (c->name() == name) return c.get();
  return nullptr;
}

void Scene::addListener(SceneListener* listener) {
  if (listener && std::find(listeners_.begin(), listeners_.end(), listener) == listeners_.end())
    listeners_.push_back(listener);
}

void Scene::removeListener(SceneListener* listener) {
  listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

void Scene::log(LogLevel level, std::string_view message) const {
  forEachListener([&](SceneListener& l) { l.onLog(level, message); });
}

void Scene::update(double dt) noexcept {
  if (!std::isfinite(dt) || dt < 0.0 || dt > kMaxUpdateSeconds) {
    log(LogLevel::Warning,
        "Scene::update: dt must be finite, >= 0 and at most 3600 s (Scene::kMaxUpdateSeconds); the clock did not advance");
    return;
  }
  time_ += dt;
  ++frame_;
  // Serial: reads other characters' last frame. After it, a character's update
  // reads only itself, so any order and any thread give the same result.
  for (auto& c : characters_) c->state_->resolveExternalTargets();
  if (parallelFor_ && characters_.size() > kChunk) {
    updateHooked(dt);
  } else if (parallel_ && characters_.size() > kChunk) {
    parallel_->next.store(0, std::memory_order_relaxed);  // published by the pool's mutex
    parallel_->dt = dt;
    lockListeners_ = true;
    parallel_->pool.run(&Scene::updateChunks, this);
    lockListeners_ = false;
  } else {
    for (auto& c : characters_) updateCharacter(*c, *scratch_, dt);
  }
}

void Scene::updateChunks(void* scene, int participant) noexcept {
  Scene& s = *static_cast<Scene*>(scene);
  Parallel& p = *s.parallel_;
  FrameScratch& scratch = participant == 0 ? *s.scratch_ : *p.scratch[static_cast<std::size_t>(participant - 1)];
  // Copies: `next` shares a cache line with these and bounces between threads.
  const std::size_t n = s.characters_.size();
  const double dt = p.dt;
  for (;;) {
    const std::size_t begin = p.next.fetch_add(kChunk, std::memory_order_relaxed);
    if (begin >= n) return;
    const std::size_t end = std::min(n, begin + kChunk);
    for (std::size_t i = begin; i < end; ++i) s.updateCharacter(*s.characters_[i], scratch, dt);
  }
}

void Scene::updateCharacter(Character& c, FrameScratch& scratch, double dt) noexcept {
  c.state_->scratch_ = &scratch;
  if (stats_) {
    const auto start = std::chrono::steady_clock::now();
    c.update(dt);
    c.state_->stats_.lastUpdateMicros =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  } else {
    c.update(dt);
  }
  c.state_->scratch_ = scratch_.get();  // back to the caller's: command-time calls find a reserved scratch
}

}  // namespace marionette
