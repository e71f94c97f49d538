// Between an AR scene file and an augmentation: what authoring records of the scene's tracker,
// paths written relative to the augmentation, and what a restore puts back into the scene.
#pragma once
#include <optional>
#include <string>

#include "ar_scene_file.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/authoring/augmentation.hpp"
#include "marionette_ar/authoring/authoring_session.hpp"

namespace marionette::ar {

// The scene's tracker as an augmentation names it; markerless: the map's checksum read from the
// map file (an error in `diagnostics` names the file and the place when it is not a readable map).
[[nodiscard]] bool trackerReference(const ArTracker& tracker, TrackerReference& out, Diagnostics& diagnostics);

// A new authoring session on `scene` (the AR scene) and `characters` (its middleware scene,
// `loaded` by loadSceneFile with meshes: the characters' assets): the scene's tracker and saved map (both needed: an augmentation belongs to a map),
// its environment and exposure, the characters measured at rest (warnings to stderr). nullopt with
// an error in `diagnostics` naming the scene file and the key (or the map file) otherwise.
[[nodiscard]] std::optional<AuthoringSession> startAuthoring(const ArScene& scene, const Scene& characters,
                                                             const SceneLoadResult& loaded, Diagnostics& diagnostics);

// A copy with every path relative to the folder of `file` (where it will be written), so that a
// folder holding the scene, the map and the augmentation can move.
[[nodiscard]] Augmentation relativeTo(const Augmentation& augmentation, const std::string& file);

// The scene's tracker replaced by the augmentation's (the map it was authored on, checked by its
// checksum), the environment and the exposure by its own. False with errors in `diagnostics`
// naming the augmentation file and the field (and the map file's own, when it is not a readable
// map) and what differs; then `scene` is unchanged.
[[nodiscard]] bool restoreInto(const Augmentation& augmentation, const std::string& augmentationPath, ArScene& scene,
                               Diagnostics& diagnostics);

}  // namespace marionette::ar
