// An animation clip: per-joint translation / rotation / scale tracks, each with
// its own key times, and morph-weight tracks. Interpolation modes follow glTF.
#pragma once
#include <string>
#include <vector>

#include "marionette/core/transform.hpp"

namespace marionette {

enum class Interpolation { Linear, Step, CubicSpline };

// Keys of one property. For CubicSpline, `values` holds three entries per key
// (in-tangent, value, out-tangent), as in glTF; otherwise one per key.
// Times are clip-local seconds, strictly increasing (importers enforce this).
template <class T>
struct Track {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;
  std::vector<T> values;

  [[nodiscard]] bool empty() const noexcept { return times.empty(); }
  [[nodiscard]] std::size_t keyCount() const noexcept { return times.size(); }
};

struct JointTrack {
  int joint = -1;  // index into the skeleton the clip is bound to
  Track<glm::vec3> translation;
  Track<glm::quat> rotation;
  Track<glm::vec3> scale;
};

// Weights of a set of morph targets over time. `targets` are indices into the
// owning asset's morph-target list (Asset::morphTargets). `weights` holds
// targets.size() values per key (three times that for CubicSpline).
struct MorphTrack {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<int> targets;
  std::vector<float> times;
  std::vector<float> weights;
};

// An authored marker on a clip: a name at a clip-local time in [0, duration] (glTF
// animation extras, a profile's "events"; docs/animation-events.md). Played clips send
// it to the listeners when their playhead crosses it (animation_events.hpp).
struct ClipEvent {
  float time = 0.0f;
  std::string name;  // not empty
};

struct Clip {
  std::string name;
  float duration = 0.0f;               // seconds; last key time of any track (0 for a one-key clip)
  std::vector<JointTrack> tracks;      // at most one per joint, sorted by joint index
  std::vector<MorphTrack> morphTracks;
  std::vector<ClipEvent> events;       // authored markers, in time order

  // Empty when valid for a skeleton of `jointCount` joints, else what is wrong.
  [[nodiscard]] std::string validate(std::size_t jointCount) const;
  // Recompute `duration` from the tracks.
  void updateDuration() noexcept;
};

}  // namespace marionette
