// AnimationEvent: what SceneListener::onAnimationEvent hears when a clip layer's playhead
// crosses one of its clip's events (animation/animation_events.hpp; the conventions are
// docs/animation-events.md's).
#pragma once
#include <string_view>

#include "marionette/animation/animation_events.hpp"

namespace marionette {

struct AnimationEvent {
  AnimationEventKind kind = AnimationEventKind::Marker;
  FootSide side = FootSide::None;  // which foot, for FootDown and FootUp
  // The marker's name; for feet "left_foot_down", "left_foot_up", "right_foot_down",
  // "right_foot_up". Valid during the call only, as `clip`.
  std::string_view name;
  std::string_view clip;  // the clip's name
  int layer = 0;          // the character's layer that plays it
  float weight = 0.0f;    // the layer's weight this frame (fades included)
  float clipTime = 0.0f;  // the event's own time in the clip, seconds
  double sceneTime = 0.0; // when the playhead crossed it on the scene clock, within the frame
};

}  // namespace marionette
