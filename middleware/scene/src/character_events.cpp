// Animation events of the clip layers: the events of a layer's clip found when it starts
// playing (command time), and those its playhead crossed sent to the listeners at the end
// of each update (frame time: no allocation). docs/animation-events.md has the rules.
#include <algorithm>
#include <cstdio>

#include "character_state.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette {

void Character::State::bindEvents(Layer& layer) {
  layer.eventFrom = layer.eventTo = layer.time;  // nothing crossed before the first update
  layer.events = rig_->events(*layer.clip);
  // A clip from elsewhere than the rig: its own markers (no feet: the rig's profile names
  // them for the rig's clips).
  if (!layer.events && !layer.clip->clip.events.empty())
    layer.events = std::make_shared<const AnimationEventTrack>(layer.clip->clip.duration, layer.clip->clip.events,
                                                               std::span<const ContactInterval>(),
                                                               std::span<const ContactInterval>());
  if (layer.events && layer.events->empty()) layer.events.reset();
}

void Character::State::sendAnimationEvents(double dt) noexcept {
  if (!scene_ || !(dt > 0.0)) return;
  const double frameStart = clock_ - dt;
  for (int index = 0; index < kMaxLayers; ++index) {
    Layer* const found = layers_.find(index);
    if (!found) continue;
    Layer& l = *found;
    if (!l.clip || !l.events || l.eventFrom == l.eventTo) continue;
    const double from = l.eventFrom, to = l.eventTo;
    const AnimationEventTrack* const track = l.events.get();
    // A listener may play another clip on this layer: what is being sent is held from the
    // first crossing on (no reference count is touched on frames that cross nothing), and
    // the layer's remaining crossings are dropped once its clip changed.
    std::shared_ptr<const AnimationEventTrack> heldTrack;
    std::shared_ptr<const AnimationClip> heldClip;
    bool replaced = false;
    const std::uint64_t skipped = track->forEachCrossed(
        from, to, l.options.wrap, [&](const AnimationEventTrack::Event& e, double at) {
          if (replaced || (heldTrack && (l.events != heldTrack || l.clip != heldClip))) {
            replaced = true;
            return;
          }
          if (!heldTrack) heldTrack = l.events, heldClip = l.clip;
          AnimationEvent event;
          event.kind = e.kind;
          event.side = e.side;
          event.name = track->name(e);
          event.clip = heldClip->clip.name;
          event.layer = index;
          event.weight = l.weight;
          event.clipTime = e.time;
          event.sceneTime = frameStart + std::clamp((at - from) / (to - from), 0.0, 1.0) * dt;
          scene_->forEachListener([&](SceneListener& listener) { listener.onAnimationEvent(self_, event); });
        });
    if (skipped > 0 && !replaced) {
      char message[320];  // no allocation on the frame path
      std::snprintf(message, sizeof message,
                    "character '%s' layer %d: clip '%s' looped %llu more times in one update than the %d whose events "
                    "were sent (AnimationEventTrack::kMaxPassesPerFrame); their events were skipped",
                    name_.c_str(), index, heldClip ? heldClip->clip.name.c_str() : "?",
                    static_cast<unsigned long long>(skipped), AnimationEventTrack::kMaxPassesPerFrame);
      scene_->log(LogLevel::Warning, message);
    }
  }
}

}  // namespace marionette
