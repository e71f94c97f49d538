// The C API's scene functions (marionette.h): creation, loading, BML, update,
// callbacks, errors.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "handles.hpp"
#ifdef MARIONETTE_C_HAS_BML
#include "marionette/bml/timed_files.hpp"
#endif
#include "marionette/core/text_file.hpp"
#include "marionette/io/import.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/version.h"
#ifdef MARIONETTE_C_HAS_ESPEAK
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif

using marionette::capi::fail;
using marionette::capi::guarded;
using marionette::capi::inCall;
using marionette::capi::isLive;
using marionette::capi::notLive;


namespace {

thread_local std::string t_lastError;  // failures without a valid scene

// One callback of a scene: its function and user pointer (NULL function removes it).
template <class Fn>
mn_status setCallback(mn_scene* scene, const char* what, Fn mn_scene::*fnField, void* mn_scene::*userField, Fn fn,
                      void* user) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string(what) + ": scene" + notLive(scene));
  scene->*fnField = fn;
  scene->*userField = user;
  return MN_OK;
}

bool readable(const char* path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

// Warnings of a load that succeeded go to the log callback (one line each).
void logWarnings(const mn_scene& s, const marionette::Diagnostics& d) {
  for (const marionette::Diagnostic& item : d.items)
    if (item.severity != marionette::Severity::Error)
      s.scene.log(item.severity == marionette::Severity::Warning ? marionette::LogLevel::Warning
                                                                 : marionette::LogLevel::Info,
                  item.format());
}

// Adds a character sharing a loaded file's rig and asset (mn_asset or the scene's cache).
mn_status addCharacter(mn_scene& scene, const char* call, const char* name, const mn_asset& loaded, mn_character** out) {
  if (!scene.scene.addCharacter(name, loaded.rig))
    return fail(&scene, MN_ERROR_INTERNAL, std::string(call) + ": the scene refused '" + name + "'");
  scene.assets.insert_or_assign(name, loaded.asset);
  scene.syncHandles();
  if (out) *out = scene.handles.back().get();
  return MN_OK;
}

#ifdef MARIONETTE_C_HAS_BML
marionette::Diagnostic diagnostic(marionette::Severity severity, std::string file, std::string message, int line,
                                  int column) {
  return {severity, std::move(file), line, column, std::move(message)};
}

// The id attribute of the <bml> element, read naively, for naming a block whose XML
// is too broken to parse ("" when there is none to see).
std::string sniffBlockId(std::string_view text) {
  const std::size_t open = text.find("<bml");
  const std::size_t close = open == std::string_view::npos ? open : text.find('>', open);
  if (close == std::string_view::npos) return {};
  const std::string_view tag = text.substr(open, close - open);
  for (std::size_t at = tag.find("id="); at != std::string_view::npos; at = tag.find("id=", at + 3)) {
    if (at == 0 || (tag[at - 1] != ' ' && tag[at - 1] != '\t' && tag[at - 1] != '\n')) continue;  // not characterId
    const std::size_t q = at + 3;
    if (q >= tag.size() || (tag[q] != '\'' && tag[q] != '"')) return {};
    const std::size_t end = tag.find(tag[q], q + 1);
    return end == std::string_view::npos ? std::string() : std::string(tag.substr(q + 1, end - q - 1));
  }
  return {};
}

// "bml block 'id':line:col: error: TYPE: behavior 'b': message" (the block names the place).
std::string formatWarning(const std::string& blockId, const marionette::bml::Warning& w) {
  const std::string block = !w.blockId.empty() ? w.blockId : blockId;
  return diagnostic(w.fatal ? marionette::Severity::Error : marionette::Severity::Warning,
                    block.empty() ? "bml block (no id)" : "bml block '" + block + "'",
                    std::string(marionette::bml::toString(w.type)) + ": " +
                        (w.behaviorId.empty() ? "" : "behavior '" + w.behaviorId + "': ") + w.message,
                    w.line, w.column)
      .format();
}

void sendFeedback(mn_scene& s, const marionette::bml::Feedback& f) {
  if (!s.feedbackFn) return;
  static constexpr mn_feedback_kind kinds[] = {MN_FEEDBACK_PREDICTION, MN_FEEDBACK_BLOCK_PROGRESS,
                                               MN_FEEDBACK_SYNC_POINT, MN_FEEDBACK_WARNING, MN_FEEDBACK_EVENT};
  static_assert(std::size(kinds) == static_cast<std::size_t>(marionette::bml::Feedback::Kind::Event) + 1,
                "one C kind per feedback kind");
  const std::string message = f.kind == marionette::bml::Feedback::Kind::Warning ? formatWarning(f.blockId, f.warning)
                              : f.kind == marionette::bml::Feedback::Kind::Event ? f.message
                                                                                 : "";
  mn_feedback out{kinds[static_cast<int>(f.kind)], f.character.c_str(), f.blockId.c_str(), f.behaviorId.c_str(),
                  f.syncPoint.c_str(), message.c_str(), f.blockTime, f.sceneTime};
  s.feedbackFn(s.feedbackUser, &out);
}

// Sends the scene files' BML whose time falls before `until` (the end of the coming frame).
void sendDueBml(mn_scene& s, double until) {
  for (; s.nextBml < s.pendingBml.size() && s.pendingBml[s.nextBml].time <= until + 1e-9; ++s.nextBml) {
    const marionette::TimedFile& f = s.pendingBml[s.nextBml];
    std::string text = f.text.value_or(std::string());
    if (marionette::Diagnostics unread; !f.text && !marionette::readTextFile(f.path, text, unread, "cannot read the BML file")) {
      for (const marionette::Diagnostic& d : unread.items) s.scene.log(marionette::LogLevel::Error, d.format());
      continue;
    }
    marionette::bml::SchedulerOptions options;  // what the file names is beside it (<bmlt:audiofile>)
    options.fileDirectory = std::filesystem::path(f.path).parent_path().generic_string();
    s.realizer->perform(text, f.character, options, f.time);  // problems arrive as warning feedback
  }
}
#endif

}  // namespace

