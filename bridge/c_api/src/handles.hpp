// What the C API's opaque handles are, and the guard every entry point runs in:
// no C++ exception crosses the C boundary; each failure leaves a status and a
// message on the scene (or, without a scene, on the calling thread).
#pragma once
#include <map>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bridge/morph_binding.hpp"
#include "marionette/bridge/palette_binding.hpp"
#include "marionette/marionette.h"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#ifdef MARIONETTE_C_HAS_BML
#include "marionette/bml/realizer.hpp"
#endif

namespace marionette::capi {

// Every live handle's address, so that each entry point can refuse a destroyed (or
// foreign) one. The memory of a destroyed handle is held back (kQuarantine handles)
// before it is freed, so that a new handle does not soon take a stale one's address.
inline constexpr std::size_t kQuarantine = 256;
void* allocateHandle(std::size_t bytes);  // registers it as live
void freeHandle(void* handle) noexcept;   // no longer live; freed kQuarantine frees later
[[nodiscard]] bool isLive(const void* handle) noexcept;
// Why a handle was refused, for a message "FUNCTION: NAME" + notLive(handle).
[[nodiscard]] const char* notLive(const void* handle) noexcept;

// Why an option struct from the caller is refused: its first field, struct_size, is not this
// library's size of it (a header of another version, or a struct not from ..._default()).
// Checked before the struct is read, so that a smaller one is never read past its end.
[[nodiscard]] std::string badStructSize(const char* call, const char* type, std::size_t given, std::size_t expected);

// Handles are allocated through the registry.
struct Registered {
  static void* operator new(std::size_t bytes) { return allocateHandle(bytes); }
  static void operator delete(void* handle) noexcept { freeHandle(handle); }
};

}  // namespace marionette::capi

struct mn_character : marionette::capi::Registered {
  mn_scene* owner = nullptr;
  marionette::Character* character = nullptr;
  marionette::bridge::PaletteBinding palette;  // identity, bound once
  // What the character was imported from (skeleton, humanoid map, file name; no meshes):
  // the rig keeps only what the runtime needs, a joint map is guessed from the asset.
  std::shared_ptr<const marionette::Asset> asset;
};

// A character bound to an engine's bone and morph order (mn_binding_create). It names
// its character, which it checks is live on every call.
struct mn_binding : marionette::capi::Registered {
  mn_character* character = nullptr;
  marionette::bridge::PaletteBinding palette;
  marionette::bridge::MorphBinding morphs;
  std::string report;
};

// Forwards the scene's listener calls to the C callbacks.
class CallbackForwarder final : public marionette::SceneListener {
 public:
  explicit CallbackForwarder(mn_scene& owner) : owner_(owner) {}
  void onViseme(const marionette::Character& character, std::string_view viseme, float weight, double time) override;
  void onLog(marionette::LogLevel level, std::string_view message) override;
  void onSpeech(const marionette::Character& character, std::string_view behaviorId,
                const marionette::speech::Utterance& utterance, std::string_view audioFile, double sceneStart) override;
  void onCharacterChanged(const marionette::Character& character, marionette::ChangeKind kind,
                          std::string_view what) override;

 private:
  mn_scene& owner_;
  std::string text_, text2_, text3_;  // NUL-terminated copies of string views, reused (no allocation once grown)
};

struct mn_scene : marionette::capi::Registered {
  mn_scene();
  ~mn_scene();

  int callDepth = 0;              // > 0 while mn_scene_update or mn_scene_send_bml runs (callbacks may come)
  bool destroyRequested = false;  // mn_scene_destroy from a callback: destroyed when that call returns

  marionette::Scene scene;
#ifdef MARIONETTE_C_HAS_BML
  std::unique_ptr<marionette::bml::Realizer> realizer;  // after `scene`: destroyed first
#endif
  CallbackForwarder forwarder{*this};
  std::vector<std::unique_ptr<mn_character>> handles;  // one per scene character, in scene order
  // The imported asset of each character by name, for its handle (mn_character::asset).
  std::map<std::string, std::shared_ptr<const marionette::Asset>, std::less<>> assets;
  std::vector<marionette::TimedFile> pendingBml;       // scene files' "bml" lists, sent by update
  std::size_t nextBml = 0;
  mutable std::string lastError;  // set by failing calls, const ones included

  mn_feedback_fn feedbackFn = nullptr;
  void* feedbackUser = nullptr;
  mn_viseme_fn visemeFn = nullptr;
  void* visemeUser = nullptr;
  mn_log_fn logFn = nullptr;
  void* logUser = nullptr;
  mn_speech_fn speechFn = nullptr;
  void* speechUser = nullptr;
  mn_clip_fn clipFn = nullptr;
  void* clipUser = nullptr;

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
