// libFuzzer target: the C API (bridge/c_api/include/marionette/marionette.h) driven by a byte
// stream. Each operation byte picks a call: create and destroy scenes (twice too, and from
// a callback), add the project's real characters (with and without profiles, and paths
// that are missing, folders or not characters), load scene text and send BML taken from
// the stream, update with any 8-byte double (NaN, Inf, huge, negative), query characters,
// joints, palettes and morphs with live, destroyed, foreign and NULL handles, bad layouts,
// any int as a status. Contract: no crash or UB; every call returns a documented status
// (a bad handle or argument MN_ERROR_INVALID_ARGUMENT, a failure with a message), never
// NULL strings, finite matrices. Stale handles stay within the header's 256-destroys
// promise (a few scenes per input). With MARIONETTE_FUZZ_WRITE_SEED=folder the program
// writes a few seed streams there and exits. Built by scripts/fuzz.
#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

#include "fuzz_support.hpp"
#include "marionette/marionette.h"

using marionette::fuzz::require;

namespace {

#define MN_SHARED MARIONETTE_SOURCE_DIR "/../shared/assets/characters/"
#define MN_PROFILES MARIONETTE_SOURCE_DIR "/assets/profiles/"
// Character files to add (asset, profile): real ones, and paths the API must refuse.
constexpr std::array<std::array<const char*, 2>, 7> kCharacters{{
    {MN_SHARED "CesiumMan.glb", nullptr},
    {MN_SHARED "RobotExpressive.glb", MN_PROFILES "RobotExpressive.json"},
    {MN_SHARED "Godette_vrm_v4.vrm", MN_PROFILES "Godette_vrm_v4.json"},
    {MN_SHARED "CesiumMan.glb", MN_PROFILES "RobotExpressive.json"},  // a profile for another character
    {MN_SHARED "no-such-file.glb", nullptr},
    {MN_SHARED, nullptr},                                          // a folder
    {MN_PROFILES "RobotExpressive.json", MN_SHARED "missing.json"},  // not a character file
}};
constexpr int kMaxScenes = 4;      // per input: stale handles stay quarantined (marionette.h)
constexpr int kMaxCharacterLoads = 2;  // each import takes milliseconds

enum Op : std::uint8_t {
  kCreate, kDestroy, kAddCharacter, kLoadSceneText, kSendBml, kUpdate, kSceneQueries, kCharacterCalls,
  kPalette, kMorphs, kEnums, kCallbacks, kNullArguments, kClips, kRemoveCharacter, kInterrupt, kBinding, kDialect, kObject, kOpCount
};

class Stream {
 public:
  Stream(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
  [[nodiscard]] bool empty() const { return n_ == 0; }
  std::uint8_t byte() { return n_ ? (--n_, *p_++) : 0; }
  template <class T>
  T raw() {
    T v{};
    const std::size_t k = std::min(sizeof v, n_);
    std::memcpy(&v, p_, k);
    p_ += k, n_ -= k;
    return v;
  }
  std::string text() {  // u16 length, then that many bytes (NUL bytes end the C string early)
    const std::size_t len = std::min<std::size_t>(raw<std::uint16_t>(), n_);
    std::string s(reinterpret_cast<const char*>(p_), len);
    p_ += len, n_ -= len;
    return s;
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
};

bool documented(mn_status s) { return s >= MN_OK && s <= MN_ERROR_INTERNAL; }

struct SceneSlot {
  mn_scene* scene = nullptr;
  bool live = false;
};

struct Callbacks {  // what a callback may do to its own scene
  SceneSlot* slot = nullptr;
  bool destroyFromCallback = false;
};

void checkString(const char* s) {
  require(s != nullptr, "a string callback argument is NULL");
  (void)std::strlen(s);  // readable to its end (ASan)
}

void onFeedback(void* user, const mn_feedback* f) {
  auto* c = static_cast<Callbacks*>(user);
  require(f != nullptr, "feedback is NULL");
  for (const char* s : {f->character, f->block, f->behavior, f->sync_point, f->message}) checkString(s);
  require(f->kind >= MN_FEEDBACK_PREDICTION && f->kind <= MN_FEEDBACK_WARNING, "unknown feedback kind");
  // Re-entry is refused; a destroy waits until the call returns.
  require(mn_scene_update(c->slot->scene, 0.0) == MN_ERROR_INVALID_ARGUMENT, "mn_scene_update from a callback ran");
  if (c->destroyFromCallback && c->slot->live) {
    mn_scene_destroy(c->slot->scene);
    c->slot->live = false;
  }
}
void onViseme(void*, const mn_viseme* v) {
  require(v != nullptr, "viseme is NULL");
  checkString(v->character);
  checkString(v->viseme);
}
void onSpeech(void*, const mn_speech* s) {
  require(s != nullptr, "speech is NULL");
  for (const char* t : {s->character, s->behavior, s->audio_file}) checkString(t);
  require(std::isfinite(s->start_time) && std::isfinite(s->duration) && s->duration >= 0.0, "speech times");
  if (s->samples && s->sample_count) {  // readable to the end (ASan)
    volatile short first = s->samples[0], last = s->samples[s->sample_count - 1];
    (void)first;
    (void)last;
  }
}
void onClip(void*, const mn_clip_event* e) {
  require(e != nullptr, "clip event is NULL");
  require(e->kind == MN_CLIP_STARTED || e->kind == MN_CLIP_STOPPED, "unknown clip event");
  checkString(e->character);
  checkString(e->clip);
}
void onLog(void*, mn_log_level level, const char* message) {
  require(level >= MN_LOG_INFO && level <= MN_LOG_ERROR, "unknown log level");
  checkString(message);
}

class Driver {
 public:
  void run(Stream& in) {
    while (!in.empty()) step(in);
    for (mn_binding* b : bindings_) mn_binding_destroy(b);  // outliving their characters and scenes
    for (SceneSlot& s : scenes_)
      if (s.live) mn_scene_destroy(s.scene);
  }

 private:
  std::array<SceneSlot, kMaxScenes> scenes_{};
  std::array<Callbacks, kMaxScenes> callbacks_{};
  int created_ = 0, loads_ = 0, sceneTexts_ = 0;
  struct CharacterSlot {
    mn_character* handle;
    const mn_scene* owner;  // the handle is live while its scene is, until removed
    bool removed = false;
  };
  std::vector<CharacterSlot> characters_;  // every handle seen, live or not
  std::vector<mn_binding*> bindings_;  // live bindings (destroyed at the end)
  char foreign_[64] = {};                   // an address that is no handle

  SceneSlot& slot(Stream& in) { return scenes_[in.byte() % kMaxScenes]; }
  // A scene handle: live, destroyed, never created (NULL) or foreign.
  mn_scene* anyScene(Stream& in) {
    const std::uint8_t b = in.byte();
    if (b % 8 == 6) return nullptr;
    if (b % 8 == 7) return reinterpret_cast<mn_scene*>(foreign_);
    return scenes_[b % kMaxScenes].scene;
  }
  // A character handle and whether it is live: of a live scene, of a destroyed one, NULL or foreign.
  std::pair<mn_character*, bool> anyCharacter(Stream& in) {
    const std::uint8_t b = in.byte();
    if (b == 255 || characters_.empty()) return {b % 2 ? nullptr : reinterpret_cast<mn_character*>(foreign_), false};
    const CharacterSlot& c = characters_[b % characters_.size()];
    return {c.handle, isLiveScene(c.owner) && !c.removed};
  }
  [[nodiscard]] const mn_scene* ownerOf(const mn_character* c) const {
    for (const CharacterSlot& slot : characters_)
      if (slot.handle == c && !slot.removed) return slot.owner;
    return nullptr;
  }
  [[nodiscard]] bool isLiveScene(const mn_scene* s) const {
    for (const SceneSlot& slot : scenes_)
      if (slot.live && slot.scene == s) return true;
    return false;
  }

  // A failure leaves a message on the scene (or the thread, without a live scene).
  void failed(mn_status s, const mn_scene* scene) {
    require(documented(s), "an undocumented status");
    if (s == MN_OK) return;
    const char* e = mn_scene_last_error(isLiveScene(scene) ? scene : nullptr);
    require(e != nullptr && *e != '\0', "a failure without a message");
  }

  void step(Stream& in) {
    switch (static_cast<Op>(in.byte() % kOpCount)) {
      case kCreate: {
        SceneSlot& s = slot(in);
        if (s.live || created_ >= kMaxScenes) return;
        ++created_;
        require(mn_scene_create(&s.scene) == MN_OK && s.scene != nullptr, "mn_scene_create failed");
        s.live = true;
        return;
      }
      case kDestroy: {
        SceneSlot& s = slot(in);
        mn_scene_destroy(s.scene);  // a second time too: refused, nothing freed
        s.live = false;
        return;
      }
      case kAddCharacter: {
        mn_scene* scene = anyScene(in);
        const auto& [asset, profile] = kCharacters[in.byte() % kCharacters.size()];
        const bool read = asset[std::strlen(asset) - 1] != '/' && std::strstr(asset, "no-such") == nullptr;
        if (read && loads_++ >= kMaxCharacterLoads) return;
        const std::string name = in.text();
        mn_character* c = reinterpret_cast<mn_character*>(foreign_);
        const mn_status st = mn_scene_add_character(scene, name.c_str(), asset, profile, &c);
        failed(st, scene);
        if (!isLiveScene(scene)) require(st == MN_ERROR_INVALID_ARGUMENT, "a call on a bad scene handle ran");
        require((st == MN_OK) == (c != nullptr), "add_character's out does not match its status");
        if (c) characters_.push_back({c, scene});
        return;
      }
      case kLoadSceneText: {
        mn_scene* scene = anyScene(in);
        const std::string text = in.text();
        if (sceneTexts_++ >= 1) return;  // scene files may name characters: one a input
        const std::string path = marionette::fuzz::writeInput(reinterpret_cast<const std::uint8_t*>(text.data()),
                                                              text.size(), "scene.json");
        const mn_status st = mn_scene_load_file(scene, path.c_str());
        failed(st, scene);
        if (isLiveScene(scene))
          for (std::size_t i = 0; i < mn_scene_character_count(scene); ++i)
            characters_.push_back({mn_scene_character_at(scene, i), scene});
        return;
      }
      case kSendBml: {
        mn_scene* scene = anyScene(in);
        const std::uint8_t who = in.byte();
        const std::string name = in.text(), bml = in.text();
        const char* character = who % 3 == 0 ? nullptr : who % 3 == 1 ? "c" : name.c_str();
        const mn_status st = mn_scene_send_bml(scene, character, bml.c_str());
        failed(st, scene);
        require(st == MN_OK || st == MN_ERROR_BML || st == MN_ERROR_NOT_FOUND || st == MN_ERROR_INVALID_ARGUMENT ||
                    st == MN_ERROR_UNSUPPORTED,
                "send_bml returned an unexpected status");
        return;
      }
      case kUpdate: {
        mn_scene* scene = anyScene(in);
        const double dt = in.raw<double>();
        const bool valid = std::isfinite(dt) && dt >= 0.0 && dt <= 3600.0;
        const double before = mn_scene_time(scene);
        const mn_status st = mn_scene_update(scene, dt);
        failed(st, scene);
        const bool live = isLiveScene(scene);
        if (!valid || !live) {
          require(st == MN_ERROR_INVALID_ARGUMENT, "update with a bad dt or handle was accepted");
          if (live) require(mn_scene_time(scene) == before, "a refused update moved the clock");
        } else {
          require(st == MN_OK, "a valid update failed");
        }
        for (SceneSlot& s : scenes_)  // a callback may have destroyed it
          if (s.scene == scene && !s.live) return;
        if (live) require(std::isfinite(mn_scene_time(scene)), "scene time not finite");
        return;
      }
      case kSceneQueries: {
        mn_scene* scene = anyScene(in);
        const bool live = isLiveScene(scene);
        const std::size_t count = mn_scene_character_count(scene);
        if (!live) require(count == 0, "a bad scene has characters");
        const std::uint8_t index = in.byte();
        mn_character* at = mn_scene_character_at(scene, index);
        require((at != nullptr) == (index < count), "character_at disagrees with character_count");
        const std::string name = in.text();
        mn_character* found = reinterpret_cast<mn_character*>(foreign_);
        const mn_status st = mn_scene_find_character(scene, name.c_str(), &found);
        failed(st, scene);
        require((st == MN_OK) == (found != nullptr), "find_character's out does not match its status");
        require(st == MN_OK || st == MN_ERROR_NOT_FOUND || st == MN_ERROR_INVALID_ARGUMENT, "find_character status");
        require(mn_scene_last_error(scene) != nullptr, "last_error is NULL");
        require(live || mn_scene_time(scene) == 0.0, "a bad scene has a time");
        return;
      }
      case kCharacterCalls: {
        const auto [c, live] = anyCharacter(in);
        checkString(mn_character_name(c));
        if (!live) require(mn_character_joint_count(c) == 0 && mn_character_morph_count(c) == 0, "a bad character has joints");
        const std::size_t joints = mn_character_joint_count(c);
        const std::uint16_t j = in.raw<std::uint16_t>();
        const char* jointName = mn_character_joint_name(c, j);
        require((jointName != nullptr) == (j < joints), "joint_name disagrees with joint_count");
        const std::string name = in.text();
        const int found = mn_character_find_joint(c, name.c_str());
        require(found >= -1 && found < static_cast<int>(joints), "find_joint out of range");
        const auto x = in.raw<float>(), y = in.raw<float>(), z = in.raw<float>();
        const mn_status pos = mn_character_set_position(c, x, y, z);
        require(documented(pos) && (pos == MN_OK) == (live && std::isfinite(x) && std::isfinite(y) && std::isfinite(z)),
                "set_position status");
        const auto heading = in.raw<float>();
        const mn_status h = mn_character_set_heading(c, heading);
        require((h == MN_OK) == (live && std::isfinite(heading)), "set_heading status");
        float m[16];
        const bool out = in.byte() % 4 != 0;
        const mn_status w = mn_character_world_matrix(c, out ? m : nullptr);
        require((w == MN_OK) == (live && out) && (w == MN_OK || w == MN_ERROR_INVALID_ARGUMENT), "world_matrix status");
        if (w == MN_OK)
          for (float v : m) require(std::isfinite(v), "world matrix not finite");
        return;
      }
      case kPalette: {
        const auto [c, live] = anyCharacter(in);
        const auto layout = static_cast<mn_palette_layout>(in.raw<std::int32_t>());
        const int inverseBind = in.raw<std::int8_t>();
        std::vector<float> buffer(std::min<std::size_t>(in.raw<std::uint16_t>(), 16 * 256));
        const mn_status st =
            mn_character_palette(c, layout, inverseBind, buffer.empty() ? nullptr : buffer.data(), buffer.size());
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT, "palette status");
        if (!live || mn_palette_floats_per_joint(layout) == 0) require(st != MN_OK, "a bad palette call was accepted");
        if (st == MN_OK) {
          require(buffer.size() >= mn_character_joint_count(c) * mn_palette_floats_per_joint(layout), "palette overrun");
          for (float v : buffer) require(std::isfinite(v), "palette not finite");
        }
        return;
      }
      case kMorphs: {
        const auto [c, live] = anyCharacter(in);
        const std::size_t morphs = mn_character_morph_count(c);
        const std::uint8_t k = in.byte();
        require((mn_character_morph_name(c, k) != nullptr) == (k < morphs), "morph_name disagrees with morph_count");
        std::vector<float> weights(in.byte() % 32);
        const mn_status st = mn_character_morph_weights(c, weights.empty() ? nullptr : weights.data(), weights.size());
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT, "morph_weights status");
        if (!live) require(st != MN_OK, "morph_weights on a bad handle was accepted");
        if (st == MN_OK)
          for (std::size_t i = 0; i < morphs; ++i) require(std::isfinite(weights[i]), "morph weight not finite");
        return;
      }
      case kEnums: {
        const auto status = static_cast<mn_status>(in.raw<std::int32_t>());
        checkString(mn_status_name(status));
        const std::size_t floats = mn_palette_floats_per_joint(static_cast<mn_palette_layout>(in.raw<std::int32_t>()));
        require(floats == 0 || floats == 12 || floats == 16, "floats_per_joint");
        return;
      }
      case kCallbacks: {
        const std::size_t i = in.byte() % kMaxScenes;
        const std::uint8_t how = in.byte();
        callbacks_[i] = {&scenes_[i], (how & 8) != 0};
        mn_scene* scene = scenes_[i].scene;
        for (mn_status st : {mn_scene_set_feedback_callback(scene, how & 1 ? onFeedback : nullptr, &callbacks_[i]),
                             mn_scene_set_viseme_callback(scene, how & 2 ? onViseme : nullptr, nullptr),
                             mn_scene_set_log_callback(scene, how & 4 ? onLog : nullptr, nullptr),
                             mn_scene_set_speech_callback(scene, how & 16 ? onSpeech : nullptr, nullptr),
                             mn_scene_set_clip_callback(scene, how & 32 ? onClip : nullptr, nullptr)})
          require(st == (scenes_[i].live ? MN_OK : MN_ERROR_INVALID_ARGUMENT), "set_callback status");
        return;
      }
      case kNullArguments: {
        mn_scene* scene = anyScene(in);
        const auto invalid = [](mn_status st) { require(st == MN_ERROR_INVALID_ARGUMENT, "a NULL argument was accepted"); };
        invalid(mn_scene_create(nullptr));
        invalid(mn_scene_load_file(scene, nullptr));
        invalid(mn_scene_add_character(scene, nullptr, kCharacters[0][0], nullptr, nullptr));
        invalid(mn_scene_add_character(scene, "", kCharacters[0][0], nullptr, nullptr));
        invalid(mn_scene_add_character(scene, "n", nullptr, nullptr, nullptr));
        invalid(mn_scene_find_character(scene, nullptr, nullptr));
        invalid(mn_scene_send_bml(scene, nullptr, nullptr));
        require(mn_scene_last_error(nullptr) != nullptr, "last_error(NULL) is NULL");
        return;
      }
      case kClips: {
        const auto [c, live] = anyCharacter(in);
        const std::size_t clips = mn_character_clip_count(c);
        if (!live) require(clips == 0, "a bad character has clips");
        const std::uint8_t k = in.byte();
        require((mn_character_clip_name(c, k) != nullptr) == (k < clips), "clip_name disagrees with clip_count");
        const double d = mn_character_clip_duration(c, k);
        require(std::isfinite(d) && d >= 0.0, "clip_duration");
        // A clip of the rig or any text; defaults or fuzzed options; any layer.
        const std::string name = clips && in.byte() % 2 ? mn_character_clip_name(c, in.byte() % clips) : in.text();
        mn_play_options o = mn_play_options_default();
        const bool fuzzed = in.byte() % 2;
        if (fuzzed) {
          o.weight = in.raw<float>();
          o.speed = in.raw<float>();
          o.loop = in.raw<std::int8_t>();
          o.start_time = in.raw<double>();
          o.fade_in = in.raw<float>();
          o.additive = in.raw<std::int8_t>();
          o.root_motion = in.raw<std::int8_t>();
        }
        const int layer = in.raw<std::int8_t>();
        const mn_status st = mn_character_play(c, layer, name.c_str(), fuzzed ? &o : nullptr);
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_NOT_FOUND, "play status");
        if (!live || layer < 0 || layer > 7) require(st != MN_OK, "a bad play was accepted");
        failed(st, ownerOf(c));
        const mn_status stop = mn_character_stop(c, in.raw<std::int8_t>(), in.raw<float>());
        require(stop == MN_OK || stop == MN_ERROR_INVALID_ARGUMENT, "stop status");
        if (!live) require(stop != MN_OK, "a stop on a bad handle was accepted");
        return;
      }
      case kRemoveCharacter: {
        mn_scene* scene = anyScene(in);
        const auto [c, live] = anyCharacter(in);
        const mn_status st = mn_scene_remove_character(scene, c);
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_NOT_FOUND, "remove status");
        if (!live || !isLiveScene(scene)) require(st != MN_OK, "a bad remove was accepted");
        if (st == MN_OK)
          for (CharacterSlot& slot : characters_)
            if (slot.handle == c) slot.removed = true;
        failed(st, scene);
        return;
      }
      case kInterrupt: {
        mn_scene* scene = anyScene(in);
        const std::string block = in.text();
        const mn_status st = mn_scene_interrupt_block(scene, in.byte() % 8 ? block.c_str() : nullptr);
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_NOT_FOUND || st == MN_ERROR_UNSUPPORTED,
                "interrupt status");
        failed(st, scene);
        return;
      }
      case kDialect: {  // a dialect name, mostly a real one, for the scene or a character (maybe unknown)
        mn_scene* scene = anyScene(in);
        static const char* const kNames[] = {"auto", "bml", "smartbody"};
        const std::uint8_t pick = in.byte();
        const std::string name = pick % 4 == 3 ? in.text() : kNames[pick % 4];
        const std::string character = in.text();
        const mn_status st = mn_scene_set_bml_dialect(scene, pick & 4 ? character.c_str() : nullptr, name.c_str());
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_UNSUPPORTED, "dialect status");
        failed(st, scene);
        return;
      }
      case kObject: {  // a place to aim at: set (maybe not finite) or removed
        mn_scene* scene = anyScene(in);
        const std::string name = in.byte() % 4 ? std::string("camera") : in.text();
        const float x = in.byte() % 16 ? static_cast<float>(in.byte()) - 128.0f : std::numeric_limits<float>::quiet_NaN();
        const mn_status st = in.byte() % 3 ? mn_scene_set_object(scene, name.c_str(), x, 1.5f, 2.0f)
                                           : mn_scene_remove_object(scene, name.c_str());
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_NOT_FOUND, "object status");
        failed(st, scene);
        return;
      }
      case kBinding: {  // bind to an engine skeleton of fuzzed names and parents, copy, maybe destroy
        const auto [c, live] = anyCharacter(in);
        const std::size_t bones = in.byte() % 24, morphs = in.byte() % 4;
        std::vector<std::string> names;
        std::vector<int> parents;
        for (std::size_t i = 0; i < bones; ++i) {
          const std::uint8_t pick = in.byte();  // a joint of the character's, or fuzzed text
          const char* joint = mn_character_joint_name(c, pick);
          names.push_back(pick % 3 && joint ? std::string(joint) : in.text());
          parents.push_back(static_cast<int>(in.raw<std::int8_t>()));
        }
        for (std::size_t i = 0; i < morphs; ++i) {
          const char* morph = mn_character_morph_name(c, in.byte());
          names.push_back(morph ? std::string(morph) : in.text());
        }
        std::vector<const char*> ptrs;
        for (const std::string& n : names) ptrs.push_back(n.c_str());
        const std::uint8_t flags = in.byte();
        mn_engine_skeleton engine{ptrs.data(), flags & 1 ? parents.data() : nullptr, bones, ptrs.data() + bones, morphs};
        mn_binding_options o = mn_binding_options_default();
        o.through_joint_maps = flags & 2;
        const std::string map = in.text();
        if (flags & 4) o.engine_joint_map = map.c_str();
        mn_binding* b = nullptr;
        const mn_status st = mn_binding_create(c, &engine, flags & 8 ? &o : nullptr, &b);
        require(st == MN_OK || st == MN_ERROR_INVALID_ARGUMENT || st == MN_ERROR_IO || st == MN_ERROR_LOAD,
                "binding status");
        require((st == MN_OK) == (b != nullptr), "a binding without MN_OK, or none with it");
        if (!live) require(st != MN_OK, "a binding of a bad character was accepted");
        failed(st, ownerOf(c));
        if (b) bindings_.push_back(b);
        if (bindings_.empty()) return;
        mn_binding* any = bindings_[in.byte() % bindings_.size()];  // maybe of a removed character
        checkString(mn_binding_report(any));
        std::vector<float> palette(mn_binding_bone_count(any) * 16 + in.byte() % 2);
        const mn_status p =
            mn_binding_palette(any, static_cast<mn_palette_layout>(in.byte() % 4), 1, palette.data(), palette.size());
        require(p == MN_OK || p == MN_ERROR_INVALID_ARGUMENT, "binding palette status");
        if (p == MN_OK)
          for (float v : palette) require(std::isfinite(v), "binding palette not finite");
        std::vector<float> weights(mn_binding_morph_slot_count(any), 0.0f);
        const mn_status w = mn_binding_morph_weights(any, weights.data(), weights.size());
        require(w == MN_OK || w == MN_ERROR_INVALID_ARGUMENT, "binding morph status");
        for (float v : weights) require(std::isfinite(v), "binding morph weight not finite");
        for (std::size_t slot = 0; slot < mn_binding_bone_count(any); ++slot)
          require(mn_binding_joint_for_bone(any, slot) >= -1, "joint_for_bone below -1");
        if (in.byte() % 4 == 0) {
          mn_binding_destroy(any);
          bindings_.erase(std::find(bindings_.begin(), bindings_.end(), any));
        }
        return;
      }
      case kOpCount: return;
    }
  }
};

