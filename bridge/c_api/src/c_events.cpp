// The C API's animation events: mn_scene_set_event_callback and the forwarder's
// onAnimationEvent (docs/bridge.md, docs/animation-events.md).
#include <string>

#include "handles.hpp"

using namespace marionette::capi;

namespace {

mn_animation_event_kind kindOf(marionette::AnimationEventKind kind) noexcept {
  switch (kind) {
    case marionette::AnimationEventKind::FootDown: return MN_ANIMATION_EVENT_FOOT_DOWN;
    case marionette::AnimationEventKind::FootUp: return MN_ANIMATION_EVENT_FOOT_UP;
    case marionette::AnimationEventKind::Marker: break;
  }
  return MN_ANIMATION_EVENT_MARKER;
}

mn_foot_side sideOf(marionette::FootSide side) noexcept {
  switch (side) {
    case marionette::FootSide::Left: return MN_FOOT_LEFT;
    case marionette::FootSide::Right: return MN_FOOT_RIGHT;
    case marionette::FootSide::None: break;
  }
  return MN_FOOT_NONE;
}

}  // namespace

void CallbackForwarder::reserveEventText() {
  // Names longer than this grow the copies once, at their first event.
  eventName_.reserve(128);
  eventClip_.reserve(128);
}

void CallbackForwarder::onAnimationEvent(const marionette::Character& character,
                                         const marionette::AnimationEvent& event) {
  if (!owner_.eventFn) return;
  eventName_.assign(event.name);
  eventClip_.assign(event.clip);
  const mn_animation_event e{kindOf(event.kind), sideOf(event.side), character.name().c_str(), eventName_.c_str(),
                             eventClip_.c_str(), event.layer, event.weight, static_cast<double>(event.clipTime),
                             event.sceneTime};
  owner_.eventFn(owner_.eventUser, &e);
}

mn_status mn_scene_set_event_callback(mn_scene* scene, mn_animation_event_fn fn, void* user) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_event_callback: scene") + notLive(scene));
  return guarded(scene, [&] {
    if (fn) scene->forwarder.reserveEventText();
    scene->eventFn = fn;
    scene->eventUser = user;
    return MN_OK;
  });
}
