#include "marionette/core/text_file.hpp"
#include "marionette/scene_file/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marionette/rig/detail/json_places.hpp"
#include "marionette/animation/cycle.hpp"
#include "marionette/animation/clip_binding.hpp"
#include "marionette/io/import.hpp"
#include "marionette/retarget/retarget_metrics.hpp"
#include "marionette/retarget/retargeter.hpp"
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

// One entry of a character's "clips".
struct ClipSpec {
  std::string file, name;
  bool retarget = false;               // through joint maps, not by joint name
  std::string sourceMap, targetMap;    // joint-map files; "" = guessed
  bool feetIk = true;                  // retargeting holds the source's foot contacts
  bool hasRange = false;
  float range[2] = {0.0f, 0.0f};       // seconds of the source clip
  bool loopBest = false;               // "loop": "best"
  std::string where;                   // JSON pointer of the entry
};

struct CharacterSpec {
  std::string name, asset, profile;  // profile: a character profile JSON ("" = guessed)
  glm::vec3 position{0.0f};
  float headingDegrees = 0.0f;
  float scale = 1.0f;
  std::vector<ClipSpec> clips;
  std::vector<PlaySpec> play;
  bool playGiven = false;
  std::string bmlDialect;  // "" = the file's
};


// Reads typed members and reports "<file>:12:7: error: /characters/2/position: expected ..."
// (line:column of the value the JSON pointer names, when the text has it).
class Reader {
 public:
  Reader(Diagnostics& d, std::string file, const std::string& text) : diags_(d), file_(std::move(file)), lines_(text), places_(text) {}
  void fail(const std::string& where, const std::string& what) {
    const auto [line, column] = place(where);
    diags_.error(file_, where + ": " + what, line, column);
  }
  void warn(const std::string& where, const std::string& what) {
    const auto [line, column] = place(where);
    diags_.warning(file_, where + ": " + what, line, column);
  }
  [[nodiscard]] std::pair<int, int> place(const std::string& where) const {
    std::string pointer = where == "/" ? "" : where;
    for (;;) {  // the value, else its nearest enclosing value that has a place
      const std::ptrdiff_t at = places_.value(pointer);
      if (at >= 0) return lines_.at(at);
      const auto slash = pointer.rfind('/');
      if (pointer.empty() || slash == std::string::npos) return {0, 0};
      pointer.resize(slash);
    }
  }

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
      if (ok) continue;
      const std::string pointer = where + "/" + json_detail::JsonPlaces::escape(it.key());
      const std::ptrdiff_t at = places_.key(pointer);
      const auto [line, column] = at >= 0 ? lines_.at(at) : place(pointer);
      diags_.warning(file_, pointer + ": unknown key '" + it.key() + "' ignored", line, column);
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
  LineIndex lines_;
  json_detail::JsonPlaces places_;
};

