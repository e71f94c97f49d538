// Scene files (JSON): characters with their asset, placement and what they play.
//
// {
//   "characters": [
//     { "name": "robot",                      // required, unique
//       "asset": "RobotExpressive.glb",       // required; relative to the scene file, or absolute
//       "position": [0, 0, 0],                // metres (default origin)
//       "heading": 0,                         // degrees about +Y; 0 faces +Z (default)
//       "scale": 1.0,                         // extra length scale on import (e.g. BVH units to metres)
//       "bmlDialect": "smartbody",            // how its BML is read (default: the file's)
//       "clips": [ { "file": "walk.fbx", "name": "walk" } ],  // more clips, bound by joint name,
//       // or retargeted through joint maps, cut to a range, looped (see below):
//       // "clips": [ { "file": "/usr/share/assimp/models/BVH/01_03.bvh", "name": "walk",
//       //              "retarget": { "sourceMap": "cmu_mb.json", "targetMap": "bcn.json", "feetIk": true },
//       //              "range": [0.2, 2.9], "loop": "best" } ],
//       "play": "Walking"                     // a clip name, or a list of layers:
//       // "play": [ { "clip": "Walking", "layer": 0, "weight": 1, "speed": 1, "loop": true,
//       //             "rootMotion": false, "fadeIn": 0, "additive": false, "start": 0 } ]
//       // ("clip" may be left out in a layer: the first clip)
//     } ],
//   "bml": [ { "file": "greet.xml", "time": 1.5, "character": "robot" } ],  // optional
//   "objects": [ { "name": "camera", "position": [0, 1.6, 3] } ],  // optional: places to
//                                            // gaze, point and walk at (Scene::setObject)
//   "bmlDialect": "smartbody",               // optional: how the characters' BML is read
//                                            // ("auto" default, "bml", "smartbody"; a
//                                            // character's own "bmlDialect" comes first)
//   "speech": {                              // optional
//     "lines": [ { "text": "Hello there.", "audio": "hello.wav", "alignment": "hello.phones.txt" } ],
//     "synthesizer": true,                   // false: recorded lines only, never espeak-ng
//     "voices": { "openmary": "en-us", "default": "en-gb" }  // other engines' voice names;
//                                            // "default": for lines naming none or an unknown one
//   }
// }
//
// "clips" entries: "file" (required: the motion, its first clip) and "name" (default:
// the file's clip name). "retarget": true retargets it (retarget/retargeter.hpp)
// with the joint maps guessed from both skeletons, or an object naming joint-map
// files ("sourceMap" for the motion, "targetMap" for the character; each guessed
// when left out, as `marionette retarget` without --src-map / --dst-map) and
// "feetIk" (default true: the source's foot contacts hold; retargeting is done as
// `marionette retarget --ik feet`, with the standing hips reference). Without it
// the clip is bound by joint name (same naming). "range": [start, end] keeps those
// seconds of the source clip (times then start at 0). "loop": "best" keeps, within
// the range (or the clip), the sub-range of 0.8 to 2.6 s (one or two gait cycles)
// whose end pose best matches its start pose (local joint rotations, the root's
// without its yaw and travel), spreads the residual over it so that it loops, and
// turns it to start facing +Z over the rest place: a walk for the locomotion.
// The residual is reported in SceneLoadResult::clips and ::notes. The scene's
// clips are added to the asset before the "profile" is read, so a profile can
// name them ("clips": {"walk": "walk"}).
//
// Errors and warnings name the scene file, line:column and the JSON pointer.
//
// "speech" lines are recorded voice lines (speech/recorded_speech.hpp): a <speech>
// whose text matches one plays it instead of synthesizing. They are read at load.
//
// "bml" lists files to send at scene times; the middleware does not read BML
// (module rule): it resolves the paths and hands the list to whoever drives a
// BML realizer (the `marionette` tool does).
//
// Without "play", a character plays its first clip (or stands in its rest pose).
// Assets are loaded once per (file, scale, profile, clips with all their settings) and shared by the
// characters that use them; meshes are not loaded (a headless scene needs none).
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/asset/asset.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/core/file_reader.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette {

struct SceneLoadOptions {
  bool loadMeshes = false;  // a renderer wants them; a headless run does not
  // Read Assimp's formats in a forked child first (ImportOptions::isolateThirdPartyParsers):
  // for command-line tools that open files from anywhere; never inside an engine's process.
  bool isolateThirdPartyParsers = false;
  // Where every file is read: the scene file, its assets (and their buffers), clips, joint
  // maps, profiles, recorded lines and BML files (ImportOptions::readFile; empty: the disk).
  // With a reader, the "bml" files are read during the load (TimedFile::text).
  FileReader readFile{};
};

struct TimedFile {
  std::string path;       // resolved against the scene file
  double time = 0.0;      // scene time at which to send it
  std::string character;  // empty = the block's characterId or the first character
  std::optional<std::string> text{};  // the file's text when read during the load (a FileReader); else read at send time
};

// A clip a scene file added to a character: where it came from and how it loops.
struct SceneClipInfo {
  std::string where;           // JSON pointer of its "clips" entry
  std::string name;
  float start = 0.0f, end = 0.0f;  // seconds of the source clip kept
  float duration = 0.0f;
  float loopResidual = -1.0f;  // "loop": "best": radians RMS over the joints, end pose against start; else -1
  float loopWorstJoint = 0.0f; // radians
  float loopTurn = 0.0f;       // radians: the root's yaw over the cycle
  float turnedBy = 0.0f;       // radians: the yaw that turned the cycle to face +Z
};

struct SceneLoadResult {
  Diagnostics diagnostics;  // each names the scene file (or asset) and the place
  int charactersAdded = 0;
  int assetsLoaded = 0;
  std::vector<TimedFile> bml;  // the file's "bml" list, sorted by time
  std::vector<SceneClipInfo> clips;  // the clips its "clips" entries made, in file order (per distinct asset)
  std::vector<std::string> notes;    // one line per such clip, for logs and --stats
  // "bmlDialect" per character (its own, else the file's), for whoever drives the realizer
  // (bml::useSceneDialects): {character, "auto" | "bml" | "smartbody"}; none when not given.
  std::vector<std::pair<std::string, std::string>> bmlDialects;
  // The imported asset of each character added, by name: what a renderer draws (meshes,
  // materials, images; with SceneLoadOptions::loadMeshes). Characters made from one file
  // share one asset, as they share one Rig; the rig itself keeps no reference to it.
  std::map<std::string, std::shared_ptr<const Asset>, std::less<>> assets;
  [[nodiscard]] bool ok() const noexcept { return diagnostics.ok(); }
  // The asset of the character `name` added by this load, or null.
  [[nodiscard]] std::shared_ptr<const Asset> assetOf(std::string_view name) const {
    const auto it = assets.find(name);
    return it == assets.end() ? nullptr : it->second;
  }
};

// Adds the file's characters to `scene`. On an error nothing is added.
[[nodiscard]] SceneLoadResult loadSceneFile(const std::string& path, Scene& scene, const SceneLoadOptions& options = {});
// Same, from JSON text; `name` is used in diagnostics and `baseDir` resolves paths.
[[nodiscard]] SceneLoadResult loadSceneText(const std::string& text, const std::string& name, const std::string& baseDir,
                                            Scene& scene, const SceneLoadOptions& options = {});

}  // namespace marionette
