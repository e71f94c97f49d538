// What the C API's opaque handles are, and the guard every entry point runs in:
// no C++ exception crosses the C boundary; each failure leaves a status and a
// message on the scene (or, without a scene, on the calling thread).
#pragma once
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bridge/palette_binding.hpp"
#include "marionette/marionette.h"
#include "marionette/scene/scene.hpp"
#include "marionette/scene/scene_file.hpp"
#ifdef MARIONETTE_C_HAS_BML
#include "marionette/bml/realizer.hpp"
#endif

struct mn_character {
  mn_scene* owner = nullptr;
  marionette::Character* character = nullptr;
  marionette::bridge::PaletteBinding palette;  // identity, bound once
};

// Forwards the scene's listener calls to the C callbacks.
class CallbackForwarder final : public marionette::SceneListener {
 public:
  explicit CallbackForwarder(mn_scene& owner) : owner_(owner) {}
  void onViseme(const marionette::Character& character, std::string_view viseme, float weight, double time) override;
  void onLog(marionette::LogLevel level, std::string_view message) override;

 private:
  mn_scene& owner_;
  std::string text_;  // NUL-terminated copies of string views, reused (no allocation once grown)
};

struct mn_scene {
  mn_scene();
  ~mn_scene();

  marionette::Scene scene;
#ifdef MARIONETTE_C_HAS_BML
  std::unique_ptr<marionette::bml::Realizer> realizer;  // after `scene`: destroyed first
#endif
  CallbackForwarder forwarder{*this};
  std::vector<std::unique_ptr<mn_character>> handles;  // one per scene character, in scene order
  std::vector<marionette::TimedFile> pendingBml;       // scene files' "bml" lists, sent by update
  std::size_t nextBml = 0;
  mutable std::string lastError;  // set by failing calls, const ones included

  mn_feedback_fn feedbackFn = nullptr;
  void* feedbackUser = nullptr;
  mn_viseme_fn visemeFn = nullptr;
  void* visemeUser = nullptr;
  mn_log_fn logFn = nullptr;
  void* logUser = nullptr;

  // Handles for characters the scene gained (added or loaded from a file).
  void syncHandles();
};

namespace marionette::capi {

// Records a failure: on the scene when there is one, else on the thread.
mn_status fail(const mn_scene* scene, mn_status status, std::string_view message) noexcept;

// Runs `body` (returning mn_status), turning any exception into a status and message.
template <class Body>
mn_status guarded(const mn_scene* scene, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(scene, MN_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(scene, MN_ERROR_INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(scene, MN_ERROR_INTERNAL, "internal error: unknown exception");
  }
}

}  // namespace marionette::capi
