// An authoring session: the augmentation being built, what is picked, and the undo history. The
// windowed UI and the headless replay (`marionette-ar author`) both turn what the user does into
// Actions and apply them here, so a click and a line of an action file have the same effect.
// GL-free: a click is a ray through the camera the caller passes (the tracked pose of the frame
// the user saw), met with the tracked floor, the target's plane y = 0.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "marionette_ar/authoring/augmentation.hpp"
#include "marionette_ar/authoring/authoring_actions.hpp"
#include "marionette_ar/authoring/life_size.hpp"

namespace marionette::ar {

// A character the session can place: one of the scene's, measured in its rest pose.
struct CatalogueEntry {
  std::string name;
  std::string asset;
  float heightMetres = 1.0f;  // rest-pose height at scale 1 (the asset's own size, metres)
  glm::vec3 pivot{0.0f};      // the middle of its feet: the lowest point under its centre, model space
  std::optional<float> profileLifeHeight{};  // its profile's "lifeHeight" (metres), if it gives one

  // The height it stands at when placed (lifeSizeHeight's rule), and the note when the rule fell
  // back on the default height.
  [[nodiscard]] LifeSize lifeSize() const { return lifeSizeHeight(name, asset, heightMetres, profileLifeHeight); }
};

// The camera a click is seen through: OpenGL view and projection, and the pixel size of the
// image the click's coordinates are in (x right, y down from the top-left corner).
struct AuthoringView {
  glm::mat4 view{1.0f}, projection{1.0f};
  int width = 0, height = 0;
  bool tracked = false;  // false: no pose (LOST), a click meets no floor
};

// Where the ray through `pixel` meets the floor y = 0 in front of the camera; nullopt when the
// view is not tracked, the ray runs parallel to the floor or meets it behind the camera or
// further than `maxDistance` metres (a click on the horizon).
[[nodiscard]] std::optional<glm::vec3> floorPoint(const AuthoringView& view, glm::vec2 pixel,
                                                  float maxDistance = 50.0f) noexcept;

class AuthoringSession {
 public:
  // `base` brings the tracker, the environment and the starting exposure; its characters, if
  // any, are there from the start (a session reopened on a saved augmentation).
  AuthoringSession(Augmentation base, std::vector<CatalogueEntry> catalogue);

  // Applies one action seen through `view`. False with an error in `diagnostics` saying why
  // (nothing changes), e.g. a click off the floor, a turn with nothing placed, an undo with no
  // history. The session does not know where the action came from (a click, an action file):
  // the error's `file` is empty, and the caller names the file and the action.
  bool apply(const Action& action, const AuthoringView& view, Diagnostics& diagnostics);

  [[nodiscard]] const Augmentation& augmentation() const noexcept { return current_.augmentation; }
  [[nodiscard]] const std::vector<CatalogueEntry>& catalogue() const noexcept { return catalogue_; }
  // The picked catalogue entry (-1: none) and its placed character in augmentation() (-1: not placed).
  [[nodiscard]] int pickedEntry() const noexcept { return current_.picked; }
  [[nodiscard]] int pickedCharacter() const noexcept;
  [[nodiscard]] const std::string& pickedBml() const noexcept { return current_.bml; }
  [[nodiscard]] std::size_t undoDepth() const noexcept { return history_.size(); }
  // Saves asked for so far (the caller writes the file when apply() of a Save returns true).
  [[nodiscard]] int saves() const noexcept { return saves_; }

 private:
  struct State {
    Augmentation augmentation;
    int picked = -1;
    std::string bml;
  };
  PlacedCharacter* placed();
  State current_;
  std::vector<CatalogueEntry> catalogue_;
  std::vector<State> history_;
  int saves_ = 0;
};

}  // namespace marionette::ar
