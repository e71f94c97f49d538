// Character, bindings: each behavior kind's request bound to its controller at command time
// (the table in character_behaviors.cpp's addBehavior picks one per kind), and the profile's
// idle life started when the character joins a scene.
#include "character_state.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/behavior/procedural_controllers.hpp"
#include "marionette/core/text.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

std::string Character::State::bindLocomotionEntry(BehaviorTimeline::Entry&, std::string&) {
  if (!locomotion_) locomotion_ = std::make_unique<LocomotionController>(locomotionSet_, skeleton(), rig_->joints());
  locomotion_->setSettings(locomotionSettings_);
  ensureScratch();
  return {};
}

std::string Character::State::bindGazeEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  return bindGaze(e, *rig_, targetJointFinder(false), warning);
}

std::string Character::State::bindHeadDirectionEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  std::string why = bindGazeEntry(e, warning);
  // headDirectionShift points the head (with the neck), not the eyes.
  if (GazeState* g = e.as<GazeState>(); why.empty() && g) {
    g->influence = GazeInfluence::Neck;
    g->useEyes = false;
  }
  return why;
}

std::string Character::State::bindHeadEntry(BehaviorTimeline::Entry& e, std::string& warning) { return bindHead(e, *rig_, warning); }

std::string Character::State::bindFaceEntry(BehaviorTimeline::Entry& e, std::string& warning) { return bindFace(e, *rig_, warning); }

std::string Character::State::bindWaitEntry(BehaviorTimeline::Entry&, std::string&) { return {}; }  // nothing to move

std::shared_ptr<const speech::SpokenLine> Character::State::prepareSpeech(const BehaviorRequest& request,
                                                                          Diagnostics& diagnostics) const {
  if (!scene_) {
    diagnostics.error(request.id, "a character outside a scene has no speech service");
    return nullptr;
  }
  std::string warning;
  speech::SpeechService::Result said = scene_->speech().speak(speech::withVoiceNames(speechRequestOf(request, warning), rig_->profile().voices));
  if (!said.line) diagnostics.error(request.id, said.error);
  return said.line;
}

std::shared_ptr<const speech::SpeechService::Preparation> Character::State::prepareSpeechInBackground(
    const BehaviorRequest& request) const {
  if (!scene_) return nullptr;
  std::string warning;  // reported when the behavior is added
  return scene_->speech().prepare(speech::withVoiceNames(speechRequestOf(request, warning), rig_->profile().voices));
}

std::string Character::State::bindSpeechEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  if (!scene_) return "a character outside a scene has no speech service";
  speech::SpeechService::Result said = scene_->speech().speak(speech::withVoiceNames(speechRequestOf(e.request, warning), rig_->profile().voices));
  if (!said.line) return "speech cannot be said: " + said.error;
  const std::shared_ptr<const speech::SpokenLine> line = said.line;
  SpeechState& speech = e.controller.emplace<SpeechState>();
  speech.line = line;
  speech.nextPhoneme = 0;
  // No envelope: the curves start and end at rest, and a blend-in would hide the first phoneme.
  e.blendInEnd = e.request.start();
  e.blendOutStart = e.request.end();
  // Everything below may call listeners, which may add or cancel behaviors (moving `e`): copies only.
  const std::string id = e.request.id;
  const double start = e.request.start(), span = e.request.end() - e.request.start();
  const std::string who = "speech '" + id + "' of '" + name_ + "': ";
  // `warning` is for bad parameters (the realizer reports it so); what the backend repaired
  // or guessed, and a face that cannot move, go to the scene's log.
  if (!line->audioError.empty()) scene_->log(LogLevel::Warning, who + line->audioError);  // no WAV; it still plays
  for (const std::string& w : line->utterance->warnings) scene_->log(LogLevel::Warning, who + w);
  if (std::abs(span - line->utterance->duration) > 0.05) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "the request lasts %.3f s but the line %.3f s (Character::prepareSpeech gives its length)",
                  span, line->utterance->duration);
    scene_->log(LogLevel::Warning, who + buf);
  }
  if (std::string face = speechFaceNote(*rig_); !face.empty()) scene_->log(LogLevel::Info, who + face);
  const std::string audio = line->audioFile.string();
  scene_->forEachListener([&](SceneListener& l) { l.onSpeech(self_, id, *line->utterance, audio, start); });
  return {};
}

