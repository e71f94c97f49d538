// An augmentation: the characters an author placed in a tracked scene, with everything needed
// to bring them back from the same spot (docs/authoring.md, "The augmentation file"): the map
// they belong to, the tracker and camera files, each character's asset, placement (position in
// the tracked world, rotor, scale), BML, the exposure and the environment. JSON, versioned.
// Rotations are rotors (4 floats that round-trip bit-exactly), never Euler angles.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/authoring/rotor.hpp"

namespace marionette::ar {

// The character's frame in the tracked world: placementMatrix() = T(position) R S T(-pivot), so the
// asset's point `pivot` (the middle of its feet) stands at `position` and the turns pivot there.
struct Placement {
  glm::vec3 position{0.0f};         // metres, in the tracked world (the target's plane is y = 0)
  ga::Rotor rotation;               // unit
  float scale = 1.0f;               // uniform, on the asset's size in metres (1: its own size)
  glm::vec3 pivot{0.0f};            // metres, in the asset's model space at scale 1
};

// T(position) R S T(-pivot): what the renderer multiplies a character's own world matrix by.
[[nodiscard]] glm::mat4 placementMatrix(const Placement& placement) noexcept;

struct PlacedCharacter {
  std::string name;                 // unique in the file
  std::string asset;                // a character file (relative paths: to the augmentation file)
  std::string bml;                  // optional: the BML block it performs
  Placement placement;
};

struct TrackerReference {
  std::string kind = "markerless";  // "markerless" or "apriltag"
  std::string camera;               // the calibration (OpenCV YAML)
  std::string map;                  // markerless: the map file the placements are in
  std::string mapCrc32;             // its checksum as written (8 hex digits; empty: not checked)
  double tagSize = 0;               // apriltag: metres
};

struct Augmentation {
  static constexpr int kVersion = 1;
  TrackerReference tracker;
  float exposureEv = 0.0f;
  std::string environment;          // optional: an HDR probe
  std::vector<PlacedCharacter> characters;
};

// Errors name the file and the key (`characters[1].rotor`). Relative paths are resolved against
// the file's folder. A newer version, an unknown key (a warning) or a non-unit rotor is said so.
[[nodiscard]] std::optional<Augmentation> readAugmentation(const std::string& path, Diagnostics& diagnostics);
[[nodiscard]] std::optional<Augmentation> parseAugmentation(const std::string& text, const std::string& path,
                                                            Diagnostics& diagnostics);
// The text of an augmentation (paths as they are in memory) and the file; false with an error
// naming the file when it cannot be written.
[[nodiscard]] std::string formatAugmentation(const Augmentation& augmentation);
bool writeAugmentation(const std::string& path, const Augmentation& augmentation, Diagnostics& diagnostics);

}  // namespace marionette::ar