namespace marionette::capi {

mn_status fail(const mn_scene* scene, mn_status status, std::string_view message) noexcept {
  try {
    while (!message.empty() && message.back() == '\n') message.remove_suffix(1);  // Diagnostics end lines
    (scene ? scene->lastError : t_lastError).assign(message);
  } catch (...) {  // no memory for the message: the status still says what happened
  }
  return status;
}

}  // namespace marionette::capi

void CallbackForwarder::onViseme(const marionette::Character& character, std::string_view viseme, float weight,
                                 double time) {
  if (!owner_.visemeFn) return;
  text_.assign(viseme);
  const mn_viseme v{character.name().c_str(), text_.c_str(), weight, time};
  owner_.visemeFn(owner_.visemeUser, &v);
}

void CallbackForwarder::onLog(marionette::LogLevel level, std::string_view message) {
  if (!owner_.logFn) return;
  text_.assign(message);
  owner_.logFn(owner_.logUser, static_cast<mn_log_level>(level), text_.c_str());
}

void CallbackForwarder::onSpeech(const marionette::Character& character, std::string_view behaviorId,
                                 const marionette::speech::Utterance& utterance, std::string_view audioFile,
                                 double sceneStart) {
  if (!owner_.speechFn) return;
  text2_.assign(behaviorId);
  text3_.assign(audioFile);
  const mn_speech s{character.name().c_str(), text2_.c_str(),
                    utterance.audio.empty() ? nullptr : utterance.audio.data(), utterance.audio.size(),
                    utterance.sampleRate,       text3_.c_str(),
                    sceneStart,                 utterance.duration};
  owner_.speechFn(owner_.speechUser, &s);
}

void CallbackForwarder::onCharacterChanged(const marionette::Character& character, marionette::ChangeKind kind,
                                           std::string_view what) {
  if (!owner_.clipFn || kind == marionette::ChangeKind::Placement) return;
  text3_.assign(what);
  const mn_clip_event e{kind == marionette::ChangeKind::ClipStarted ? MN_CLIP_STARTED : MN_CLIP_STOPPED,
                        character.name().c_str(), text3_.c_str(), owner_.scene.time()};
  owner_.clipFn(owner_.clipUser, &e);
}

mn_scene::mn_scene() {
  scene.addListener(&forwarder);
#ifdef MARIONETTE_C_HAS_BML
  realizer = std::make_unique<marionette::bml::Realizer>(scene);
  realizer->addFeedbackListener([this](const marionette::bml::Feedback& f) { sendFeedback(*this, f); });
#endif
}

