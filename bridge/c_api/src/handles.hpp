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
#include "marionette/io/import.hpp"
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
// Handles' memory comes from the runtime allocator (mn_set_allocator; core/allocator.hpp).
void* allocateHandle(std::size_t bytes);                // registers it as live
void freeHandle(void* handle, std::size_t bytes) noexcept;  // no longer live; freed kQuarantine frees later
// For mn_set_allocator: how many handles are live; when none is, the quarantined memory is
// freed now (to the allocator that gave it), so that nothing of the old allocator is held.
[[nodiscard]] std::size_t releaseQuarantineIfNoneLive() noexcept;
[[nodiscard]] bool isLive(const void* handle) noexcept;
// Why a handle was refused, for a message "FUNCTION: NAME" + notLive(handle).
[[nodiscard]] const char* notLive(const void* handle) noexcept;

// Why an option struct from the caller is refused: its first field, struct_size, is not this
// library's size of it (a header of another version, or a struct not from ..._default()).
// Checked before the struct is read, so that a smaller one is never read past its end.
[[nodiscard]] std::string badStructSize(const char* call, const char* type, std::size_t given, std::size_t expected);

// The folder of this library's file (found by dladdr; "" when unknown): where the installed
// joint maps and profiles are looked for (share/marionette/ beside its parent).
[[nodiscard]] std::string libraryFolder();

// The C play options as the C++ ones (checked by the caller: finite, sizes).
[[nodiscard]] inline marionette::PlayOptions toPlayOptions(const mn_play_options& o) {
  marionette::PlayOptions p;
  p.weight = o.weight;
  p.speed = o.speed;
  p.wrap = o.loop ? marionette::WrapMode::Loop : marionette::WrapMode::Clamp;
  p.startTime = o.start_time;
  p.fadeIn = o.fade_in;
  p.additive = o.additive != 0;
  p.rootMotion = o.root_motion != 0;
  return p;
}

// Handles are allocated through the registry.
struct Registered {
  static void* operator new(std::size_t bytes) { return allocateHandle(bytes); }
  static void operator delete(void* handle, std::size_t bytes) noexcept { freeHandle(handle, bytes); }
};

}  // namespace marionette::capi

struct mn_character : marionette::capi::Registered {
  mn_scene* owner = nullptr;
  marionette::Character* character = nullptr;
  // Identity, bound once per skeleton and shared by the characters of one rig (mn_scene::identityPalette).
  std::shared_ptr<const marionette::bridge::PaletteBinding> palette;
  // What the character was imported from (skeleton, humanoid map, file name; no meshes):
  // the rig keeps only what the runtime needs, a joint map is guessed from the asset.
  std::shared_ptr<const marionette::Asset> asset;
};

// A loaded character file (mn_asset_load_*): the rig its characters share (skeleton, clips,
// profile) and the imported asset without meshes (skeleton, humanoid map, file name), from
// which joint maps are guessed. Characters hold both; releasing the handle drops only its own.
struct mn_asset : marionette::capi::Registered {
  std::shared_ptr<const marionette::Rig> rig;
  std::shared_ptr<const marionette::Asset> asset;
  std::string warnings;  // the import's and the profile's, one per line (mn_asset_report)
};

namespace marionette::capi {
// Loads a character file for mn_asset_load_* and mn_scene_add_character: imported once
// without meshes, its rig made with the profile at `profilePath` (read through the options'
// reader), else the installed profile of a known asset, else the guess. `bytes`: the file's
// content in memory (`path` names it), or null to read `path`. Warnings go to `warnings`,
// one line each. A failure is recorded on `scene` (or the thread) and its status returned.
mn_status loadAsset(const mn_scene* scene, const char* call, const std::string& path, const std::string_view* bytes,
                    const marionette::ImportOptions& options, const char* profilePath, mn_asset& out,
                    std::string& warnings);
}  // namespace marionette::capi

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
  void onAnimationEvent(const marionette::Character& character, const marionette::AnimationEvent& event) override;  // c_events.cpp
  void onAudio(const marionette::Character& character, std::string_view behaviorId, const marionette::speech::AudioClip& clip,
               std::string_view file, double sceneStart) override;  // c_audio.cpp
  void onAudioStopped(const marionette::Character& character, std::string_view behaviorId, double time) override;
  void reserveEventText();  // c_events.cpp: at mn_scene_set_event_callback, so that events allocate nothing

 private:
  mn_scene& owner_;
  std::string text_, text2_, text3_;  // NUL-terminated copies of string views, reused (no allocation once grown)
  std::string eventName_, eventClip_;  // the same for animation events
};

namespace marionette::speech {
class RecordedSpeech;
}

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
  // What mn_scene_add_character loaded, by file and profile: a later character of the same
  // pair shares it while a character made from it lives (weak: removing the last frees it).
  struct LoadedFile {
    std::weak_ptr<const marionette::Rig> rig;
    std::weak_ptr<const marionette::Asset> asset;
  };
  std::map<std::string, LoadedFile, std::less<>> loadedFiles;
  std::shared_ptr<marionette::speech::RecordedSpeech> recordedLines;  // mn_scene_add_speech_line's (c_speech_lines.cpp)
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
  mn_animation_event_fn eventFn = nullptr;  // c_events.cpp
  void* eventUser = nullptr;
  mn_audio_fn audioFn = nullptr;  // c_audio.cpp
  void* audioUser = nullptr;

  // Handles for characters the scene gained (added or loaded from a file).
  void syncHandles();
  // The identity palette binding of a rig's skeleton, made once for all its characters (a
  // binding is about 1.5 KiB for a 43-joint skeleton: per character it would be a tenth of
  // each character's memory). Checked by joint names, so a rig freed and another made at
  // its address never shares a stale binding.
  std::shared_ptr<const marionette::bridge::PaletteBinding> identityPalette(const marionette::Character& c);
  std::map<const marionette::Rig*, std::shared_ptr<const marionette::bridge::PaletteBinding>> identityPalettes;
};

namespace marionette::capi {

// The engine's read function (mn_read_file_fn) as a FileReader; empty for NULL (the disk). c_asset.cpp.
[[nodiscard]] marionette::FileReader engineReader(mn_read_file_fn fn, void* user);

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

// A call on `scene` that may reach its callbacks (or the engine's read function). From inside
// a callback of the same scene the call is refused; a mn_scene_destroy from a callback waits
// for its end.
template <class Body>
mn_status inCall(mn_scene* scene, const char* what, Body&& body) {
  if (scene->callDepth > 0)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, std::string(what) + ": called from a callback of the same scene");
  ++scene->callDepth;
  const mn_status status = guarded(scene, body);
  if (--scene->callDepth == 0 && scene->destroyRequested) delete scene;
  return status;
}

}  // namespace marionette::capi
