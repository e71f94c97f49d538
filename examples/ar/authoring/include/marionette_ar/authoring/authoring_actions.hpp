// The operations of an authoring session, as data: what a click, a drag, a slider or a key does in
// the authoring UI is one Action, and a file of them replays the same session headless
// (`marionette-ar author`, docs/authoring.md "Actions"). Each action also has a modelled time, the
// Keystroke-Level Model's estimate of how long a user takes to perform it.
//
// {
//   "format": "marionette-actions", "version": 1,
//   "actions": [
//     { "do": "pick-character", "name": "bcn" },           // from the scene's characters
//     { "do": "pick-bml", "file": "../bml/wave.xml" },     // what the picked character performs
//     { "do": "place", "pixel": [330, 410] },              // a click on the tracked floor
//     { "do": "drag", "from": [330, 410], "to": [300, 380] },  // move it over the floor
//     { "do": "rotate", "axes": "global", "plane": "e31", "degrees": 30 },  // or "local"; e23, e31, e12
//     { "do": "height", "metres": 1.75 },                  // life size (slider)
//     { "do": "exposure", "ev": -0.5 },                    // slider
//     { "do": "undo" },
//     { "do": "save" }
//   ]
// }
//
// Pixels are in the camera image (x right, y down, from its top-left corner). Any action may say
// "frame": N, the camera frame it happens at; without it, the replay shows the frame the session
// has reached by the modelled times of the actions before it. A plane is named as a bivector
// (docs/authoring.md: e23 turns about x, e31 about y, e12 about z); a step is an angle in one plane,
// never a set of Euler angles.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/authoring/rotor.hpp"

namespace marionette::ar {

enum class ActionKind { PickCharacter, PickBml, Place, Drag, Rotate, Height, Exposure, Undo, Save };

enum class RotationPlane { E23, E31, E12 };

struct Action {
  ActionKind kind = ActionKind::Save;
  std::string name{};            // PickCharacter: the character; PickBml: the file (resolved)
  glm::vec2 pixel{0.0f};         // Place: the click; Drag: where it starts
  glm::vec2 to{0.0f};            // Drag: where it ends
  ga::Axes axes = ga::Axes::Global;
  RotationPlane plane = RotationPlane::E31;
  float value = 0.0f;            // Rotate: degrees; Height: metres; Exposure: EV
  long frame = -1;               // the camera frame it happens at; -1: by the modelled clock
};

// "pick-character", "place", ... as the file spells them.
[[nodiscard]] const char* actionName(ActionKind kind) noexcept;
[[nodiscard]] const char* planeName(RotationPlane plane) noexcept;  // "e23", "e31", "e12"
[[nodiscard]] ga::Bivector<float> planeBivector(RotationPlane plane) noexcept;

// The UI's fixed rotation step (a key or a button): a rotate action by a whole number of these
// is modelled as key presses, any other angle as a free drag.
inline constexpr float kRotationStepDegrees = 15.0f;

// Seconds a user takes for `action` (docs/authoring.md "Time model"): the Keystroke-Level Model's
// operators (Card, Moran and Newell): M 1.35 s to decide, P 1.1 s to point, B 0.1 s a mouse
// button press or release, K 0.28 s a key. `previous` is the action before it (nullptr for the
// first): repeating the same rotation step costs a key press, without a new decision.
[[nodiscard]] double modelledSeconds(const Action& action, const Action* previous) noexcept;

// Errors name the file, the action's index and the key (`actions[3].pixel`); relative paths
// resolve against the file's folder. An unknown key is a warning.
[[nodiscard]] std::optional<std::vector<Action>> parseActions(const std::string& text, const std::string& path,
                                                              Diagnostics& diagnostics);
[[nodiscard]] std::optional<std::vector<Action>> readActions(const std::string& path, Diagnostics& diagnostics);
// The file text for a list of actions (what the windowed UI records of a session).
[[nodiscard]] std::string formatActions(const std::vector<Action>& actions);

}  // namespace marionette::ar