mn_scene::~mn_scene() { scene.removeListener(&forwarder); }

std::shared_ptr<const marionette::bridge::PaletteBinding> mn_scene::identityPalette(const marionette::Character& c) {
  auto& shared = identityPalettes[&c.rig()];
  const marionette::Skeleton& skeleton = c.skeleton();
  if (!shared || shared->slotCount() != skeleton.jointCount() || shared->report().byName != skeleton.names)
    shared = std::make_shared<const marionette::bridge::PaletteBinding>(skeleton);
  return shared;
}

void mn_scene::syncHandles() {
  const auto& characters = scene.characters();
  while (handles.size() < characters.size()) {
    auto h = std::make_unique<mn_character>();
    h->owner = this;
    h->character = characters[handles.size()].get();
    h->palette = identityPalette(*h->character);
    // The palette is made as the engine copies it (mn_character_palette, mn_binding_palette):
    // the same bits, 64 bytes a joint less per character.
    const marionette::Rig& rig = h->character->rig();
    h->character->transformBuffer().setSkinningStored(false, rig.skeleton().inverseBind, &rig.paletteBasis());
    if (const auto it = assets.find(h->character->name()); it != assets.end()) h->asset = it->second;
    handles.push_back(std::move(h));
  }
}

extern "C" {

const char* mn_status_name(mn_status status) {
  switch (status) {
    case MN_OK: return "MN_OK";
    case MN_ERROR_INVALID_ARGUMENT: return "MN_ERROR_INVALID_ARGUMENT";
    case MN_ERROR_NOT_FOUND: return "MN_ERROR_NOT_FOUND";
    case MN_ERROR_IO: return "MN_ERROR_IO";
    case MN_ERROR_LOAD: return "MN_ERROR_LOAD";
    case MN_ERROR_BML: return "MN_ERROR_BML";
    case MN_ERROR_UNSUPPORTED: return "MN_ERROR_UNSUPPORTED";
    case MN_ERROR_OUT_OF_MEMORY: return "MN_ERROR_OUT_OF_MEMORY";
    case MN_ERROR_INTERNAL: return "MN_ERROR_INTERNAL";
    default: break;  // any other int (the enum holds every int value)
  }
  return "MN_ERROR_UNKNOWN_STATUS";
}

const char* mn_version(void) { return MARIONETTE_VERSION_STRING; }

int mn_has_speech_synthesis(void) {
#ifdef MARIONETTE_C_HAS_ESPEAK
  return 1;
#else
  return 0;
#endif
}

mn_status mn_scene_create(mn_scene** out) {
  if (!out) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_scene_create: out is NULL");
  *out = nullptr;
  return guarded(nullptr, [&] {
    *out = new mn_scene();
#ifdef MARIONETTE_C_HAS_ESPEAK  // libmarionette_c_espeak: the same API, espeak-ng (GPL) linked in
    marionette::speech::useEspeak((*out)->scene.speech());
#endif
    return MN_OK;
  });
}

void mn_scene_destroy(mn_scene* scene) {
  if (!scene) return;
  if (!isLive(scene)) {  // a second destroy, or not a scene: recorded, nothing freed
    fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_scene_destroy: scene is not a live handle (destroyed already?)");
    return;
  }
  if (scene->callDepth > 0) {  // from one of its own callbacks: when that call returns
    scene->destroyRequested = true;
    return;
  }
  delete scene;
}

const char* mn_scene_last_error(const mn_scene* scene) {
  if (scene && !isLive(scene)) return "mn_scene_last_error: scene is not a live handle (destroyed, or not from mn_scene_create)";
  return scene ? scene->lastError.c_str() : t_lastError.c_str();
}

mn_status mn_scene_load_file(mn_scene* scene, const char* path) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_load_file: scene") + notLive(scene));
  if (!path) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_load_file: path is NULL");
  return inCall(scene, "mn_scene_load_file", [&] {
    if (!readable(path)) return fail(scene, MN_ERROR_IO, std::string(path) + ": error: cannot open the scene file");
    marionette::SceneLoadResult r = marionette::loadSceneFile(path, scene->scene);
    if (!r.ok()) return fail(scene, MN_ERROR_LOAD, r.diagnostics.format());
    logWarnings(*scene, r.diagnostics);
    for (const auto& [character, asset] : r.assets) scene->assets.insert_or_assign(character, asset);
    scene->syncHandles();
#ifdef MARIONETTE_C_HAS_BML
    marionette::bml::useSceneDialects(*scene->realizer, r);
#endif
    if (!r.bml.empty()) {
#ifdef MARIONETTE_C_HAS_BML
      scene->pendingBml.insert(scene->pendingBml.end(), r.bml.begin(), r.bml.end());
      std::stable_sort(scene->pendingBml.begin() + static_cast<std::ptrdiff_t>(scene->nextBml), scene->pendingBml.end(),
                       [](const marionette::TimedFile& a, const marionette::TimedFile& b) { return a.time < b.time; });
#else
      scene->scene.log(marionette::LogLevel::Warning,
                       std::string(path) + ": warning: \"bml\" is ignored: this library was built without BML");
#endif
    }
    return MN_OK;
  });
}

