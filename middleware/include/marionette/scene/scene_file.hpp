// Scene files (JSON): characters with their asset, placement and what they play.
//
// {
//   "characters": [
//     { "name": "robot",                      // required, unique
//       "asset": "RobotExpressive.glb",       // required; relative to the scene file, or absolute
//       "position": [0, 0, 0],                // metres (default origin)
//       "heading": 0,                         // degrees about +Y; 0 faces +Z (default)
//       "scale": 1.0,                         // extra length scale on import (e.g. BVH units to metres)
//       "clips": [ { "file": "walk.fbx", "name": "walk" } ],  // more clips, bound by joint name
//       "play": "Walking"                     // a clip name, or a list of layers:
//       // "play": [ { "clip": "Walking", "layer": 0, "weight": 1, "speed": 1, "loop": true,
//       //             "rootMotion": false, "fadeIn": 0, "additive": false, "start": 0 } ]
//       // ("clip" may be left out in a layer: the first clip)
//     } ],
//   "bml": [ { "file": "greet.xml", "time": 1.5, "character": "robot" } ],  // optional
//   "speech": {                              // optional
//     "lines": [ { "text": "Hello there.", "audio": "hello.wav", "alignment": "hello.phones.txt" } ],
//     "synthesizer": true                    // false: recorded lines only, never espeak-ng
//   }
// }
//
// "speech" lines are recorded voice lines (speech/recorded_speech.hpp): a <speech>
// whose text matches one plays it instead of synthesizing. They are read at load.
//
// "bml" lists files to send at scene times; the middleware does not read BML
// (module rule): it resolves the paths and hands the list to whoever drives a
// BML realizer (the `marionette` tool does).
//
// Without "play", a character plays its first clip (or stands in its rest pose).
// Assets are loaded once per (file, scale, clip files) and shared by the
// characters that use them; meshes are not loaded (a headless scene needs none).
#pragma once
#include <string>

#include "marionette/core/diagnostic.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette {

struct SceneLoadOptions {
  bool loadMeshes = false;  // a renderer wants them; a headless run does not
};

struct TimedFile {
  std::string path;       // resolved against the scene file
  double time = 0.0;      // scene time at which to send it
  std::string character;  // empty = the block's characterId or the first character
};

struct SceneLoadResult {
  Diagnostics diagnostics;  // each names the scene file (or asset) and the place
  int charactersAdded = 0;
  int assetsLoaded = 0;
  std::vector<TimedFile> bml;  // the file's "bml" list, sorted by time
  [[nodiscard]] bool ok() const noexcept { return diagnostics.ok(); }
};

// Adds the file's characters to `scene`. On an error nothing is added.
[[nodiscard]] SceneLoadResult loadSceneFile(const std::string& path, Scene& scene, const SceneLoadOptions& options = {});
// Same, from JSON text; `name` is used in diagnostics and `baseDir` resolves paths.
[[nodiscard]] SceneLoadResult loadSceneText(const std::string& text, const std::string& name, const std::string& baseDir,
                                            Scene& scene, const SceneLoadOptions& options = {});

}  // namespace marionette
