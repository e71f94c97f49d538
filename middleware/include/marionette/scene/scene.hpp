// Scene: many characters on one monotonic clock. No process-wide state: several
// scenes may coexist. update(dt) is deterministic: the same calls give
// bit-identical transform buffers.
#pragma once
#include <memory>
#include <string_view>
#include <vector>

#include "marionette/scene/character.hpp"
#include "marionette/scene/listener.hpp"

namespace marionette {

class Scene {
 public:
  Scene() = default;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  ~Scene();

  // Adds a character; names must be unique (returns nullptr and logs otherwise).
  Character* addCharacter(std::string name, std::shared_ptr<const Rig> rig);
  bool removeCharacter(std::string_view name);
  [[nodiscard]] Character* findCharacter(std::string_view name) noexcept;
  [[nodiscard]] const std::vector<std::unique_ptr<Character>>& characters() const noexcept { return characters_; }

  // Listeners are not owned. They are called until removed, never from ~Scene
  // (destroying a scene sends no onCharacterRemoved), so a listener may die
  // before the scene as long as it is not used after its own destruction.
  void addListener(SceneListener* listener);
  void removeListener(SceneListener* listener);

  // Advances the clock by dt seconds and updates every character. A negative or
  // non-finite dt is rejected with a warning (the frame is not advanced); dt = 0
  // re-evaluates poses without moving time.
  void update(double dt) noexcept;
  [[nodiscard]] double time() const noexcept { return time_; }
  [[nodiscard]] std::uint64_t frame() const noexcept { return frame_; }

  // Per-character wall-clock timing in CharacterStats (costs two clock reads each).
  void setStatsEnabled(bool on) noexcept { stats_ = on; }
  [[nodiscard]] bool statsEnabled() const noexcept { return stats_; }

  // Listener fan-out (used by characters and, later, behavior realizers).
  void log(LogLevel level, std::string_view message) const;
  template <class F>
  void forEachListener(F&& f) const {
    for (SceneListener* l : listeners_) f(*l);
  }

 private:
  std::vector<std::unique_ptr<Character>> characters_;
  std::vector<SceneListener*> listeners_;
  FrameScratch scratch_;  // shared by the characters' blends, sized to the largest skeleton
  double time_ = 0.0;
  std::uint64_t frame_ = 0;
  bool stats_ = false;
};

}  // namespace marionette