mn_status mn_scene_add_character(mn_scene* scene, const char* name, const char* asset_path, const char* profile_path,
                                 mn_character** out) {
  if (out) *out = nullptr;
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_add_character: scene") + notLive(scene));
  if (!name || !*name) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_add_character: name is NULL or empty");
  if (!asset_path) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_add_character: asset_path is NULL");
  return inCall(scene, "mn_scene_add_character", [&] {
    if (scene->scene.findCharacter(name))
      return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                  std::string("mn_scene_add_character: a character named '") + name + "' exists already");
    if (!readable(asset_path))
      return fail(scene, MN_ERROR_IO, std::string(asset_path) + ": error: cannot open the character file");
    if (profile_path && !readable(profile_path))
      return fail(scene, MN_ERROR_IO, std::string(profile_path) + ": error: cannot open the character profile");
    // A file this scene loaded already (for a character that still lives) is shared, not read again.
    std::error_code ec;
    const std::string key = std::filesystem::absolute(asset_path, ec).lexically_normal().string() + "\n" +
                            (profile_path ? std::filesystem::absolute(profile_path, ec).lexically_normal().string() : "");
    mn_asset loaded;
    if (auto it = scene->loadedFiles.find(key); it != scene->loadedFiles.end()) {
      loaded.rig = it->second.rig.lock();
      loaded.asset = it->second.asset.lock();
    }
    if (!loaded.rig || !loaded.asset) {
      marionette::ImportOptions options;
      options.loadMeshes = false;
      std::string warnings;
      if (const mn_status s = marionette::capi::loadAsset(scene, "mn_scene_add_character", asset_path, nullptr, options,
                                                         profile_path, loaded, warnings);
          s != MN_OK)
        return s;
      for (std::size_t at = 0, next; at < warnings.size(); at = next + 1) {
        next = warnings.find('\n', at);
        if (next == std::string::npos) next = warnings.size();
        scene->scene.log(marionette::LogLevel::Warning, std::string_view(warnings).substr(at, next - at));
      }
      scene->loadedFiles.insert_or_assign(key, mn_scene::LoadedFile{loaded.rig, loaded.asset});
    }
    return addCharacter(*scene, "mn_scene_add_character", name, loaded, out);
  });
}

mn_status mn_scene_add_character_from_asset(mn_scene* scene, const char* name, mn_asset* asset, mn_character** out) {
  if (out) *out = nullptr;
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_add_character_from_asset: scene") + notLive(scene));
  if (!name || !*name) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_add_character_from_asset: name is NULL or empty");
  if (!isLive(asset))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_add_character_from_asset: asset") + notLive(asset));
  return inCall(scene, "mn_scene_add_character_from_asset", [&] {
    if (scene->scene.findCharacter(name))
      return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                  std::string("mn_scene_add_character_from_asset: a character named '") + name + "' exists already");
    return addCharacter(*scene, "mn_scene_add_character_from_asset", name, *asset, out);
  });
}

mn_status mn_scene_find_character(mn_scene* scene, const char* name, mn_character** out) {
  if (out) *out = nullptr;
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_find_character: scene") + notLive(scene));
  if (!name || !out) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_find_character: name or out is NULL");
  return guarded(scene, [&] {
    scene->syncHandles();
    for (const auto& h : scene->handles)
      if (h->character->name() == name) {
        *out = h.get();
        return MN_OK;
      }
    return fail(scene, MN_ERROR_NOT_FOUND, std::string("no character named '") + name + "' in the scene");
  });
}

