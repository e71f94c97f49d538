// SceneListener: how an engine hears what the runtime does. Every callback has
// a no-op default, so a listener overrides only what it needs. Callbacks come
// from Scene::update (and from the calls that change a scene) on the caller's
// thread, except that with Scene::setThreadCount > 1 callbacks made during
// update() may come from worker threads, one at a time (see scene.hpp); the
// string views are valid only during the call.
#pragma once
#include <string_view>

#include "marionette/scene/animation_event.hpp"
#include "marionette/speech/audio_clip.hpp"
#include "marionette/speech/utterance.hpp"

namespace marionette {

class Character;

enum class LogLevel { Info, Warning, Error };

enum class ChangeKind {
  ClipStarted,   // a clip layer began playing
  ClipStopped,   // a clip layer was stopped or faded out
  Placement,     // position or heading set
};

class SceneListener {
 public:
  virtual ~SceneListener() = default;
  virtual void onCharacterCreated(const Character& /*character*/) {}
  virtual void onCharacterRemoved(const Character& /*character*/) {}
  virtual void onCharacterChanged(const Character& /*character*/, ChangeKind /*kind*/, std::string_view /*what*/) {}
  // BML feedback: a block reached a sync point (e.g. "start", "stroke", "end").
  virtual void onBehaviorProgress(const Character& /*character*/, std::string_view /*blockId*/,
                                  std::string_view /*syncPoint*/, double /*time*/) {}
  // A speech behavior's phoneme starts: its OVR viseme ("PP", "aa", ...; speech/phoneme.hpp),
  // the weight its channel reaches in that phoneme, and the phoneme's start on the scene clock.
  virtual void onViseme(const Character& /*character*/, std::string_view /*viseme*/, float /*weight*/,
                        double /*time*/) {}
  // A speech behavior was realized (at command time, before its start): play
  // `utterance.audio` (or `audioFile`, written when the scene's speech service has an
  // audio directory; empty otherwise) from scene time `sceneStart` to stay in sync.
  virtual void onSpeech(const Character& /*character*/, std::string_view /*behaviorId*/,
                        const speech::Utterance& /*utterance*/, std::string_view /*audioFile*/,
                        double /*sceneStart*/) {}
  // A speech was cut off before its end (BML REPLACE, interrupt, Character::cancelBehavior):
  // stop its audio. `time` is the scene time of the cut; the lips blend out from there.
  virtual void onSpeechStopped(const Character& /*character*/, std::string_view /*behaviorId*/, double /*time*/) {}
  // A sound behavior was realized (at command time, before its start; AsapRealizer's
  // <bmlt:audiofile>, or a request of kind Audio): play `clip` (decoded, every channel),
  // read from `file`, from scene time `sceneStart`. Once per behavior.
  virtual void onAudio(const Character& /*character*/, std::string_view /*behaviorId*/,
                       const speech::AudioClip& /*clip*/, std::string_view /*file*/, double /*sceneStart*/) {}
  // A sound stops before the clip's end: its behavior was cut off (REPLACE, interrupt,
  // Character::cancelBehavior) or ends earlier (a BML end before the clip's). At most once.
  virtual void onAudioStopped(const Character& /*character*/, std::string_view /*behaviorId*/, double /*time*/) {}
  // A script's message at a moment of its performance (BML <event message>, SmartBody's
  // <sbm:event>): a game cue, a sound, a camera cut. `time` is the scene time it was due.
  virtual void onMessage(const Character& /*character*/, std::string_view /*message*/, double /*time*/) {}
  // A clip layer's playhead crossed an event of its clip (a foot down or up, an authored
  // marker), once per crossing, in the order crossed; sent at the end of the character's
  // update, so the frame's pose is written. docs/animation-events.md has the rules.
  virtual void onAnimationEvent(const Character& /*character*/, const AnimationEvent& /*event*/) {}
  virtual void onLog(LogLevel /*level*/, std::string_view /*message*/) {}
};

}  // namespace marionette
