#include "marionette/scene/scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace marionette {

// No listener calls here: listeners are often declared after the scene and so
// destroyed before it (UBSan caught exactly that in the tests).
Scene::~Scene() = default;

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
  c->scene_ = this;
  c->clock_ = time_;
  scratch_.reserve(c->skeleton().jointCount());
  c->scratch_ = &scratch_;
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
  if (!std::isfinite(dt) || dt < 0.0) {
    log(LogLevel::Warning, "Scene::update: negative or non-finite dt rejected; the clock did not advance");
    return;
  }
  time_ += dt;
  ++frame_;
  for (auto& c : characters_) c->resolveExternalTargets();
  for (auto& c : characters_) {
    if (stats_) {
      const auto start = std::chrono::steady_clock::now();
      c->update(dt);
      c->stats_.lastUpdateMicros =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    } else {
      c->update(dt);
    }
  }
}

}  // namespace marionette