size_t mn_scene_character_count(const mn_scene* scene) { return isLive(scene) ? scene->scene.characters().size() : 0; }

mn_character* mn_scene_character_at(mn_scene* scene, size_t index) {
  if (!isLive(scene)) return nullptr;
  try {
    scene->syncHandles();
  } catch (...) {
    fail(scene, MN_ERROR_OUT_OF_MEMORY, "out of memory");
    return nullptr;
  }
  return index < scene->handles.size() ? scene->handles[index].get() : nullptr;
}

mn_status mn_scene_send_bml(mn_scene* scene, const char* character, const char* bml_text) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_send_bml: scene") + notLive(scene));
  if (!bml_text) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_send_bml: bml_text is NULL");
#ifdef MARIONETTE_C_HAS_BML
  return inCall(scene, "mn_scene_send_bml", [&] {
    if (character && !scene->scene.findCharacter(character))
      return fail(scene, MN_ERROR_NOT_FOUND, std::string("mn_scene_send_bml: no character named '") + character + "'");
    const marionette::bml::Schedule s = scene->realizer->perform(bml_text, character ? character : "");
    if (!s.failed) return MN_OK;
    const std::string blockId = !s.blockId.empty() ? s.blockId : sniffBlockId(bml_text);
    std::string message;
    for (const marionette::bml::Warning& w : s.warnings) message += formatWarning(blockId, w) + "\n";
    if (message.empty()) message = "bml block '" + blockId + "': error: the block failed\n";
    message.pop_back();
    return fail(scene, MN_ERROR_BML, message);
  });
#else
  (void)character;
  return fail(scene, MN_ERROR_UNSUPPORTED, "mn_scene_send_bml: this library was built without BML (MARIONETTE_WITH_BML=OFF)");
#endif
}

mn_status mn_scene_set_speech_synthesis(mn_scene* scene, mn_speech_synthesis mode) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_speech_synthesis: scene") + notLive(scene));
  const int value = static_cast<int>(mode);  // any int may arrive from C: checked before it is an enum of C++
  if (value != MN_SPEECH_BACKGROUND && value != MN_SPEECH_INLINE)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_scene_set_speech_synthesis: mode " + std::to_string(value) +
                    " is neither MN_SPEECH_BACKGROUND (0) nor MN_SPEECH_INLINE (1)");
#ifdef MARIONETTE_C_HAS_BML
  scene->realizer->setSpeechSynthesis(value == MN_SPEECH_INLINE ? marionette::bml::Realizer::SpeechSynthesis::Inline
                                                                : marionette::bml::Realizer::SpeechSynthesis::Background);
#endif
  return MN_OK;
}

mn_status mn_scene_wait_for_speech(mn_scene* scene) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_wait_for_speech: scene") + notLive(scene));
#ifdef MARIONETTE_C_HAS_BML
  return inCall(scene, "mn_scene_wait_for_speech", [&] {
    scene->realizer->waitForSpeech();
    return MN_OK;
  });
#else
  return MN_OK;
#endif
}

mn_status mn_scene_update(mn_scene* scene, double dt) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_update: scene") + notLive(scene));
  if (!std::isfinite(dt) || dt < 0.0 || dt > marionette::Scene::kMaxUpdateSeconds)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_update: dt must be finite, >= 0 and at most 3600 seconds");
  return inCall(scene, "mn_scene_update", [&] {
#ifdef MARIONETTE_C_HAS_BML
    if (scene->nextBml < scene->pendingBml.size()) sendDueBml(*scene, scene->scene.time() + dt);
#endif
    scene->scene.update(dt);
#ifdef MARIONETTE_C_HAS_BML
    scene->realizer->update();
#endif
    return MN_OK;
  });
}

double mn_scene_time(const mn_scene* scene) { return isLive(scene) ? scene->scene.time() : 0.0; }

mn_status mn_scene_set_feedback_callback(mn_scene* scene, mn_feedback_fn fn, void* user) {
  return setCallback(scene, "mn_scene_set_feedback_callback", &mn_scene::feedbackFn, &mn_scene::feedbackUser, fn, user);
}

