#include "marionette/scene/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marionette/io/import.hpp"
#include "marionette/speech/recorded_speech.hpp"

namespace marionette {

namespace {
using Json = nlohmann::json;
namespace fs = std::filesystem;

struct PlaySpec {
  std::string clip;
  int layer = 0;
  PlayOptions options;
};

struct CharacterSpec {
  std::string name, asset, profile;  // profile: a character profile JSON ("" = guessed)
  glm::vec3 position{0.0f};
  float headingDegrees = 0.0f;
  float scale = 1.0f;
  std::vector<std::pair<std::string, std::string>> clips;  // file, name
  std::vector<PlaySpec> play;
  bool playGiven = false;
};

// Reads typed members and reports "<file>: error: /characters/2/position: expected ...".
class Reader {
 public:
  Reader(Diagnostics& d, std::string file) : diags_(d), file_(std::move(file)) {}
  void fail(const std::string& where, const std::string& what) { diags_.error(file_, where + ": " + what); }

  bool number(const Json& j, const std::string& where, float& out, float lo = -1e30f, float hi = 1e30f) {
    if (!j.is_number()) return fail(where, "expected a number"), false;
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
      return fail(where, "expected a finite number in [" + fmt(lo) + ", " + fmt(hi) + "]"), false;
    out = static_cast<float>(v);
    return true;
  }
  bool string(const Json& j, const std::string& where, std::string& out) {
    if (!j.is_string() || j.get<std::string>().empty()) return fail(where, "expected a non-empty string"), false;
    out = j.get<std::string>();
    return true;
  }
  bool boolean(const Json& j, const std::string& where, bool& out) {
    if (!j.is_boolean()) return fail(where, "expected true or false"), false;
    out = j.get<bool>();
    return true;
  }
  bool vec3(const Json& j, const std::string& where, glm::vec3& out) {
    if (!j.is_array() || j.size() != 3) return fail(where, "expected [x, y, z]"), false;
    for (int i = 0; i < 3; ++i)
      if (!number(j[i], where + "/" + std::to_string(i), out[i])) return false;
    return true;
  }
  void unknownKeys(const Json& obj, const std::string& where, std::initializer_list<const char*> known) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = false;
      for (const char* k : known) ok |= it.key() == k;
      if (!ok) diags_.warning(file_, where + ": unknown key '" + it.key() + "' ignored");
    }
  }

