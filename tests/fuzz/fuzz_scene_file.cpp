// libFuzzer target: scene files (JSON text: characters, clips, speech lines, BML lists),
// read as loadSceneText reads a file, then one frame. Assets named by the seeds (the
// project's own scenes) resolve against the source tree. Built by scripts/fuzz.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marionette;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  const SceneLoadResult r = loadSceneText(text, "fuzz.json", MARIONETTE_SOURCE_DIR "/assets/scenes", scene);
  // The contract: a failed load names the file and leaves no character behind.
  if (!r.ok()) {
    if (r.diagnostics.items.empty() || r.diagnostics.format().find("fuzz.json") == std::string::npos) {
      bool named = false;  // an asset's own error names the asset instead
      for (const Diagnostic& d : r.diagnostics.items) named = named || !d.file.empty();
      if (!named) __builtin_trap();
    }
    return 0;
  }
  scene.update(1.0 / 30.0);
  for (const auto& c : scene.characters())
    for (float v : c->transformBuffer().skinning())
      if (!std::isfinite(v)) __builtin_trap();
  return 0;
}