// Seeds: operation streams that reach deep (a real character, BML, frames, palettes).
void writeSeeds(const std::string& dir) {
  auto text = [](std::vector<std::uint8_t>& s, std::string_view t) {
    s.push_back(static_cast<std::uint8_t>(t.size())), s.push_back(static_cast<std::uint8_t>(t.size() >> 8));
    s.insert(s.end(), t.begin(), t.end());
  };
  auto f64 = [](std::vector<std::uint8_t>& s, double v) {
    std::uint8_t b[8];
    std::memcpy(b, &v, 8);
    s.insert(s.end(), b, b + 8);
  };
  const std::string bml =
      "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b1\" characterId=\"c\">"
      "<gaze id=\"g\" target=\"camera\"/><head id=\"h\" lexeme=\"NOD\" start=\"g:end\"/>"
      "<faceLexeme id=\"f\" lexeme=\"SMILE\" amount=\"0.8\"/><gesture id=\"w\" lexeme=\"BEAT\"/></bml>";
  for (std::uint8_t character = 0; character < 3; ++character) {
    std::vector<std::uint8_t> s = {kCreate, 0, kCallbacks, 0, 7, kAddCharacter, 0, character};
    text(s, "c");
    s.insert(s.end(), {kSendBml, 0, 0});
    text(s, "");
    text(s, bml);
    for (double dt : {0.1, 0.5, 1.0}) s.push_back(kUpdate), s.push_back(0), f64(s, dt);
    s.insert(s.end(), {kPalette, 0, 0, 0, 0, 0, 1, 0x00, 0x10, kMorphs, 0, 0, 16, kCharacterCalls, 0, 3, 0});
    text(s, "Head");
    s.insert(s.end(), 17, 0);
    s.insert(s.end(), {kDestroy, 0, kDestroy, 0, kCharacterCalls, 0, 0, 0, 0, 0});
    const std::string path = dir + "/character" + std::to_string(character) + ".bin";
    marionette::fuzz::writeInput(s.data(), s.size(), "seed.bin");
    std::filesystem::copy_file(marionette::fuzz::tempDir() / "seed.bin", path,
                               std::filesystem::copy_options::overwrite_existing);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    writeSeeds(dir);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Stream in(data, size);
  Driver().run(in);
  return 0;
}
