// libFuzzer target: authoring action files (marionette_ar/authoring/authoring_actions.hpp: what
// the authoring window records and `marionette-ar author` replays), parsed from memory by
// parseActions. Contract: no crash; a refused text has an error and every diagnostic names the
// file; actions that parse have finite values and a positive, finite modelled time, and writing
// them and reading them back gives the same actions. With MARIONETTE_FUZZ_WRITE_SEED=folder the
// program writes its seed there and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <cmath>

#include "fuzz_support.hpp"
#include "marionette_ar/authoring/authoring_actions.hpp"

using namespace marionette;
using fuzz::require;

namespace {

const char* kSeed = R"({"format": "marionette-actions", "version": 1, "actions": [
  {"do": "pick-character", "name": "bcn"}, {"do": "pick-bml", "file": "wave.xml"},
  {"do": "place", "pixel": [330, 410]}, {"do": "drag", "from": [330, 410], "to": [300, 380], "frame": 90},
  {"do": "rotate", "axes": "local", "plane": "e31", "degrees": 30}, {"do": "height", "metres": 1.75},
  {"do": "exposure", "ev": -0.5}, {"do": "undo"}, {"do": "save"}]})";

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    std::ofstream(std::string(dir) + "/actions.json", std::ios::binary) << kSeed;
    Diagnostics d;
    std::exit(ar::parseActions(kSeed, "seed", d) ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Diagnostics d;
  const std::optional<std::vector<ar::Action>> actions = ar::parseActions(text, "in.json", d);
  if (!actions) {
    fuzz::requireNamedFailure(d, "in.json");
    return 0;
  }
  require(fuzz::allName(d, "in.json"), "a diagnostic does not name the file");
  const ar::Action* previous = nullptr;
  for (const ar::Action& a : *actions) {
    require(std::isfinite(a.value) && std::isfinite(a.pixel.x) && std::isfinite(a.pixel.y) && std::isfinite(a.to.x) &&
                std::isfinite(a.to.y),
            "an action with a value that is not finite");
    const double seconds = ar::modelledSeconds(a, previous);
    require(std::isfinite(seconds) && seconds > 0, "an action without a positive modelled time");
    previous = &a;
  }
  Diagnostics again;
  const auto back = ar::parseActions(ar::formatActions(*actions), "in.json", again);
  require(back.has_value() && back->size() == actions->size(), "what was read does not read back");
  for (std::size_t i = 0; i < actions->size(); ++i) {
    const ar::Action &a = (*actions)[i], &b = (*back)[i];
    require(a.kind == b.kind && a.name == b.name && a.pixel == b.pixel && a.to == b.to && a.value == b.value &&
                a.axes == b.axes && a.plane == b.plane && a.frame == b.frame,
            "an action changed in the round trip");
  }
  return 0;
}