 private:
  static std::string fmt(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  Diagnostics& diags_;
  std::string file_;
};

bool readPlay(Reader& r, const Json& j, const std::string& where, PlaySpec& p) {
  if (j.is_string()) return r.string(j, where, p.clip);
  if (!j.is_object()) return r.fail(where, "expected a clip name or an object with \"clip\""), false;
  r.unknownKeys(j, where, {"clip", "layer", "weight", "speed", "loop", "rootMotion", "fadeIn", "additive", "start"});
  bool ok = true;  // without "clip", the character's first clip
  if (j.contains("clip")) ok = r.string(j["clip"], where + "/clip", p.clip);
  float f;
  bool b;
  if (j.contains("layer") && (ok &= r.number(j["layer"], where + "/layer", f, 0, Character::kMaxLayers - 1)))
    p.layer = static_cast<int>(f);
  if (j.contains("weight")) ok &= r.number(j["weight"], where + "/weight", p.options.weight, 0.0f, 1e6f);
  if (j.contains("speed")) ok &= r.number(j["speed"], where + "/speed", p.options.speed, -1e3f, 1e3f);
  if (j.contains("fadeIn")) ok &= r.number(j["fadeIn"], where + "/fadeIn", p.options.fadeIn, 0.0f, 1e6f);
  if (j.contains("start") && (ok &= r.number(j["start"], where + "/start", f))) p.options.startTime = f;
  if (j.contains("loop") && (ok &= r.boolean(j["loop"], where + "/loop", b)))
    p.options.wrap = b ? WrapMode::Loop : WrapMode::Clamp;
  if (j.contains("rootMotion")) ok &= r.boolean(j["rootMotion"], where + "/rootMotion", p.options.rootMotion);
  if (j.contains("additive")) ok &= r.boolean(j["additive"], where + "/additive", p.options.additive);
  return ok;
}

bool readCharacter(Reader& r, const Json& j, const std::string& where, CharacterSpec& c) {
  if (!j.is_object()) return r.fail(where, "expected an object with \"name\" and \"asset\""), false;
  r.unknownKeys(j, where, {"name", "asset", "profile", "position", "heading", "scale", "clips", "play"});
  bool ok = true;
  if (!j.contains("name")) ok = false, r.fail(where, "missing \"name\"");
  else ok &= r.string(j["name"], where + "/name", c.name);
  if (!j.contains("asset")) ok = false, r.fail(where, "missing \"asset\" (path of a character file)");
  else ok &= r.string(j["asset"], where + "/asset", c.asset);
  if (j.contains("profile")) ok &= r.string(j["profile"], where + "/profile", c.profile);
  if (j.contains("position")) ok &= r.vec3(j["position"], where + "/position", c.position);
  if (j.contains("heading")) ok &= r.number(j["heading"], where + "/heading", c.headingDegrees, -1e6f, 1e6f);
  if (j.contains("scale")) ok &= r.number(j["scale"], where + "/scale", c.scale, 1e-6f, 1e6f);
  if (j.contains("clips")) {
    const Json& clips = j["clips"];
    if (!clips.is_array()) return r.fail(where + "/clips", "expected an array of {\"file\", \"name\"}"), false;
    for (std::size_t i = 0; i < clips.size(); ++i) {
      const std::string w = where + "/clips/" + std::to_string(i);
      std::string file, name;
      if (!clips[i].is_object() || !clips[i].contains("file")) {
        r.fail(w, "expected {\"file\": PATH, \"name\": NAME}");
        ok = false;
        continue;
      }
      ok &= r.string(clips[i]["file"], w + "/file", file);
      if (clips[i].contains("name")) ok &= r.string(clips[i]["name"], w + "/name", name);
      c.clips.emplace_back(file, name);
    }
  }
  if (j.contains("play")) {
    c.playGiven = true;
    const Json& play = j["play"];
    if (play.is_array()) {
      for (std::size_t i = 0; i < play.size(); ++i) {
        PlaySpec p;
        p.layer = static_cast<int>(i);
        ok &= readPlay(r, play[i], where + "/play/" + std::to_string(i), p);
        c.play.push_back(std::move(p));
      }
    } else {
      PlaySpec p;
      ok &= readPlay(r, play, where + "/play", p);
      c.play.push_back(std::move(p));
    }
  }
  return ok;
}

std::string resolve(const std::string& baseDir, const std::string& path) {
  fs::path p(path);
  if (p.is_absolute() || baseDir.empty()) return p.lexically_normal().string();
  return (fs::path(baseDir) / p).lexically_normal().string();
}
}  // namespace

