// libFuzzer target: augmentation files (marionette_ar/authoring/augmentation.hpp: what authoring
// saves and a restore reads), parsed from memory by parseAugmentation. Contract: no crash; a
// refused text has an error and every diagnostic names the file; an augmentation that parses has
// named characters with an asset, finite positions, unit rotors and positive scales, and writing
// it and reading it back gives the same placements, bit for bit. With
// MARIONETTE_FUZZ_WRITE_SEED=folder the program writes its seed there and exits (scripts/fuzz
// seeds the corpus so). Built by scripts/fuzz.
#include <cmath>
#include <cstring>

#include "fuzz_support.hpp"
#include "marionette_ar/authoring/augmentation.hpp"

using namespace marionette;
using fuzz::require;

namespace {

std::string seed() {
  ar::Augmentation a;
  a.tracker.camera = "camera.yml";
  a.tracker.map = "poster.map";
  a.tracker.mapCrc32 = "0a1b2c3d";
  a.environment = "forest.exr";
  ar::PlacedCharacter c;
  c.name = "bcn";
  c.asset = "BCN.x";
  c.bml = "wave.xml";
  c.placement.position = {0.1f, 0.0f, -0.2f};
  c.placement.rotation = ar::ga::rotation(ar::ga::kPlaneY<float>, 0.3f);
  c.placement.scale = 0.5f;
  a.characters.push_back(c);
  return ar::formatAugmentation(a);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    std::ofstream(std::string(dir) + "/augmentation.json", std::ios::binary) << seed();
    Diagnostics d;
    std::exit(ar::parseAugmentation(seed(), "seed", d) ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Diagnostics d;
  const std::optional<ar::Augmentation> a = ar::parseAugmentation(text, "in.json", d);
  if (!a) {
    fuzz::requireNamedFailure(d, "in.json");
    return 0;
  }
  require(fuzz::allName(d, "in.json"), "a diagnostic does not name the file");
  for (const ar::PlacedCharacter& c : a->characters) {
    const ar::Placement& p = c.placement;
    require(!c.name.empty() && !c.asset.empty(), "a character without a name or an asset");
    require(std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z),
            "a position that is not finite");
    require(std::abs(p.rotation.norm() - 1.0f) <= 1e-4f, "a rotor that is not unit");
    require(p.scale > 0 && std::isfinite(p.scale), "a scale that is not positive");
  }
  Diagnostics again;
  const std::optional<ar::Augmentation> b = ar::parseAugmentation(ar::formatAugmentation(*a), "in.json", again);
  require(b.has_value() && b->characters.size() == a->characters.size(), "what was read does not read back");
  for (std::size_t i = 0; i < a->characters.size(); ++i)
    require(std::memcmp(&a->characters[i].placement, &b->characters[i].placement, sizeof(ar::Placement)) == 0,
            "a placement changed in the round trip");
  return 0;
}
