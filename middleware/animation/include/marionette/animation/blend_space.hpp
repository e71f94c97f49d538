// Blend spaces: clips placed at points of a 1D or 2D parameter space (speed, or
// speed x direction), blended by the weights of a parameter point, and played as
// one cycle whose clips are time-warped onto a shared phase by their foot
// contacts, so that a walk and a run blended together put their feet down at the
// same moment and do not slide (docs/blend-spaces.md).
//
// Weights. 1D: piecewise linear between the two samples around the point (the
// end sample outside the range). 2D: a Delaunay triangulation of the samples
// (made once, in coordinates scaled by each axis's extent) and the barycentric
// weights of the triangle holding the point; outside the convex hull, those of
// the nearest point of the hull. Either way the weights are >= 0, sum to 1, are
// continuous in the point, exactly one sample has weight 1 at a sample, at most
// 3 samples (2 in 1D) are non-zero, and inside the range or hull the weighted
// mean of the sample points is the point itself (linear precision: a speed x
// direction space whose points are its clips' velocities moves at the velocity asked).
//
// Phase. The space plays a shared phase (cycles). Each clip with usable foot
// contacts (one touchdown per cycle for the left foot and one for the right, from
// detectFootContacts) maps shared phase 0 to its left touchdown and 0.5 to its
// right touchdown, piecewise linearly between them; a clip with the left or right
// touchdown only is shifted so that it lands at 0 (left) or 0.5 (right); a clip
// without (no feet, no contacts, several per foot) plays at plain normalized time,
// shared phase x its duration, as every clip does when phase alignment is off.
// The cycle's duration is the weighted mean of the clips' durations, so the
// phase advances by dt / duration.
//
// Command time (make, validation) allocates; the per-frame queries (weights,
// cycleDuration, clipTime) are noexcept, allocate nothing and are deterministic.
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "marionette/animation/foot_contacts.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct AnimationClip;  // marionette/animation/animation_clip.hpp

// A sample of a definition: a clip by name at a point (y unused in 1D).
struct BlendSpaceSampleDefinition {
  std::string clip;
  float x = 0.0f, y = 0.0f;
};

// A blend space by clip names, as a profile's "blendSpaces" holds it.
struct BlendSpaceDefinition {
  std::string name;
  int dimensions = 1;  // 1 or 2
  std::vector<BlendSpaceSampleDefinition> samples;
  bool phaseAligned = true;  // time-warp the clips by their foot contacts
};

// A sample of a space: a clip and its point.
struct BlendSpaceSample {
  std::shared_ptr<const AnimationClip> clip;
  float x = 0.0f, y = 0.0f;
};

// The feet whose contacts align the cycles; -1 when absent (the clips then play
// at plain normalized time).
struct BlendSpaceFeet {
  int left = -1, right = -1;
  FootContactOptions contacts;  // scaled for the character (footContactOptionsForLeg)
};

// What a definition's points say, before any clip is looked up: "" when it is
// usable, else what is wrong, naming the sample ("blend space 'locomotion':
// samples 0 and 2 are both at (1, 0)"). Checked: a name, 1 or 2 dimensions, 1 to
// kMaxSamples samples (3 in 2D), finite points, no two at one point, and in 2D
// not all on one line.
[[nodiscard]] std::string validateBlendSpaceDefinition(const BlendSpaceDefinition& definition);

class BlendSpace {
 public:
  static constexpr std::size_t kMaxSamples = 64;
  static constexpr std::size_t kMaxActive = 3;  // samples with a weight at any point

  // A key of a clip's time warp: at shared phase `shared` (cycles, in [0, 1)) the
  // clip is at phase `clip` (cycles of the clip, increasing along the keys; may pass 1).
  struct PhaseKey {
    float shared = 0.0f, clip = 0.0f;
  };
  struct Sample {
    std::shared_ptr<const AnimationClip> clip;
    float x = 0.0f, y = 0.0f;
    float duration = 0.0f;        // the clip's, seconds
    std::vector<PhaseKey> keys;   // empty: plain normalized time
    std::vector<ContactInterval> contacts[2];  // left, right, as found (with or without alignment); for tools
  };

  // Makes a space: validates the points (validateBlendSpaceDefinition), the clips
  // (present, of positive finite duration) and the 2D layout, analyses each clip's
  // foot contacts (when `feet` names them), keys the time warps when `phaseAligned`, and
  // triangulates a 2D space. Null with `error`
  // saying why (naming the space and the sample). Command time: allocates.
  [[nodiscard]] static std::shared_ptr<const BlendSpace> make(std::string name, int dimensions,
                                                              std::vector<BlendSpaceSample> samples,
                                                              const Skeleton& skeleton, const BlendSpaceFeet& feet,
                                                              bool phaseAligned, std::string& error);

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] int dimensions() const noexcept { return dimensions_; }
  [[nodiscard]] bool phaseAligned() const noexcept { return phaseAligned_; }
  [[nodiscard]] std::span<const Sample> samples() const noexcept { return samples_; }
  // 2D: the triangles, as sample indices (counter-clockwise in x, y).
  [[nodiscard]] std::span<const std::array<int, 3>> triangles() const noexcept { return triangles_; }

  // The weights of the samples at (x, y) (y ignored in 1D) into out[0, samples().size()).
  // A non-finite coordinate counts as the range's or hull's middle. Per frame: noexcept.
  void weights(float x, float y, std::span<float> out) const noexcept;
  // The cycle's duration for these weights: the weighted mean of the clips' durations (s).
  [[nodiscard]] double cycleDuration(std::span<const float> weights) const noexcept;
  // Sample i's clip time (seconds, unwrapped: whole cycles count) at shared phase
  // `phase` (cycles, unwrapped). The time warp is monotone and continuous across cycles.
  [[nodiscard]] double clipTime(std::size_t sample, double phase) const noexcept;
  // The inverse over one cycle: the shared phase in [0, 1) at which sample i's clip is at
  // clip phase `clipPhase` (cycles; wrapped). For tests and tools.
  [[nodiscard]] double sharedPhase(std::size_t sample, double clipPhase) const noexcept;

 private:
  BlendSpace() = default;
  void weights1D(float x, std::span<float> out) const noexcept;
  void weights2D(float x, float y, std::span<float> out) const noexcept;

  std::string name_;
  int dimensions_ = 1;
  bool phaseAligned_ = true;
  std::vector<Sample> samples_;
  std::vector<int> order1D_;                   // 1D: sample indices by x
  std::vector<std::array<int, 3>> triangles_;  // 2D
  std::vector<std::array<int, 2>> hull_;       // 2D: boundary edges
  float scaleX_ = 1.0f, scaleY_ = 1.0f;        // 2D: 1 / each axis's extent
  float centreX_ = 0.0f, centreY_ = 0.0f;      // what a non-finite coordinate becomes
};

}  // namespace marionette