SceneLoadResult loadSceneText(const std::string& text, const std::string& name, const std::string& baseDir,
                              Scene& scene, const SceneLoadOptions& options) {
  SceneLoadResult result;
  Diagnostics& diags = result.diagnostics;
  Json doc;
  try {  // load time, not per frame: nlohmann reports the byte offset only through its exception
    doc = Json::parse(text);
  } catch (const Json::parse_error& e) {
    auto [line, col] = lineColumnAt(text, e.byte > 0 ? static_cast<std::ptrdiff_t>(e.byte) - 1 : 0);
    std::string msg = e.what();
    auto pos = msg.find("syntax error");
    diags.error(name, pos != std::string::npos ? msg.substr(pos) : msg, line, col);
    return result;
  }
  Reader r(diags, name);
  if (!doc.is_object() || !doc.contains("characters") || !doc["characters"].is_array()) {
    r.fail("/", "expected an object with a \"characters\" array");
    return result;
  }
  r.unknownKeys(doc, "", {"characters", "comment", "bml", "speech"});
  // Recorded voice lines: read now (errors name the line), added to the scene's speech below.
  std::shared_ptr<speech::RecordedSpeech> recorded;
  bool synthesizer = true;
  if (doc.contains("speech")) {
    const Json& sp = doc["speech"];
    if (!sp.is_object()) {
      r.fail("/speech", "expected {\"lines\": [{\"text\", \"audio\", \"alignment\"}], \"synthesizer\": true}");
    } else {
      r.unknownKeys(sp, "/speech", {"lines", "synthesizer", "comment"});
      if (sp.contains("synthesizer")) r.boolean(sp["synthesizer"], "/speech/synthesizer", synthesizer);
      const Json* lines = sp.contains("lines") ? &sp["lines"] : nullptr;
      if (lines && !lines->is_array()) r.fail("/speech/lines", "expected an array of {\"text\", \"audio\", \"alignment\"}");
      for (std::size_t i = 0; lines && lines->is_array() && i < lines->size(); ++i) {
        const std::string where = "/speech/lines/" + std::to_string(i);
        const Json& e = (*lines)[i];
        std::string lineText, audio, alignment;
        if (!e.is_object() || !e.contains("text") || !e.contains("alignment")) {
          r.fail(where, "expected {\"text\": WORDS, \"audio\": WAV, \"alignment\": PHONES}");
          continue;
        }
        r.unknownKeys(e, where, {"text", "audio", "alignment"});
        if (!r.string(e["text"], where + "/text", lineText) || !r.string(e["alignment"], where + "/alignment", alignment)) continue;
        if (e.contains("audio") && !r.string(e["audio"], where + "/audio", audio)) continue;
        if (!recorded) recorded = std::make_shared<speech::RecordedSpeech>();
        const std::string error =
            recorded->addLine(lineText, audio.empty() ? fs::path() : fs::path(resolve(baseDir, audio)), resolve(baseDir, alignment));
        if (!error.empty()) r.fail(where, error);
      }
    }
  }
  if (doc.contains("bml")) {
    const Json& list = doc["bml"];
    if (!list.is_array()) {
      r.fail("/bml", "expected an array of {\"file\", \"time\", \"character\"}");
    } else {
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string where = "/bml/" + std::to_string(i);
        const Json& e = list[i];
        TimedFile t;
        std::string file;
        float time = 0.0f;
        if (!e.is_object() || !e.contains("file")) {
          r.fail(where, "expected {\"file\": PATH, \"time\": SECONDS, \"character\": NAME}");
          continue;
        }
        r.unknownKeys(e, where, {"file", "time", "character"});
        if (!r.string(e["file"], where + "/file", file)) continue;
        if (e.contains("time") && !r.number(e["time"], where + "/time", time, 0.0f, 1e9f)) continue;
        if (e.contains("character") && !r.string(e["character"], where + "/character", t.character)) continue;
        t.path = resolve(baseDir, file);
        t.time = time;
        result.bml.push_back(std::move(t));
      }
      std::stable_sort(result.bml.begin(), result.bml.end(),
                       [](const TimedFile& a, const TimedFile& b) { return a.time < b.time; });
    }
  }
  std::vector<CharacterSpec> specs;
  std::set<std::string> names;
  const Json& list = doc["characters"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    CharacterSpec c;
    const std::string where = "/characters/" + std::to_string(i);
    if (!readCharacter(r, list[i], where, c)) continue;
    if (!names.insert(c.name).second) {
      r.fail(where + "/name", "a character named '" + c.name + "' exists already in this file");
      continue;
    }
    if (scene.findCharacter(c.name)) {
      r.fail(where + "/name", "the scene has a character named '" + c.name + "' already");
      continue;
    }
    specs.push_back(std::move(c));
  }
  if (!diags.ok()) return result;

  // Load each distinct (asset, scale, clip files) once.
  std::map<std::string, std::shared_ptr<const Rig>> rigs;
  std::vector<std::shared_ptr<const Rig>> rigOf(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const CharacterSpec& c = specs[i];
    std::string key = resolve(baseDir, c.asset) + "|" + std::to_string(c.scale) + "|" + resolve(baseDir, c.profile);
    for (auto& [file, clipName] : c.clips) key += "|" + resolve(baseDir, file) + "#" + clipName;
    if (auto it = rigs.find(key); it != rigs.end()) {
      rigOf[i] = it->second;
      continue;
    }
    ImportOptions io;
    io.loadMeshes = options.loadMeshes;
    io.extraScale = c.scale;
    ImportResult imported = importAsset(resolve(baseDir, c.asset), io);
    diags.items.insert(diags.items.end(), imported.diagnostics.items.begin(), imported.diagnostics.items.end());
    if (!imported.ok()) {
      r.fail("/characters/" + std::to_string(i) + "/asset", "could not load '" + c.asset + "' (see above)");
      continue;
    }
    ++result.assetsLoaded;
    auto asset = std::make_shared<Asset>(std::move(*imported.asset));
    auto rig = std::make_shared<Rig>(asset);
    if (!c.profile.empty()) {
      CharacterProfileResult profile = loadCharacterProfile(resolve(baseDir, c.profile), *asset);
      diags.items.insert(diags.items.end(), profile.diagnostics.items.begin(), profile.diagnostics.items.end());
      if (!profile.diagnostics.ok()) r.fail("/characters/" + std::to_string(i) + "/profile", "could not load '" + c.profile + "' (see above)");
      rig->setProfile(std::move(profile.profile));
    }
    for (std::size_t k = 0; k < c.clips.size(); ++k) {
      const auto& [file, clipName] = c.clips[k];
      const std::string where = "/characters/" + std::to_string(i) + "/clips/" + std::to_string(k);
      ImportOptions mo;
      mo.loadMeshes = false;
      mo.extraScale = c.scale;
      ImportResult motion = importAsset(resolve(baseDir, file), mo);
      diags.items.insert(diags.items.end(), motion.diagnostics.items.begin(), motion.diagnostics.items.end());
      if (!motion.ok()) {
        r.fail(where + "/file", "could not load '" + file + "' (see above)");
        continue;
      }
      if (motion.asset->clips.empty()) {
        r.fail(where + "/file", "'" + file + "' has no animation");
        continue;
      }
      const int unmatched = rig->addClip(motion.asset->clips.front(), motion.asset->skeleton, clipName);
      if (unmatched > 0)
        diags.warning(name, where + ": " + std::to_string(unmatched) + " tracks of '" + file +
                                "' name joints the character does not have; they are ignored");
      ++result.assetsLoaded;
    }
    rigs[key] = rig;
    rigOf[i] = rig;
  }
  // Check the clip names before adding anything.
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (!rigOf[i]) continue;
    for (std::size_t k = 0; k < specs[i].play.size(); ++k) {
      PlaySpec& p = specs[i].play[k];
      if (p.clip.empty() && !rigOf[i]->clips().empty()) p.clip = rigOf[i]->clips().front()->clip.name;
      if (!rigOf[i]->findClip(p.clip)) {
        std::string known;
        for (const auto& c : rigOf[i]->clips()) known += (known.empty() ? "" : ", ") + c->clip.name;
        r.fail("/characters/" + std::to_string(i) + "/play" + (specs[i].play.size() > 1 ? "/" + std::to_string(k) : ""),
               "no clip named '" + p.clip + "'; the character has: " + (known.empty() ? "none" : known));
      }
    }
  }
  if (!diags.ok()) return result;

  if (recorded) scene.speech().addBackend(recorded);
  if (!synthesizer) scene.speech().useDefaultSynthesizer(false);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const CharacterSpec& c = specs[i];
    Character* ch = scene.addCharacter(c.name, rigOf[i]);
    ch->setPosition(c.position);
    ch->setHeading(glm::radians(c.headingDegrees));
    if (c.playGiven) {
      for (const PlaySpec& p : c.play) ch->play(p.layer, p.clip, p.options);
    } else if (!rigOf[i]->clips().empty()) {
      ch->play(0, rigOf[i]->clips().front());
    }
    ++result.charactersAdded;
  }
  return result;
}

SceneLoadResult loadSceneFile(const std::string& path, Scene& scene, const SceneLoadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    SceneLoadResult r;
    r.diagnostics.error(path, "cannot open the scene file");
    return r;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  return loadSceneText(ss.str(), path, fs::path(path).parent_path().string(), scene, options);
}

}  // namespace marionette