std::string Character::State::bindAudioEntry(BehaviorTimeline::Entry& e, std::string&) {
  const AudioParameters* p = e.request.as<AudioParameters>();
  if (!p || !p->clip || p->clip->frames() == 0 || p->clip->sampleRate <= 0)
    return "an audio request needs a clip with samples (AudioParameters::clip, speech/audio_clip.hpp)";
  // The clip plays from the start; a request that ends first cuts it there (the engine is told).
  const double clipEnd = e.request.start() + p->clip->duration();
  AudioState& audio = e.controller.emplace<AudioState>();
  audio.cut = e.request.end() < clipEnd - 1e-9;
  audio.playEnd = audio.cut ? e.request.end() : clipEnd;
  if (!scene_) return {};
  // Listeners may add or cancel behaviors (moving `e`): copies only.
  const std::shared_ptr<const speech::AudioClip> clip = p->clip;
  const std::string id = e.request.id, file = p->file;
  const double start = e.request.start();
  scene_->forEachListener([&](SceneListener& l) { l.onAudio(self_, id, *clip, file, start); });
  return {};
}

TargetJointFinder Character::State::targetJointFinder(bool chest) const {
  // A character named without a joint: its head for a gaze, its chest for a pointing.
  return [this, chest](std::string_view name, std::string_view joint) -> int {
    const Character* c = scene_ ? scene_->findCharacter(name) : nullptr;
    if (!c) return scene_ && scene_->findObject(name) ? (joint.empty() ? -1 : -3) : -2;
    if (!joint.empty()) return c->skeleton().findJoint(joint);
    const RigJoints& j = c->rig().joints();
    return chest ? (!j.spine.empty() ? j.spine.back() : j.hips) : j.head;
  };
}

std::string Character::State::bindPointingEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  PointingState pointing;
  std::string why = bindPointing(e.request, *rig_, skeleton(), targetJointFinder(true), pointing, warning);
  if (why.empty()) e.controller = std::move(pointing);
  return why;
}

std::string Character::State::bindGestureEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  // DEICTIC / POINT with a target is a pointing: the pointing controller aims the arm.
  const GestureParameters* g = e.request.as<GestureParameters>();
  if (g && !g->target.empty() && (equalsIgnoringCase(g->lexeme, "DEICTIC") || equalsIgnoringCase(g->lexeme, "POINT"))) {
    PointingState pointing;
    BehaviorRequest asPointing = e.request;
    asPointing.parameters = PointingParameters{g->target, g->hands};
    std::string why = bindPointing(asPointing, *rig_, skeleton(), targetJointFinder(true), pointing, warning);
    if (why.empty()) e.controller = std::move(pointing);
    return why;
  }
  GestureState gesture;
  std::string why = bindProceduralGesture(e.request, *rig_, skeleton(), gesture, warning);
  if (why.empty()) e.controller = std::move(gesture);
  return why;
}