// A "clips" entry: {"file", "name", "retarget", "range", "loop"}.
bool readClip(Reader& r, const Json& j, const std::string& w, ClipSpec& c) {
  c.where = w;
  if (!j.is_object() || !j.contains("file")) {
    r.fail(w, "expected {\"file\": PATH, \"name\": NAME}");
    return false;
  }
  r.unknownKeys(j, w, {"file", "name", "retarget", "range", "loop", "comment"});
  bool ok = r.string(j["file"], w + "/file", c.file);
  if (j.contains("name")) ok &= r.string(j["name"], w + "/name", c.name);
  if (j.contains("retarget")) {
    const Json& rt = j["retarget"];
    const std::string wr = w + "/retarget";
    if (rt.is_boolean()) {
      c.retarget = rt.get<bool>();
    } else if (rt.is_object()) {
      c.retarget = true;
      r.unknownKeys(rt, wr, {"sourceMap", "targetMap", "feetIk"});
      if (rt.contains("sourceMap")) ok &= r.string(rt["sourceMap"], wr + "/sourceMap", c.sourceMap);
      if (rt.contains("targetMap")) ok &= r.string(rt["targetMap"], wr + "/targetMap", c.targetMap);
      if (rt.contains("feetIk")) ok &= r.boolean(rt["feetIk"], wr + "/feetIk", c.feetIk);
    } else {
      r.fail(wr, "expected true, false or {\"sourceMap\": PATH, \"targetMap\": PATH, \"feetIk\": true}");
      ok = false;
    }
  }
  if (j.contains("range")) {
    const Json& range = j["range"];
    if (!range.is_array() || range.size() != 2) {
      r.fail(w + "/range", "expected [start, end] in seconds of the source clip");
      ok = false;
    } else if (r.number(range[0], w + "/range/0", c.range[0], 0.0f, 1e6f) &&
               r.number(range[1], w + "/range/1", c.range[1], 0.0f, 1e6f)) {
      if (!(c.range[1] > c.range[0])) {
        r.fail(w + "/range", "the end must come after the start");
        ok = false;
      }
      c.hasRange = true;
    } else {
      ok = false;
    }
  }
  if (j.contains("loop")) {
    const Json& loop = j["loop"];
    if (loop.is_string() && loop.get<std::string>() == "best") c.loopBest = true;
    else if (!(loop.is_boolean() && !loop.get<bool>())) {
      r.fail(w + "/loop", "expected \"best\" (the best-looping gait cycle within the range) or false");
      ok = false;
    }
  }
  return ok;
}

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

// The BML dialect names (bml::dialectFromName reads the same; the middleware does not read
// BML, so it only checks the name and hands it on: SceneLoadResult::bmlDialects).
bool readBmlDialect(Reader& r, const Json& j, const std::string& where, std::string& out) {
  if (!r.string(j, where, out)) return false;
  for (const char* known : {"auto", "bml", "smartbody"})
    if (out == known) return true;
  r.fail(where, "\"" + out + "\" is not a BML dialect (auto, bml or smartbody)");
  return false;
}

