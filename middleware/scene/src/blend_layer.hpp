// What a character's layer keeps while it plays a blend space (character_blend.cpp):
// the parameter point, its weights, the shared phase and a sampling cursor per clip.
// Sized at play time; the frame only reads and writes it (no allocation).
#pragma once
#include <memory>
#include <vector>

#include "marionette/animation/animation_events.hpp"
#include "marionette/animation/blend_space.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/core/allocator.hpp"

namespace marionette {

struct BlendSpaceLayer {
  std::shared_ptr<const BlendSpace> space;  // null: the layer plays a clip, or nothing
  float x = 0.0f, y = 0.0f;                 // the parameter point
  double phase = 0.0;                       // shared phase, cycles, unwrapped
  RuntimeVector<float> weights;             // per sample, from (x, y)
  RuntimeVector<SamplingCursor> cursors, rootCursors;  // per sample
  // Animation events: each sample clip's track (the rig's; null when it has none), found at
  // play, and the sample whose events this frame sends: the heaviest, as its clip is the one
  // the pose follows most (docs/animation-events.md).
  std::vector<std::shared_ptr<const AnimationEventTrack>> eventTracks;
  std::size_t eventSample = 0;
};

}  // namespace marionette
