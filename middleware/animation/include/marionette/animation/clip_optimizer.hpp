// Load-time clip optimization: tracks that never leave the rest pose are
// removed (the joint then takes its rest value, which the sampler writes
// anyway), and tracks that hold one value become one key. Files exported by
// samplers (FBX, BVH) animate every property of every joint; on the Pab walk
// 69 of 75 translation tracks are constant rest values.
//
// The tolerances bound the error per joint-local property; the stats report
// the largest deviation actually dropped, so callers can state it.
#pragma once
#include <cstddef>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct ClipOptimizeOptions {
  float translationTolerance = 1e-5f;  // metres (10 µm)
  float rotationTolerance = 1e-5f;     // radians
  float scaleTolerance = 1e-5f;        // relative
};

struct ClipOptimizeStats {
  int tracksRemoved = 0;       // properties now taken from the rest pose
  int tracksMadeConstant = 0;  // properties reduced to one key
  std::size_t keysBefore = 0, keysAfter = 0;
  float maxTranslationError = 0.0f;  // metres, largest dropped deviation
  float maxRotationError = 0.0f;     // radians
  float maxScaleError = 0.0f;        // relative
};

// Angle in radians between two unit quaternions (q and -q equal), accurate for
// tiny angles (uses the chord, not acos of a dot product near 1).
[[nodiscard]] float rotationAngle(const glm::quat& a, const glm::quat& b) noexcept;

ClipOptimizeStats optimizeClip(Clip& clip, const Skeleton& skeleton, const ClipOptimizeOptions& options = {});

}  // namespace marionette
