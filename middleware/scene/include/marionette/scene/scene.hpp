// Scene: many characters on one monotonic clock. No process-wide state: several
// scenes may coexist. update(dt) is deterministic: the same calls give
// bit-identical transform buffers, whatever threadCount() is.
//
// Threads. A scene is used from one thread at a time. With setThreadCount(n > 1),
// update() updates the characters on that thread and n - 1 worker threads of the
// scene's own. Listener callbacks that characters make during update() (for
// example onCharacterChanged when a clip fades out, onLog) may then arrive on a
// worker thread, one at a time (the scene serializes them; a callback may call
// log() again) and in an unspecified order. Until update() returns, such a
// callback may read the character it is about but must not read other characters
// or call anything else that changes the scene (addListener, update, ...).
// Callbacks outside update() stay on the calling thread. With setParallelFor the
// engine's job system runs the characters instead, under the same rules.
#pragma once
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "marionette/core/allocator.hpp"
#include "marionette/scene/character.hpp"
#include "marionette/scene/listener.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

struct FrameScratch;  // scene/src/frame_scratch.hpp

// Made with new, the object comes from the runtime allocator (core/allocator.hpp).
class Scene : public RuntimeAllocated {
 public:
  Scene();  // out of line: Parallel is complete only in scene.cpp
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  ~Scene();

  // Adds a character; names must be unique (returns nullptr and logs otherwise).
  Character* addCharacter(std::string name, std::shared_ptr<const Rig> rig);
  bool removeCharacter(std::string_view name);
  [[nodiscard]] Character* findCharacter(std::string_view name) noexcept;
  [[nodiscard]] const std::vector<std::unique_ptr<Character>>& characters() const noexcept { return characters_; }

  // Named places that behaviors aim at and walk to as they do at characters (SmartBody's
  // pawns, props, the viewer): a gaze, pointing or locomotion target naming one finds it
  // (a character of the same name comes first). "camera" is the viewer: the AR renderer
  // moves it with the tracked camera every frame. Command time (between updates); a target
  // is read again before every frame, so a moved object is followed. setObject replaces an
  // object of that name; an empty name or a position that is not finite is refused (false,
  // logged).
  bool setObject(std::string name, const glm::vec3& position);
  bool removeObject(std::string_view name);
  [[nodiscard]] std::optional<glm::vec3> findObject(std::string_view name) const noexcept;
  [[nodiscard]] const std::vector<std::pair<std::string, glm::vec3>>& objects() const noexcept { return objects_; }

  // Listeners are not owned. They are called until removed, never from ~Scene
  // (destroying a scene sends no onCharacterRemoved), so a listener may die
  // before the scene as long as it is not used after its own destruction.
  void addListener(SceneListener* listener);
  void removeListener(SceneListener* listener);

  // The longest step update() takes: an hour. Characters keep their clocks in float
  // seconds, where a larger step loses the frame's precision and, past 3.4e38, becomes
  // infinite (then NaN in every phase).
  static constexpr double kMaxUpdateSeconds = 3600.0;

  // Advances the clock by dt seconds and updates every character. A negative,
  // non-finite or larger than kMaxUpdateSeconds dt is rejected with a warning (the
  // frame is not advanced); dt = 0 re-evaluates poses without moving time.
  void update(double dt) noexcept;
  [[nodiscard]] double time() const noexcept { return time_; }
  [[nodiscard]] std::uint64_t frame() const noexcept { return frame_; }

  // Threads that update() uses, the calling one included: 1 (the default) updates
  // every character on the caller; 0 means std::thread::hardware_concurrency();
  // clamped to [1, 64]. Command time: starts or joins worker threads (never per
  // frame); call it between updates. Scenes of at most 16 characters update on the
  // caller alone. Fewer threads than asked (with a warning) if the system refuses one.
  void setThreadCount(int n);
  [[nodiscard]] int threadCount() const noexcept;