mn_status mn_scene_set_viseme_callback(mn_scene* scene, mn_viseme_fn fn, void* user) {
  return setCallback(scene, "mn_scene_set_viseme_callback", &mn_scene::visemeFn, &mn_scene::visemeUser, fn, user);
}

mn_status mn_scene_set_speech_callback(mn_scene* scene, mn_speech_fn fn, void* user) {
  return setCallback(scene, "mn_scene_set_speech_callback", &mn_scene::speechFn, &mn_scene::speechUser, fn, user);
}

mn_status mn_scene_set_clip_callback(mn_scene* scene, mn_clip_fn fn, void* user) {
  return setCallback(scene, "mn_scene_set_clip_callback", &mn_scene::clipFn, &mn_scene::clipUser, fn, user);
}

mn_status mn_scene_remove_character(mn_scene* scene, mn_character* character) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_remove_character: scene") + notLive(scene));
  if (!isLive(character))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_remove_character: character") + notLive(character));
  if (character->owner != scene)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_scene_remove_character: character '" + character->character->name() + "' belongs to another scene");
  return inCall(scene, "mn_scene_remove_character", [&] {
    const std::string name = character->character->name();
    auto it = std::find_if(scene->handles.begin(), scene->handles.end(), [&](const auto& h) { return h.get() == character; });
    if (it == scene->handles.end() || !scene->scene.removeCharacter(name))
      return fail(scene, MN_ERROR_NOT_FOUND, "mn_scene_remove_character: the scene has no character '" + name + "'");
    scene->handles.erase(it);  // frees the handle (kept back from reuse: a stale one is refused)
    scene->assets.erase(name);
    return MN_OK;
  });
}

mn_status mn_scene_interrupt_block(mn_scene* scene, const char* block_id) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_interrupt_block: scene") + notLive(scene));
  if (!block_id) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_interrupt_block: block_id is NULL");
#ifdef MARIONETTE_C_HAS_BML
  return inCall(scene, "mn_scene_interrupt_block", [&] {
    if (!scene->realizer->interrupt(block_id))
      return fail(scene, MN_ERROR_NOT_FOUND, std::string("mn_scene_interrupt_block: no block '") + block_id + "' is running or waiting");
    return MN_OK;
  });
#else
  return fail(scene, MN_ERROR_UNSUPPORTED, "mn_scene_interrupt_block: this library was built without BML");
#endif
}

mn_status mn_scene_set_object(mn_scene* scene, const char* name, float x, float y, float z) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_object: scene") + notLive(scene));
  if (!name || !*name) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_set_object: name is NULL or empty");
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_object: the position of '") + name + "' is not finite");
  return inCall(scene, "mn_scene_set_object", [&] {
    scene->scene.setObject(name, {x, y, z});
    return MN_OK;
  });
}

mn_status mn_scene_remove_object(mn_scene* scene, const char* name) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_remove_object: scene") + notLive(scene));
  if (!name) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_remove_object: name is NULL");
  return inCall(scene, "mn_scene_remove_object", [&] {
    if (!scene->scene.removeObject(name))
      return fail(scene, MN_ERROR_NOT_FOUND, std::string("mn_scene_remove_object: no object '") + name + "'");
    return MN_OK;
  });
}

mn_status mn_scene_set_bml_dialect(mn_scene* scene, const char* character, const char* dialect) {
  if (!isLive(scene)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_bml_dialect: scene") + notLive(scene));
  if (!dialect) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_set_bml_dialect: dialect is NULL");
#ifdef MARIONETTE_C_HAS_BML
  return inCall(scene, "mn_scene_set_bml_dialect", [&] {
    const std::optional<marionette::bml::Dialect> d = marionette::bml::dialectFromName(dialect);
    if (!d)
      return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                  std::string("mn_scene_set_bml_dialect: \"") + dialect + "\" is not a BML dialect (auto, bml or smartbody)");
    if (character) scene->realizer->setDialect(character, *d);
    else scene->realizer->setDialect(*d);
    return MN_OK;
  });
#else
  return fail(scene, MN_ERROR_UNSUPPORTED, "mn_scene_set_bml_dialect: this library was built without BML");
#endif
}

mn_status mn_scene_set_log_callback(mn_scene* scene, mn_log_fn fn, void* user) {
  return setCallback(scene, "mn_scene_set_log_callback", &mn_scene::logFn, &mn_scene::logUser, fn, user);
}

}  // extern "C"
