// Life size: the height a humanoid stands at when an authoring session places it (docs/authoring.md
// "Life size"). A character file's own size is often not the character's: RobotExpressive's file
// is 4.46 m tall, and placed at its own size it would tower over a poster on the floor.
#pragma once
#include <optional>
#include <string>

namespace marionette::ar {

// A character file whose rest pose is this tall (metres, ends included) is taken at its own size.
inline constexpr float kPersonHeightMinMetres = 0.5f;
inline constexpr float kPersonHeightMaxMetres = 2.5f;
// The height of a humanoid neither its profile nor its file gives a plausible height for.
inline constexpr float kDefaultLifeHeightMetres = 1.7f;

struct LifeSize {
  enum class From { Profile, File, Default };
  float metres = kDefaultLifeHeightMetres;  // its height standing life size
  From from = From::Default;
  // Default only: why, for the user (the authoring window and `marionette-ar author --json`);
  // empty otherwise.
  std::string note;
};

// The rule, in order: the profile's "lifeHeight" when it gives one (a finite height above 0; the
// profile loader keeps it in [0.05, 20] m); else the file's own height `fileHeightMetres` when a
// person could be that tall, in [kPersonHeightMinMetres, kPersonHeightMaxMetres] (then the
// character keeps scale 1); else kDefaultLifeHeightMetres, with a note naming the character
// `name` and its file `asset` (a path; its file name is shown), the file's height and the fix.
[[nodiscard]] LifeSize lifeSizeHeight(const std::string& name, const std::string& asset, float fileHeightMetres,
                                      std::optional<float> profileLifeHeightMetres);

}  // namespace marionette::ar