  // The engine's job system instead of the scene's threads (as Jolt's JobSystem):
  // update() splits the characters into chunks of kCharactersPerChunk consecutive ones
  // and calls parallelFor(user, task, context, chunkCount) once, on the updating thread.
  // The hook must call task(context, i) exactly once for every i in [0, chunkCount),
  // in any order, on any threads (the updating one included), concurrently or not, and
  // return only when every call has returned. Each chunk blends in scratch of its own
  // and runs under the updating thread's floating-point environment (restored after),
  // so the buffers are bit-identical to one thread and to the scene's own pool. A task
  // never throws, allocates nothing and takes about 16 character updates (~25 us for
  // RobotExpressive). Listener calls made meanwhile are serialized as with the pool and
  // may arrive on the engine's threads. The hook must not call back into the scene.
  // Scenes of at most one chunk update on the caller without calling it; a hook that
  // returns with chunks not run is reported (an error log), and their characters keep
  // their last frame. Command time (between updates): while a hook is set the scene owns
  // no worker thread (threadCount() is 1, setThreadCount's count waits); nullptr goes
  // back to the threads of setThreadCount. Allocates one scratch per chunk (~100 bytes
  // per joint of the largest skeleton) here and in addCharacter, never per frame.
  using ParallelTask = void (*)(void* context, int chunk);
  using ParallelFor = void (*)(void* user, ParallelTask task, void* context, int chunkCount);
  static constexpr std::size_t kCharactersPerChunk = 16;
  void setParallelFor(ParallelFor hook, void* user);
  [[nodiscard]] ParallelFor parallelFor() const noexcept { return parallelFor_; }

  // Per-character wall-clock timing in CharacterStats (costs two clock reads each).
  void setStatsEnabled(bool on) noexcept { stats_ = on; }
  [[nodiscard]] bool statsEnabled() const noexcept { return stats_; }

  // The scene's speech: backends, utterance cache, WAV output (speech_service.hpp).
  [[nodiscard]] speech::SpeechService& speech() noexcept { return speech_; }

  // Listener fan-out (used by characters and, later, behavior realizers). During
  // a parallel update the calls are serialized (see the threads note above).
  void log(LogLevel level, std::string_view message) const;
  template <class F>
  void forEachListener(F&& f) const {
    if (lockListeners_) {
      std::lock_guard lock(listenerMutex_);
      for (SceneListener* l : listeners_) f(*l);
    } else {
      for (SceneListener* l : listeners_) f(*l);
    }
  }

 private:
  struct Parallel;  // worker pool and per-worker scratch (scene.cpp)
  static void updateChunks(void* scene, int participant) noexcept;
  // The parallel-for hook's side (scene_parallel_for.cpp).
  static void updateHookedChunk(void* frame, int chunk) noexcept;
  void updateHooked(double dt) noexcept;
  void reserveChunkScratch();
  void updateCharacter(Character& c, FrameScratch& scratch, double dt) noexcept;

  std::vector<std::unique_ptr<Character>> characters_;
  std::vector<std::pair<std::string, glm::vec3>> objects_;  // few: a linear search
  std::vector<SceneListener*> listeners_;
  speech::SpeechService speech_;
  std::unique_ptr<FrameScratch> scratch_;  // the calling thread's blend scratch, sized to the largest skeleton
  std::unique_ptr<Parallel> parallel_;  // null while threadCount() == 1
  int threadsWanted_ = 1;               // setThreadCount's, kept while a hook runs the chunks
  ParallelFor parallelFor_ = nullptr;   // the engine's hook, or null
  void* parallelForUser_ = nullptr;
  // One scratch per chunk, not per thread: the scene does not know the engine's threads, only
  // the chunk index it is given. Grows with the characters while a hook is set.
  RuntimeVector<std::unique_ptr<FrameScratch>> chunkScratch_;
  // Recursive: a callback serialized by it may call log() on the same thread.
  mutable std::recursive_mutex listenerMutex_;
  bool lockListeners_ = false;  // true only while update() runs on several threads
  double time_ = 0.0;
  std::uint64_t frame_ = 0;
  bool stats_ = false;
};

}  // namespace marionette
