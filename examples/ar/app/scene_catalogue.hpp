// The characters an authoring session can place: the scene's, each measured in its rest pose in
// the scene's frame (height and the middle of its feet) with its profile's "lifeHeight", and the
// BML the scene file offers.
#pragma once
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/authoring/authoring_session.hpp"

namespace marionette::ar {

// One entry per character, in the scene's order, measured on its asset in `loaded` (the
// result of loading the scene, with SceneLoadOptions::loadMeshes); a character `loaded` does
// not know is measured by its rig's joints, with a warning;
// a character without a finite vertex is measured by its skeleton's joints, with a warning;
// one that life size places at the default height (lifeSizeHeight) gets a note saying why.
[[nodiscard]] std::vector<CatalogueEntry> sceneCatalogue(const Scene& scene, const SceneLoadResult& loaded,
                                                         Diagnostics& diagnostics);

}  // namespace marionette::ar
