// Animation events of the clip and blend-space layers: the events of a layer's clip (or of
// each clip of its space) found when it starts playing (command time), and those its
// playhead crossed sent to the listeners at the end of each update (frame time: no
// allocation). A blend layer sends its heaviest clip's. docs/animation-events.md has the rules.
#include <algorithm>
#include <cstdio>
#include <utility>

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
    if (l.eventFrom == l.eventTo) continue;
    // What the layer plays: a clip and its events, or a blend space's heaviest sample clip.
    const auto playing = [&l]() -> std::pair<const AnimationEventTrack*, const AnimationClip*> {
      if (l.clip) return {l.events.get(), l.clip.get()};
      const BlendSpaceLayer& b = l.blend;
      if (!b.space || b.eventSample >= b.eventTracks.size()) return {nullptr, nullptr};
      return {b.eventTracks[b.eventSample].get(), b.space->samples()[b.eventSample].clip.get()};
    };
    const auto current = playing();  // not a structured binding: lambdas capture it (clang 14)
    const AnimationEventTrack* const track = current.first;
    const AnimationClip* const clip = current.second;
    if (!track || !clip) continue;
    const double from = l.eventFrom, to = l.eventTo;
    // A listener may play another clip (or space) on this layer: what is being sent is held
    // from the first crossing on (no reference count is touched on frames that cross
    // nothing), and the layer's remaining crossings are dropped once what it plays changed.
    std::shared_ptr<const void> heldTrack, heldSource;
    bool replaced = false;
    const std::uint64_t skipped = track->forEachCrossed(
        from, to, l.options.wrap, [&](const AnimationEventTrack::Event& e, double at) {
          if (replaced || (heldTrack && playing() != std::pair{track, clip})) {
            replaced = true;
            return;
          }
          if (!heldTrack) {
            heldTrack = l.clip ? std::shared_ptr<const void>(l.events) : l.blend.eventTracks[l.blend.eventSample];
            heldSource = l.clip ? std::shared_ptr<const void>(l.clip) : std::shared_ptr<const void>(l.blend.space);
          }
          AnimationEvent event;
          event.kind = e.kind;
          event.side = e.side;
          event.name = track->name(e);
          event.clip = clip->clip.name;
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
                    name_.c_str(), index, clip->clip.name.c_str(),
                    static_cast<unsigned long long>(skipped), AnimationEventTrack::kMaxPassesPerFrame);
      scene_->log(LogLevel::Warning, message);
    }
  }
}

}  // namespace marionette