std::string Character::State::bindReachEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  // A put-down without a place: SmartBody's, 0.2 of the height ahead at 0.6 of it (eye height here).
  if (ReachParameters* p = std::get_if<ReachParameters>(&e.request.parameters);
      p && p->target.empty() && p->action == ReachAction::PutDown) {
    const RigJoints& j = rig_->joints();
    const glm::vec3 ahead = glm::cross(j.leftAxis, glm::vec3(0.0f, 1.0f, 0.0f)) * (0.2f * j.eyeHeight);
    p->target = BehaviorTarget::at(glm::vec3(worldMatrix() * glm::vec4(ahead + glm::vec3(0.0f, 0.6f * j.eyeHeight, 0.0f), 1.0f)));
    warning += std::string(warning.empty() ? "" : "; ") + "put-down without a target: the place in front of the character";
  }
  ReachState reach;
  if (std::string why = bindReach(e.request, *rig_, skeleton(), targetJointFinder(true), reach, warning); !why.empty())
    return why;
  // The arm on the target's side as it stands now (a target character not yet placed: at
  // the first frame), its hand alone on the timeline, and whether the target is too far.
  resolveTarget(reach.target);
  if (reach.target.known()) {
    const glm::vec3 target(glm::inverse(worldMatrix()) * glm::vec4(reach.target.world(), 1.0f));
    chooseReachArm(reach, target, skeleton(), pose_);
    const std::string far = reachDistanceNote(reach, e.request.id, target, reachSettings_, skeleton(), pose_);
    if (!far.empty()) warning += (warning.empty() ? "" : "; ") + far;
  }
  if (reach.side >= 0) e.request.channels = reach.side == 0 ? BodyChannel::LeftHand : BodyChannel::RightHand;
  const ReachTiming timing = reachTiming(e.request, reachSettings_, warning);
  e.blendInEnd = timing.blendInEnd;
  e.blendOutStart = timing.blendOutStart;
  e.request.weight *= timing.peak;
  e.controller = std::move(reach);
  return {};
}

std::string Character::State::bindSaccadeEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  const SaccadeParameters* p = e.request.as<SaccadeParameters>();
  if (p && p->finish) return {};  // persistent and moving nothing: it replaces the running models
  SaccadeState saccade;
  std::string why = bindSaccade(e.request, *rig_, skeleton(), saccade, warning);
  if (why.empty()) e.controller = std::move(saccade);
  return why;
}

namespace {
// An idle-life emitter: bound with a seed of the character's own, then blended in (and over the
// emitter it replaces, or out for a stop) over at least `blend` seconds: nothing pops or snaps.
template <class State, class Bind>
std::string bindIdleEmitter(BehaviorTimeline::Entry& e, const Rig& rig, const std::string& character, double blend,
                            Bind bind, std::string& warning) {
  State state;
  std::string why = bind(e.request, rig, idleLifeSeed(character + "/" + e.request.id), state, warning);
  if (!why.empty()) return why;
  e.controller = std::move(state);
  e.blendInEnd = std::max(e.blendInEnd, e.request.start() + blend);
  e.blendOutStart = std::max(e.blendOutStart, e.blendInEnd);
  return {};
}
}  // namespace

std::string Character::State::bindBlinkEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  // A blink in progress fades in a blink's length; the lids do not snap open.
  return bindIdleEmitter<BlinkState>(e, *rig_, name_, kBlinkSeconds, bindBlink, warning);
}

std::string Character::State::bindBreathingEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  return bindIdleEmitter<BreathingState>(e, *rig_, name_, kBreathingBlendSeconds, bindBreathing, warning);
}

void Character::State::startIdleLife() {
  const IdleLifeProfile& idle = rig_->profile().idleLife;
  auto start = [&](const char* id, BehaviorKind kind, BehaviorParameters parameters) {
    BehaviorRequest r{.id = id, .kind = kind, .syncs = {{"start", clock_}, {"end", clock_}}, .parameters = std::move(parameters)};
    r.persistent = true;
    const BehaviorResult result = addBehavior(std::move(r));
    if (!result.message.empty() && scene_)
      scene_->log(result.realized ? LogLevel::Info : LogLevel::Warning,
                  "character '" + name_ + "': its profile's idleLife " + (kind == BehaviorKind::BlinkEmitter ? "blink" : "breathing") +
                      ": " + result.message);
  };
  if (idle.blink) {
    BlinkParameters p;
    p.meanIntervalSeconds = idle.blinkMeanInterval.value_or(p.meanIntervalSeconds);
    p.variation = idle.blinkVariation.value_or(p.variation);
    start("idleLife:blink", BehaviorKind::BlinkEmitter, p);
  }
  if (idle.breathing) {
    BreathingParameters p;
    p.breathsPerMinute = idle.breathsPerMinute.value_or(p.breathsPerMinute);
    p.amplitudeDegrees = idle.breathingAmplitude.value_or(p.amplitudeDegrees);
    start("idleLife:breathing", BehaviorKind::BreathingEmitter, p);
  }
}

}  // namespace marionette