bool readCharacter(Reader& r, const Json& j, const std::string& where, CharacterSpec& c) {
  if (!j.is_object()) return r.fail(where, "expected an object with \"name\" and \"asset\""), false;
  r.unknownKeys(j, where, {"name", "asset", "profile", "position", "heading", "scale", "clips", "play", "bmlDialect"});
  bool ok = true;
  if (!j.contains("name")) ok = false, r.fail(where, "missing \"name\"");
  else ok &= r.string(j["name"], where + "/name", c.name);
  if (!j.contains("asset")) ok = false, r.fail(where, "missing \"asset\" (path of a character file)");
  else ok &= r.string(j["asset"], where + "/asset", c.asset);
  if (j.contains("profile")) ok &= r.string(j["profile"], where + "/profile", c.profile);
  if (j.contains("position")) ok &= r.vec3(j["position"], where + "/position", c.position);
  if (j.contains("heading")) ok &= r.number(j["heading"], where + "/heading", c.headingDegrees, -1e6f, 1e6f);
  if (j.contains("scale")) ok &= r.number(j["scale"], where + "/scale", c.scale, 1e-6f, 1e6f);
  if (j.contains("bmlDialect")) ok &= readBmlDialect(r, j["bmlDialect"], where + "/bmlDialect", c.bmlDialect);
  if (j.contains("clips")) {
    const Json& clips = j["clips"];
    if (!clips.is_array()) return r.fail(where + "/clips", "expected an array of {\"file\", \"name\"}"), false;
    for (std::size_t i = 0; i < clips.size(); ++i) {
      ClipSpec spec;
      if (readClip(r, clips[i], where + "/clips/" + std::to_string(i), spec)) c.clips.push_back(std::move(spec));
      else ok = false;
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
// A joint map for a scene clip: the file's (resolved against the scene), or the guess.
std::optional<retarget::JointMap> sceneJointMap(Reader& r, Diagnostics& diags, const std::string& baseDir,
                                                const std::string& file, const Asset& asset, const std::string& where,
                                                const std::string& what, const FileReader& files) {
  retarget::JointMapResult m =
      file.empty() ? retarget::guessJointMap(asset) : retarget::loadJointMap(resolve(baseDir, file), asset, files);
  diags.items.insert(diags.items.end(), m.diagnostics.items.begin(), m.diagnostics.items.end());
  if (!m.diagnostics.ok()) {
    r.fail(where, file.empty() ? "no usable joint map guessed for the " + what + " (see above); name one"
                               : "could not use the joint map '" + file + "' for the " + what + " (see above)");
    return std::nullopt;
  }
  return std::move(m.map);
}

// Frames per second of a clip's keys (its densest rotation track), 60 without keys.
float keyRate(const Clip& clip) {
  float rate = 0.0f;
  for (const JointTrack& t : clip.tracks)
    if (t.rotation.keyCount() > 1 && t.rotation.times.back() > t.rotation.times.front())
      rate = std::max(rate, static_cast<float>(t.rotation.keyCount() - 1) / (t.rotation.times.back() - t.rotation.times.front()));
  return rate > 0.0f ? std::min(rate, 240.0f) : 60.0f;
}

// One "clips" entry, bound to `target`'s skeleton: by joint name, or retargeted;
// cut to its range; the best loop within it. Errors name the entry's place.
std::optional<Clip> loadSceneClip(Reader& r, Diagnostics& diags, const std::string& baseDir, float scale,
                                  const ClipSpec& k, const Asset& target, const SceneLoadOptions& options,
                                  SceneLoadResult& result) {
  ImportOptions mo;
  mo.loadMeshes = false;
  mo.isolateThirdPartyParsers = options.isolateThirdPartyParsers;
  mo.readFile = options.readFile;
  mo.extraScale = k.retarget ? 1.0f : scale;  // retargeting scales by the legs, whatever the source's units
  ImportResult motion = importAsset(resolve(baseDir, k.file), mo);
  diags.items.insert(diags.items.end(), motion.diagnostics.items.begin(), motion.diagnostics.items.end());
  if (!motion.ok()) {
    r.fail(k.where + "/file", "could not load '" + k.file + "' (see above)");
    return std::nullopt;
  }
  const Asset& source = *motion.asset;
  if (source.clips.empty()) {
    r.fail(k.where + "/file", "'" + k.file + "' has no animation");
    return std::nullopt;
  }
  const Clip& sourceClip = source.clips.front();
  if (k.hasRange && k.range[1] > sourceClip.duration + 1e-3f) {
    std::ostringstream m;
    m << "the range [" << k.range[0] << ", " << k.range[1] << "] s ends after the clip of '" << k.file << "' ("
      << sourceClip.duration << " s)";
    r.fail(k.where + "/range", m.str());
    return std::nullopt;
  }
  Clip clip;
  float grounded = 0.0f;
  if (k.retarget) {
    const auto sourceMap = sceneJointMap(r, diags, baseDir, k.sourceMap, source,
                                         k.where + (k.sourceMap.empty() ? "/retarget" : "/retarget/sourceMap"),
                                         "source '" + k.file + "'", options.readFile);
    const auto targetMap = sceneJointMap(r, diags, baseDir, k.targetMap, target,
                                         k.where + (k.targetMap.empty() ? "/retarget" : "/retarget/targetMap"),
                                         "character", options.readFile);
    if (!sourceMap || !targetMap) return std::nullopt;
    retarget::RetargetOptions ro;
    // A character's rest pose stands on its ground, wherever its origin is
    // (BCN_Epileptic's is at its pelvis): the standing reference is found as if
    // its rest feet stood on y = 0, which standingHipsReference requires.
    Skeleton standing = target.skeleton;
    {
      const std::vector<glm::mat4> rest = standing.restModelMatrices();
      float low = INFINITY;
      for (retarget::Bone b : {retarget::Bone::LeftFoot, retarget::Bone::RightFoot, retarget::Bone::LeftToes,
                               retarget::Bone::RightToes})
        if (const int j = targetMap->joint(b); j >= 0 && j < static_cast<int>(rest.size()))
          low = std::min(low, rest[static_cast<std::size_t>(j)][3].y);
      if (std::isfinite(low)) standing.rootTransform[3].y -= low;
    }
    ro.sourceHipsReference = retarget::standingHipsReference(source.skeleton, *sourceMap, sourceClip, standing, *targetMap);
    ro.ik.feet = k.feetIk;
    const retarget::Retargeter bound = retarget::Retargeter::bind(source.skeleton, *sourceMap, target.skeleton, *targetMap, ro);
    if (!bound.valid()) {
      std::string why;
      for (const std::string& n : bound.notes()) why += (why.empty() ? "" : "; ") + n;
      r.fail(k.where + "/retarget", "cannot retarget '" + k.file + "' onto the character: " + why);
      return std::nullopt;
    }
    clip = bound.retargetClip(sourceClip);
    // The feet come down to the character's rest ground (legs that bend otherwise float).
    std::vector<int> feet;
    for (retarget::Bone b : {retarget::Bone::LeftFoot, retarget::Bone::RightFoot, retarget::Bone::LeftToes,
                             retarget::Bone::RightToes})
      if (targetMap->joint(b) >= 0) feet.push_back(targetMap->joint(b));
    grounded = groundClip(clip, target.skeleton, feet, targetMap->joint(retarget::Bone::Hips));
  } else {
    int unmatched = 0;
    clip = bindClipByName(sourceClip, source.skeleton, target.skeleton, &unmatched);
    if (unmatched > 0)
      r.warn(k.where, std::to_string(unmatched) + " tracks of '" + k.file +
                          "' name joints the character does not have; they are ignored");
  }
  SceneClipInfo info;
  info.where = k.where;
  info.name = k.name.empty() ? sourceClip.name : k.name;
  info.start = k.hasRange ? k.range[0] : 0.0f;
  info.end = k.hasRange ? k.range[1] : clip.duration;
  if (k.loopBest) {
    const LoopMatch loop = findBestLoop(clip, target.skeleton, info.start, info.end);
    if (!loop.found) {
      std::ostringstream m;
      m << "\"loop\": \"best\" needs a range of at least " << LoopSearchOptions{}.minDuration << " s of animation";
      r.fail(k.where + (k.hasRange ? "/range" : "/loop"), m.str());
      return std::nullopt;
    }
    info.start = loop.start;
    info.end = loop.end;
    info.loopResidual = loop.residual;
    info.loopWorstJoint = loop.worstJoint;
    info.loopTurn = loop.turn;
  }
  if (k.hasRange || k.loopBest) clip = cutClip(clip, target.skeleton, info.start, info.end, keyRate(clip));
  if (k.loopBest) info.turnedBy = closeLoop(clip, target.skeleton);
  clip.name = info.name;
  info.duration = clip.duration;
  {
    std::ostringstream m;
    m.precision(3);
    m << k.where << ": clip '" << info.name << "' from " << k.file << (k.retarget ? " (retargeted)" : "") << ", "
      << info.start << " to " << info.end << " s";
    if (k.loopBest)
      m << "; best loop: residual " << glm::degrees(info.loopResidual) << " deg RMS (worst joint "
        << glm::degrees(info.loopWorstJoint) << " deg), turning " << glm::degrees(info.loopTurn)
        << " deg per cycle; turned by " << glm::degrees(info.turnedBy) << " deg to face +Z";
    if (k.retarget) m << "; lowered by " << -grounded << " to the rest ground";
    result.notes.push_back(m.str());
  }
  result.clips.push_back(std::move(info));
  return clip;
}

}  // namespace

SceneLoadResult loadSceneText(const std::string& text, const std::string& name, const std::string& baseDir,
                              Scene& scene, const SceneLoadOptions& options) {
  SceneLoadResult result;
  Diagnostics& diags = result.diagnostics;
  Json doc;  // syntax errors, NUL bytes and numbers too large for a double are errors naming the place
  if (!json_detail::parseJsonText(name, text, doc, diags)) return result;
  Reader r(diags, name, text);
  if (!doc.is_object() || !doc.contains("characters") || !doc["characters"].is_array()) {
    r.fail("/", "expected an object with a \"characters\" array");
    return result;
  }
  r.unknownKeys(doc, "", {"characters", "comment", "bml", "speech", "bmlDialect", "objects"});
  std::string fileDialect;
  if (doc.contains("bmlDialect")) (void)readBmlDialect(r, doc["bmlDialect"], "/bmlDialect", fileDialect);
  // Recorded voice lines: read now (errors name the line), added to the scene's speech below.
  std::shared_ptr<speech::RecordedSpeech> recorded;
  bool synthesizer = true;
  std::map<std::string, std::string> voiceNames;
  if (doc.contains("speech")) {
    const Json& sp = doc["speech"];
    if (!sp.is_object()) {
      r.fail("/speech", "expected {\"lines\": [{\"text\", \"audio\", \"alignment\"}], \"synthesizer\": true}");
    } else {
      r.unknownKeys(sp, "/speech", {"lines", "synthesizer", "voices", "comment"});
      if (sp.contains("synthesizer")) r.boolean(sp["synthesizer"], "/speech/synthesizer", synthesizer);
      if (sp.contains("voices")) {  // other engines' voice names to the synthesizer's
        const Json& v = sp["voices"];
        if (!v.is_object()) r.fail("/speech/voices", "expected an object of VOICE NAME: voice (\"openmary\": \"en-us\")");
        for (auto it = v.begin(); v.is_object() && it != v.end(); ++it) {
          std::string voice;
          const std::string where = "/speech/voices/" + it.key();
          if (!r.string(*it, where, voice)) continue;
          if (it.key().empty() || voice.empty()) {
            r.fail(where, "expected a non-empty voice name for a non-empty key");
            continue;
          }
          voiceNames[it.key()] = voice;
        }
      }
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
            recorded->addLine(lineText, audio.empty() ? fs::path() : fs::path(resolve(baseDir, audio)), resolve(baseDir, alignment),
                            options.readFile);
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
        if (options.readFile) {  // the engine's files are read now, while its reader is at hand
          std::string bml;
          if (!readTextFile(options.readFile, t.path, bml, result.diagnostics, "cannot read the BML file")) continue;
          t.text = std::move(bml);
        }
        result.bml.push_back(std::move(t));
      }
      std::stable_sort(result.bml.begin(), result.bml.end(),
                       [](const TimedFile& a, const TimedFile& b) { return a.time < b.time; });
    }
  }
  // Named places behaviors aim at and walk to (Scene::setObject): {"name", "position"}.
  std::vector<std::pair<std::string, glm::vec3>> objects;
  std::set<std::string> objectNames;
  if (doc.contains("objects")) {
    const Json& list = doc["objects"];
    if (!list.is_array()) r.fail("/objects", "expected an array of {\"name\", \"position\": [x, y, z]}");
    for (std::size_t i = 0; list.is_array() && i < list.size(); ++i) {
      const std::string where = "/objects/" + std::to_string(i);
      const Json& e = list[i];
      if (!e.is_object() || !e.contains("name") || !e.contains("position")) {
        r.fail(where, "expected {\"name\": NAME, \"position\": [x, y, z]}");
        continue;
      }
      r.unknownKeys(e, where, {"name", "position", "comment"});
      std::string objectName;
      glm::vec3 position(0.0f);
      if (!r.string(e["name"], where + "/name", objectName) || !r.vec3(e["position"], where + "/position", position)) continue;
      if (!objectNames.insert(objectName).second) {
        r.fail(where + "/name", "an object named '" + objectName + "' exists already in this file");
        continue;
      }
      objects.emplace_back(std::move(objectName), position);
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
    if (objectNames.count(c.name)) {  // a target naming it would be ambiguous
      r.fail(where + "/name", "'" + c.name + "' names an object of this file too");
      continue;
    }
    specs.push_back(std::move(c));
  }
  if (!diags.ok()) return result;
  for (const CharacterSpec& c : specs) {
    const std::string& dialect = c.bmlDialect.empty() ? fileDialect : c.bmlDialect;
    if (!dialect.empty()) result.bmlDialects.push_back({c.name, dialect});
  }

  // Load each distinct (asset, scale, profile, clips with their settings) once.
  std::map<std::string, std::shared_ptr<const Rig>> rigs;
  std::vector<std::shared_ptr<const Rig>> rigOf(specs.size());
  std::map<std::string, std::shared_ptr<const Asset>> assets;  // by the same key: what the rig was made from
  std::vector<std::shared_ptr<const Asset>> assetOf(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const CharacterSpec& c = specs[i];
    std::string key = resolve(baseDir, c.asset) + "|" + std::to_string(c.scale) + "|" + resolve(baseDir, c.profile);
    for (const ClipSpec& k : c.clips) {
      key += "|" + resolve(baseDir, k.file) + "#" + k.name;
      if (k.retarget)
        key += "#retarget:" + (k.sourceMap.empty() ? "" : resolve(baseDir, k.sourceMap)) + ":" +
               (k.targetMap.empty() ? "" : resolve(baseDir, k.targetMap)) + (k.feetIk ? ":feet" : ":noik");
      if (k.hasRange) key += "#range:" + std::to_string(k.range[0]) + ":" + std::to_string(k.range[1]);
      if (k.loopBest) key += "#loop:best";
    }
    if (auto it = rigs.find(key); it != rigs.end()) {
      rigOf[i] = it->second;
      assetOf[i] = assets[key];
      continue;
    }
    ImportOptions io;
    io.loadMeshes = options.loadMeshes;
    io.isolateThirdPartyParsers = options.isolateThirdPartyParsers;
    io.readFile = options.readFile;
    io.extraScale = c.scale;
    ImportResult imported = importAsset(resolve(baseDir, c.asset), io);
    diags.items.insert(diags.items.end(), imported.diagnostics.items.begin(), imported.diagnostics.items.end());
    if (!imported.ok()) {
      r.fail("/characters/" + std::to_string(i) + "/asset", "could not load '" + c.asset + "' (see above)");
      continue;
    }
    ++result.assetsLoaded;
    auto asset = std::make_shared<Asset>(std::move(*imported.asset));
    // The scene's clips join the asset's before the rig wraps them and the profile
    // is read, so that a profile can name them ("clips": {"walk": ...}).
    for (const ClipSpec& k : c.clips) {
      if (auto clip = loadSceneClip(r, diags, baseDir, c.scale, k, *asset, options, result)) {
        asset->clips.push_back(std::move(*clip));
        ++result.assetsLoaded;
      }
    }
    auto rig = std::make_shared<Rig>(*asset);
    if (!c.profile.empty()) {
      CharacterProfileResult profile = loadCharacterProfile(resolve(baseDir, c.profile), *asset, options.readFile);
      diags.items.insert(diags.items.end(), profile.diagnostics.items.begin(), profile.diagnostics.items.end());
      if (!profile.diagnostics.ok()) r.fail("/characters/" + std::to_string(i) + "/profile", "could not load '" + c.profile + "' (see above)");
      rig->setProfile(std::move(profile.profile));
    }
    rigs[key] = rig;
    rigOf[i] = rig;
    assets[key] = asset;
    assetOf[i] = asset;
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
  if (!voiceNames.empty()) scene.speech().setVoiceNames(voiceNames);
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
    result.assets.emplace(c.name, assetOf[i]);
    ++result.charactersAdded;
  }
  for (auto& [objectName, position] : objects) scene.setObject(std::move(objectName), position);
  return result;
}

SceneLoadResult loadSceneFile(const std::string& path, Scene& scene, const SceneLoadOptions& options) {
  std::string text;
  if (SceneLoadResult r; !readTextFile(options.readFile, path, text, r.diagnostics, "cannot read the scene file"))
    return r;
  return loadSceneText(text, path, fs::path(path).parent_path().string(), scene, options);
}

}  // namespace marionette
