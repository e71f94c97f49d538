#include "marionette/scene/character.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/procedural_controllers.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

void FrameScratch::reserve(std::size_t joints) {
  if (pose.size() >= joints) return;
  pose.resize(joints);
  accumulator.reset(joints);
}

Character::Character(std::string name, std::shared_ptr<const Rig> rig) : name_(std::move(name)), rig_(std::move(rig)) {
  const Skeleton& s = rig_->skeleton();
  pose_ = s.restPose;
  buffer_.resize(s.jointCount(), rig_->asset().morphTargets.size());
  morphScratch_.resize(rig_->asset().morphTargets.size());
}

void Character::notify(ChangeKind kind, std::string_view what) const {
  if (scene_) scene_->forEachListener([&](SceneListener& l) { l.onCharacterChanged(*this, kind, what); });
}

void Character::setPosition(const glm::vec3& p) noexcept {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    if (scene_) scene_->log(LogLevel::Warning, "setPosition: non-finite position rejected");
    return;
  }
  position_ = p;
  notify(ChangeKind::Placement, "position");
}

void Character::setHeading(float radians) noexcept {
  if (!std::isfinite(radians)) {
    if (scene_) scene_->log(LogLevel::Warning, "setHeading: non-finite heading rejected");
    return;
  }
  heading_ = std::remainder(radians, 6.28318530718f);
  notify(ChangeKind::Placement, "heading");
}

glm::mat4 Character::worldMatrix() const noexcept {
  Transform t;
  t.translation = position_;
  t.rotation = glm::angleAxis(heading_, glm::vec3(0, 1, 0));
  return t.matrix();
}

bool Character::play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options) {
  if (layer < 0 || layer >= kMaxLayers || !clip) {
    if (scene_) scene_->log(LogLevel::Warning, "play: layer out of range or no clip; nothing started");
    return false;
  }
  Layer& l = layers_[layer];
  const std::size_t n = skeleton().jointCount();
  l.clip = std::move(clip);
  l.options = options;
  if (!l.options.jointMask.empty()) l.options.jointMask.resize(n, 0.0f);
  l.time = std::isfinite(options.startTime) ? options.startTime : 0.0;
  const float target = std::isfinite(options.weight) ? std::max(0.0f, options.weight) : 0.0f;
  l.options.weight = target;
  if (!std::isfinite(l.options.speed)) l.options.speed = 1.0f;
  if (options.fadeIn > 0.0f && std::isfinite(options.fadeIn)) {
    l.weight = 0.0f;
    l.fadeRate = target / options.fadeIn;
  } else {
    l.weight = target;
    l.fadeRate = 0.0f;
  }
  l.stopping = false;
  l.cursor.reset(l.clip->clip);
  l.rootCursor.reset(l.clip->inPlaceRoot);
  if (!scratch_) {  // a character outside a scene blends in its own scratch (allocated here, at command time)
    ownScratch_ = std::make_unique<FrameScratch>();
    scratch_ = ownScratch_.get();
  }
  scratch_->reserve(n);
  if (options.additive) {
    l.reference.resize(n);
    sampleClip(l.clip->clip, 0.0f, skeleton().restPose, l.reference);
  }
  notify(ChangeKind::ClipStarted, l.clip->clip.name);
  return true;
}

bool Character::play(int layer, std::string_view clipName, const PlayOptions& options) {
  auto clip = rig_->findClip(clipName);
  if (!clip) {
    if (scene_) scene_->log(LogLevel::Warning, "play: no clip of that name in the character's rig");
    return false;
  }
  return play(layer, std::move(clip), options);
}

void Character::stop(int layer, float fadeOut) {
  if (layer < 0 || layer >= kMaxLayers || !layers_[layer].clip) return;
  Layer& l = layers_[layer];
  if (fadeOut > 0.0f && std::isfinite(fadeOut)) {
    l.stopping = true;
    l.fadeRate = -std::max(l.weight, 1e-6f) / fadeOut;
    return;
  }
  notify(ChangeKind::ClipStopped, l.clip->clip.name);
  l.clip.reset();
}

int Character::layerCount() const noexcept {
  int n = 0;
  for (const Layer& l : layers_) n += l.clip ? 1 : 0;
  return n;
}

double Character::layerTime(int layer) const noexcept {
  return (layer >= 0 && layer < kMaxLayers) ? layers_[layer].time : 0.0;
}

BehaviorResult Character::addBehavior(BehaviorRequest request) {
  BehaviorResult result;
  result.message = behaviors_.check(request);
  std::shared_ptr<const AnimationClip> clip;
  if (result.message.empty() && !request.clip.empty()) {
    clip = rig_->findClip(request.clip);
    if (!clip) {
      result.message = "behavior request '" + request.id + "': the character's rig has no clip named '" + request.clip + "'";
      if (!rig_->clips().empty()) {
        result.message += " (it has";
        for (std::size_t i = 0; i < rig_->clips().size() && i < 8; ++i)
          result.message += (i ? ", '" : " '") + rig_->clips()[i]->clip.name + "'";
        result.message += rig_->clips().size() > 8 ? ", ...)" : ")";
      }
    }
  }
  if (result.message.empty() && request.kind == BehaviorKind::Clip && request.clip.empty())
    result.message = "behavior request '" + request.id + "' is of kind clip but names no clip";
  if (!result.message.empty()) {
    if (scene_) scene_->log(LogLevel::Warning, result.message);
    return result;
  }
  const BehaviorKind kind = request.kind;
  // A locomotion lasts until the character arrives: its entry stays until a later one replaces it.
  std::shared_ptr<LocomotionPlan> plan;
  std::string locomotionWarning;
  if (kind == BehaviorKind::Locomotion) {
    std::string why = bindLocomotion(request, plan, locomotionWarning);
    if (!why.empty()) {
      result.message = std::move(why);
      if (scene_) scene_->log(LogLevel::Warning, "behavior request '" + request.id + "': " + result.message);
      return result;
    }
    request.persistent = true;
  }
  BehaviorTimeline::Entry& e = behaviors_.add(std::move(request));
  result.added = true;
  if (clip) {
    const std::size_t n = skeleton().jointCount();
    e.mask.assign(n, 0.0f);
    // The in-place tracks count: they move joints the clip may hold at rest (IK feet beside the root).
    for (const Clip* c : {&clip->clip, &clip->inPlaceRoot})
      for (const JointTrack& t : c->tracks)
        if (t.joint >= 0 && static_cast<std::size_t>(t.joint) < n &&
            (!t.translation.empty() || !t.rotation.empty() || !t.scale.empty()))
          e.mask[static_cast<std::size_t>(t.joint)] = 1.0f;
    // Gestures play on the upper body, over the posture and the locomotion.
    if (kind == BehaviorKind::Gesture || kind == BehaviorKind::Pointing) {
      e.upperBody = true;
      const std::vector<float> upper = upperBodyMask();
      if (!upper.empty())
        for (std::size_t i = 0; i < n; ++i) e.mask[i] *= upper[i];
    }
    e.cursor.reset(clip->clip);
    e.rootCursor.reset(clip->inPlaceRoot);
    e.clip = std::move(clip);
    if (!scratch_) {
      ownScratch_ = std::make_unique<FrameScratch>();
      scratch_ = ownScratch_.get();
    }
    scratch_->reserve(n);
    result.realized = true;
    // A pointing clip shapes the hand; with a target the arm is aimed over it.
    if (kind == BehaviorKind::Pointing && !e.request.parameter("target").empty()) {
      std::string warning;
      const std::string why = bindPointingEntry(e, warning);
      result.message = why.empty() ? warning : why + "; the clip plays without aiming";
    }
  } else if (kind == BehaviorKind::Wait) {
    result.realized = true;  // nothing to move
  } else if (kind == BehaviorKind::Locomotion) {
    e.locomotion = std::move(plan);
    if (!locomotion_) locomotion_ = std::make_unique<LocomotionController>(locomotionSet_, skeleton(), rig_->joints());
    locomotion_->setSettings(locomotionSettings_);
    if (!scratch_) {
      ownScratch_ = std::make_unique<FrameScratch>();
      scratch_ = ownScratch_.get();
    }
    scratch_->reserve(skeleton().jointCount());
    result.realized = true;
    result.message = std::move(locomotionWarning);
  } else if (kind == BehaviorKind::Pointing) {
    std::string warning;
    const std::string why = bindPointingEntry(e, warning);
    result.realized = why.empty();
    result.message = why.empty() ? warning : why;
  } else if (kind == BehaviorKind::Gaze || kind == BehaviorKind::GazeShift ||
             kind == BehaviorKind::HeadDirectionShift) {
    std::string warning;
    const std::string why = bindGaze(e, *rig_, targetJointFinder(false), warning);
    // headDirectionShift points the head (with the neck), not the eyes.
    if (kind == BehaviorKind::HeadDirectionShift && why.empty()) {
      e.gaze.influence = GazeInfluence::Neck;
      e.gaze.useEyes = false;
    }
    result.realized = why.empty();
    result.message = why.empty() ? warning : why;
  } else if (kind == BehaviorKind::Head || kind == BehaviorKind::FaceLexeme || kind == BehaviorKind::FaceFacs ||
             kind == BehaviorKind::Face || kind == BehaviorKind::FaceShift) {
    std::string warning;
    const std::string why = kind == BehaviorKind::Head ? bindHead(e, *rig_, warning) : bindFace(e, *rig_, warning);
    result.realized = why.empty();
    result.message = why.empty() ? warning : why;
  } else if (kind == BehaviorKind::Speech) {
    std::string warning;
    const std::string why = bindSpeechEntry(e, warning);
    result.realized = why.empty();
    result.message = why.empty() ? warning : why;
  } else {
    result.message = "no controller for " + std::string(toString(kind)) +
                     " behaviors exists yet; its timing, channel and feedback run but the body does not move";
  }
  return result;
}

std::shared_ptr<const speech::SpokenLine> Character::prepareSpeech(const BehaviorRequest& request,
                                                                   std::string& error) const {
  if (!scene_) {
    error = "a character outside a scene has no speech service";
    return nullptr;
  }
  std::string warning;
  speech::SpeechService::Result said = scene_->speech().speak(speechRequestOf(request, warning));
  error = said.line ? std::string() : said.error;
  return said.line;
}

std::shared_ptr<const speech::SpeechService::Preparation> Character::prepareSpeechInBackground(
    const BehaviorRequest& request) const {
  if (!scene_) return nullptr;
  std::string warning;  // reported when the behavior is added
  return scene_->speech().prepare(speechRequestOf(request, warning));
}

std::string Character::bindSpeechEntry(BehaviorTimeline::Entry& e, std::string& warning) {
  if (!scene_) return "a character outside a scene has no speech service";
  speech::SpeechService::Result said = scene_->speech().speak(speechRequestOf(e.request, warning));
  if (!said.line) return "speech cannot be said: " + said.error;
  const std::shared_ptr<const speech::SpokenLine> line = said.line;
  e.speech.line = line;
  e.speech.nextPhoneme = 0;
  e.isSpeech = true;
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
  scene_->forEachListener([&](SceneListener& l) { l.onSpeech(*this, id, *line->utterance, audio, start); });
  return {};
}

TargetJointFinder Character::targetJointFinder(bool chest) const {
  // A character named without a joint: its head for a gaze, its chest for a pointing.
  return [this, chest](std::string_view name, std::string_view joint) -> int {
    const Character* c = scene_ ? scene_->findCharacter(name) : nullptr;
    if (!c) return -2;
    if (!joint.empty()) return c->skeleton().findJoint(joint);
    const RigJoints& j = c->rig().joints();
    return chest ? (!j.spine.empty() ? j.spine.back() : j.hips) : j.head;
  };
}

std::string Character::bindPointingEntry(BehaviorTimeline::Entry& e, std::string& warning) const {
  const std::string why = bindPointing(e.request, *rig_, skeleton(), targetJointFinder(true), e.pointing, warning);
  e.isPointing = why.empty();
  return why;
}

std::vector<float> Character::upperBodyMask() const {
  // The first spine joint and everything above it; empty when the profile has no spine.
  const RigJoints& j = rig_->joints();
  const int root = !j.spine.empty() ? j.spine.front() : j.neck;
  if (root < 0) return {};
  const Skeleton& s = skeleton();
  std::vector<float> mask(s.jointCount(), 0.0f);
  mask[static_cast<std::size_t>(root)] = 1.0f;
  for (std::size_t i = static_cast<std::size_t>(root) + 1; i < s.jointCount(); ++i)
    if (s.parents[i] >= 0 && mask[static_cast<std::size_t>(s.parents[i])] > 0.0f) mask[i] = 1.0f;
  return mask;
}

const LocomotionSet& Character::locomotionSet() const {
  if (!locomotionSet_) locomotionSet_ = std::make_shared<const LocomotionSet>(makeLocomotionSet(*rig_));
  return *locomotionSet_;
}

void Character::setLocomotionSettings(const LocomotionSettings& settings) noexcept {
  locomotionSettings_ = settings;
  if (locomotion_) locomotion_->setSettings(settings);
}

std::string Character::bindLocomotion(const BehaviorRequest& request, std::shared_ptr<LocomotionPlan>& plan,
                                      std::string& warning) const {
  const LocomotionSet& set = locomotionSet();
  if (!set.usable()) {
    std::string why = "the character has no walk clip it can travel with (set \"walk\" in its profile)";
    for (const std::string& n : set.notes) why += "; " + n;
    return why;
  }
  plan = std::make_shared<LocomotionPlan>();
  std::string why = parseLocomotionPlan(request, set, locomotionSettings_, *plan, warning);
  if (!why.empty()) return why;
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (!plan->targetCharacter.empty()) {
    const Character* target = scene_ ? scene_->findCharacter(plan->targetCharacter) : nullptr;
    if (!target) return "locomotion target: the scene has no character '" + plan->targetCharacter + "'";
    if (target == this) return "locomotion target: a character cannot walk to itself";
    return {};
  }
  // The destination as seen from here: warn about the implausible ones, still go.
  const glm::vec2 here(position_.x, position_.z);
  const float distance = glm::length(plan->waypoints.back() - here);
  char buf[200];
  if (distance < 0.1f && plan->waypoints.size() == 1) {
    std::snprintf(buf, sizeof buf, "locomotion target is inside the character (%.3f m from its root); it stays and only turns to the facing",
                  static_cast<double>(distance));
    note(buf);
  } else if (distance > 1000.0f) {
    std::snprintf(buf, sizeof buf, "locomotion target is %.1f km away; at %.2f m/s that takes %.0f min",
                  static_cast<double>(distance) / 1000.0, static_cast<double>(plan->speed),
                  static_cast<double>(distance / plan->speed / 60.0f));
    note(buf);
  }
  return {};
}

std::optional<double> Character::estimateLocomotion(const BehaviorRequest& request) const {
  std::shared_ptr<LocomotionPlan> plan;
  std::string warning;
  if (!bindLocomotion(request, plan, warning).empty()) return std::nullopt;
  SteeringState from;
  from.position = {position_.x, position_.z};
  from.heading = heading_;
  glm::vec2 target(0.0f);
  std::span<const glm::vec2> waypoints = plan->waypoints;
  if (!plan->targetCharacter.empty()) {
    const Character* t = scene_ ? scene_->findCharacter(plan->targetCharacter) : nullptr;
    if (t) target = {t->position().x, t->position().z};
    waypoints = std::span<const glm::vec2>(&target, 1);
  }
  return estimateLocomotionSeconds(from, *plan, waypoints, locomotionSettings_);
}

LocomotionStatus Character::locomotionStatus(std::string_view id) const noexcept {
  LocomotionStatus st;
  const BehaviorTimeline::Entry* e = behaviors_.find(id);
  if (!e || !e->locomotion) return st;
  if (!locomotion_ || e->order > locomotionOrder_) st.state = LocomotionStatus::kPending;
  else if (e->order < locomotionOrder_) st.state = LocomotionStatus::kSuperseded;
  else if (locomotion_->moving()) st.state = LocomotionStatus::kMoving;
  else {
    st.state = LocomotionStatus::kDone;
    st.doneTime = locomotion_->doneTime();
  }
  return st;
}

bool Character::cancelBehavior(std::string_view id, double blendOut) {
  const std::vector<std::string> stopped = speechStoppedBy(id, false);
  const bool known = behaviors_.cancel(id, clock_, blendOut);
  notifySpeechStopped(stopped);
  return known;
}

std::size_t Character::cancelBehaviors(std::string_view idPrefix, double blendOut) {
  const std::vector<std::string> stopped = speechStoppedBy(idPrefix, true);
  const std::size_t n = behaviors_.cancelPrefix(idPrefix, clock_, blendOut);
  notifySpeechStopped(stopped);
  return n;
}

std::vector<std::string> Character::speechStoppedBy(std::string_view id, bool prefix) const {
  // Speech whose audio the engine was told to play and that has not ended yet.
  std::vector<std::string> ids;
  for (const BehaviorTimeline::Entry& e : behaviors_.entries())
    if (e.isSpeech && !e.cancelled() && clock_ < e.request.end() &&
        (prefix ? std::string_view(e.request.id).substr(0, id.size()) == id : e.request.id == id))
      ids.push_back(e.request.id);
  return ids;
}

void Character::notifySpeechStopped(const std::vector<std::string>& ids) const {
  if (!scene_) return;
  for (const std::string& id : ids)
    scene_->forEachListener([&](SceneListener& l) { l.onSpeechStopped(*this, id, clock_); });
}

void Character::applyBehaviors(float dt) noexcept {
  // Fixed order (DESIGN.md): clip behaviors (postures) over the layers, locomotion,
  // upper-body gestures, then gaze, head movements added on top of it, pointing
  // (after the gaze has turned the torso, so the arm aims from where it ends up),
  // then face expressions.
  const bool timing = scene_ && scene_->statsEnabled();
  auto run = [&](CharacterStats::Controller which, auto&& pass) {
    const auto start = timing ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    if (pass()) stats_.controllerUsed[which] = true;
    if (timing)
      stats_.controllerMicros[which] =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  };
  run(CharacterStats::kClipBehaviors, [&] { return applyBehaviorClips(false); });
  if (locomotion_) run(CharacterStats::kLocomotion, [&] { return applyLocomotion(dt); });
  if (applyBehaviorClips(true)) stats_.controllerUsed[CharacterStats::kClipBehaviors] = true;
  const glm::mat4 worldToModel = glm::inverse(worldMatrix());  // gaze and pointing targets
  run(CharacterStats::kGaze, [&] {
    bool any = false;
    for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
      if (!e.isGaze) continue;
      const float w = BehaviorTimeline::weightAt(e, clock_);
      if (w <= 0.0f) continue;
      const SpatialTarget& t = e.gaze.target;  // a target that has left the scene: hold the direction
      updateGaze(e.gaze, glm::vec3(worldToModel * glm::vec4(t.world(), 1.0f)), t.known(), w, gazeSettings_,
                 skeleton(), rig_->joints(), pose_, dt);
      any = true;
    }
    return any;
  });
  run(CharacterStats::kHead, [&] {
    bool any = false;
    for (const BehaviorTimeline::Entry& e : behaviors_.entries()) {
      if (e.clip || e.strokes.empty()) continue;
      if (const float w = BehaviorTimeline::weightAt(e, clock_); w > 0.0f) {
        applyHead(e, w, clock_, *rig_, pose_);
        any = true;
      }
    }
    return any;
  });
  run(CharacterStats::kPointing, [&] {
    bool any = false;
    for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
      if (!e.isPointing) continue;
      if (const float w = BehaviorTimeline::weightAt(e, clock_); w > 0.0f) {
        const SpatialTarget& t = e.pointing.target;
        updatePointing(e.pointing, glm::vec3(worldToModel * glm::vec4(t.world(), 1.0f)), t.known(), w,
                       pointingSettings_, skeleton(), pose_);
        any = true;
      }
    }
    return any;
  });
  run(CharacterStats::kFace, [&] {
    bool any = false;
    const std::span<float> morphs = buffer_.writeMorphWeights();
    for (const BehaviorTimeline::Entry& e : behaviors_.entries()) {
      if (e.morphs.empty()) continue;
      if (const float w = BehaviorTimeline::weightAt(e, clock_); w > 0.0f) {
        applyFace(e, w, morphs);
        any = true;
      }
    }
    return any;
  });
  run(CharacterStats::kSpeech, [&] { return applySpeechEntries(); });
}

bool Character::applySpeechEntries() noexcept {
  bool any = false;
  // Overlapping speech on one character: the one added last of those speaking now moves the
  // lips (a speech that could not be said takes nothing from the others).
  const BehaviorTimeline::Entry* voice = nullptr;
  for (const BehaviorTimeline::Entry& e : behaviors_.entries())
    if (e.isSpeech && clock_ >= e.request.start() && clock_ < e.finishTime()) voice = &e;
  std::array<float, speech::kLipChannelCount> channels{};
  const std::span<float> morphs = buffer_.writeMorphWeights();
  for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (!e.isSpeech) continue;
    const double local = clock_ - e.request.start();
    // Visemes of the phonemes that started by now, once each, also for a line whose lips another
    // owns (the engine hears it) and for phonemes a long frame stepped over; not those after
    // the line was cut off.
    const std::vector<speech::Phoneme>& phonemes = e.speech.line->utterance->phonemes;
    const double cutoff = e.finishTime() - e.request.start();
    while (e.speech.nextPhoneme < phonemes.size() && phonemes[e.speech.nextPhoneme].start <= local &&
           phonemes[e.speech.nextPhoneme].start < cutoff) {
      const speech::Phoneme& p = phonemes[e.speech.nextPhoneme++];
      e.speech.line->curves.evaluate(0.5 * (p.start + p.end), channels);
      const float peak = channels[static_cast<std::size_t>(p.cls.viseme)];
      scene_->forEachListener([&](SceneListener& l) {
        l.onViseme(*this, speech::visemeName(p.cls.viseme), peak, e.request.start() + p.start);
      });
    }
    if (&e != voice) continue;
    if (const float w = BehaviorTimeline::weightAt(e, clock_); w > 0.0f) {
      applySpeech(e.speech, w, local, *rig_, channels, morphs, pose_);
      any = true;
    }
  }
  return any;
}

void Character::resolveExternalTargets() noexcept {
  if (!scene_) return;
  for (BehaviorTimeline::Entry& e : behaviors_.entries())
    if (e.locomotion && e.order >= locomotionOrder_ && !e.locomotion->targetCharacter.empty())
      if (const Character* t = scene_->findCharacter(e.locomotion->targetCharacter)) e.resolvedTarget = t->position();
  auto resolve = [this](SpatialTarget& target) {
    if (!target.external()) return;
    const Character* t = scene_->findCharacter(target.character);
    target.resolvedKnown = t != nullptr;
    if (!t) return;
    const auto models = t->transformBuffer().modelMatrices();
    const auto j = static_cast<std::size_t>(target.jointIndex);
    target.resolvedPoint = target.jointIndex >= 0 && j < models.size()
                               ? glm::vec3(t->worldMatrix() * models[j][3])
                               : t->position() + glm::vec3(0.0f, 1.6f, 0.0f);
  };
  for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (e.isGaze) resolve(e.gaze.target);
    if (e.isPointing) resolve(e.pointing.target);
  }
}

bool Character::applyLocomotion(float dt) noexcept {
  // Follow the newest locomotion request that has started; stop when it is cancelled.
  bool cancelled = false;
  for (const BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (!e.locomotion || e.request.start() > clock_) continue;
    if (e.order > locomotionOrder_) {
      locomotion_->start(e.locomotion, position_, heading_);
      locomotionOrder_ = e.order;
    }
    if (e.order != locomotionOrder_) continue;
    if (!e.locomotion->targetCharacter.empty()) locomotion_->setTargetPosition(e.resolvedTarget);
    if (e.cancelled() && clock_ >= e.cancelAt) cancelled = true;
  }
  if (cancelled && locomotion_->moving()) locomotion_->stop();
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(pose_.size());
  locomotion_->update(dt, clock_, position_, heading_, skeleton(), pose_, scratch);
  return true;
}

bool Character::applyBehaviorClips(bool upperBody) noexcept {
  bool any = false;
  const std::span<const Transform> rest = skeleton().restPose;
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(rest.size());
  const std::span<float> morphs = buffer_.writeMorphWeights();
  for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (!e.clip || e.upperBody != upperBody) continue;
    const float w = BehaviorTimeline::weightAt(e, clock_);
    if (w <= 0.0f) continue;
    const AnimationClip& ac = *e.clip;
    const double start = e.request.start(), span = e.request.end() - start;
    const float t = e.request.loop || span <= 0.0
                        ? wrapClipTime(clock_ - start, ac.clip.duration, e.request.loop ? WrapMode::Loop : WrapMode::Clamp)
                        : static_cast<float>(std::clamp((clock_ - start) / span, 0.0, 1.0) * ac.clip.duration);
    sampleClip(ac.clip, t, rest, scratch, &e.cursor);
    // A clip that travels is played in place: behaviors do not move the character.
    if (!ac.rootMotion.empty()) sampleClipTracks(ac.inPlaceRoot, t, scratch, &e.rootCursor);
    blendOver(pose_, scratch, w, e.mask);
    any = true;
    if (!ac.clip.morphTracks.empty() && !morphs.empty()) {
      std::copy(morphs.begin(), morphs.end(), morphScratch_.begin());
      sampleMorphWeights(ac.clip, t, morphScratch_);
      for (std::size_t i = 0; i < morphs.size(); ++i) morphs[i] += w * (morphScratch_[i] - morphs[i]);
    }
  }
  return any;
}

void Character::sampleLayer(Layer& layer, std::span<Transform> out) noexcept {
  const AnimationClip& ac = *layer.clip;
  const float t = layer.clipTime;
  sampleClip(ac.clip, t, skeleton().restPose, out, &layer.cursor);
  if (layer.options.rootMotion && !ac.rootMotion.empty()) sampleClipTracks(ac.inPlaceRoot, t, out, &layer.rootCursor);
  if (layer.options.additive) makeAdditiveDelta(out, layer.reference, out);
}

void Character::blendLayers() noexcept {
  // Normal layers are summed one at a time through the scratch pose, then the
  // additive layers are applied in order on the result (as blendPoses does).
  const std::span<const Transform> rest = skeleton().restPose;
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(rest.size());
  scratch_->accumulator.reset(rest.size());  // no allocation: sized at play time
  for (Layer& l : layers_) {
    if (!l.clip || l.options.additive) continue;
    sampleLayer(l, scratch);
    scratch_->accumulator.addNormal(scratch, l.weight, l.options.jointMask, rest);
  }
  scratch_->accumulator.finish(rest, pose_);
  for (Layer& l : layers_) {
    if (!l.clip || !l.options.additive) continue;
    sampleLayer(l, scratch);
    applyAdditive(scratch, l.weight, l.options.jointMask, pose_);
  }
}

void Character::applyRootMotion(const Layer& layer, double t0, double t1, float weight, glm::vec3& move,
                                float& turn) const noexcept {
  const RootMotion& rm = layer.clip->rootMotion;
  if (!layer.options.rootMotion || rm.empty() || t0 == t1) return;
  glm::vec3 d;
  float y;
  if (t1 > t0) {
    rm.between(t0, t1, layer.options.wrap, d, y);
  } else {  // backwards: the inverse of the forward motion from t1 to t0
    rm.between(t1, t0, layer.options.wrap, d, y);
    d = glm::angleAxis(-y, glm::vec3(0, 1, 0)) * -d;
    y = -y;
  }
  move += d * weight;
  turn += y * weight;
}

void Character::update(double dt) noexcept {
  clock_ += dt;
  std::fill(std::begin(stats_.controllerMicros), std::end(stats_.controllerMicros), 0.0);
  glm::vec3 move(0.0f);
  float turn = 0.0f;
  int active = 0;
  Layer* only = nullptr;
  for (Layer& l : layers_) {
    if (!l.clip) continue;
    // Fade.
    if (l.fadeRate != 0.0f) {
      l.weight += static_cast<float>(l.fadeRate * dt);
      if (l.fadeRate > 0.0f && l.weight >= l.options.weight) {
        l.weight = l.options.weight;
        l.fadeRate = 0.0f;
      }
      if (l.stopping && l.weight <= 0.0f) {
        notify(ChangeKind::ClipStopped, l.clip->clip.name);
        l.clip.reset();
        continue;
      }
    }
    const double t0 = l.time;
    l.time += dt * l.options.speed;
    if (l.options.wrap == WrapMode::Clamp) l.time = std::clamp(l.time, 0.0, static_cast<double>(l.clip->clip.duration));
    l.clipTime = wrapClipTime(l.time, l.clip->clip.duration, l.options.wrap);
    applyRootMotion(l, t0, l.time, l.weight, move, turn);
    ++active;
    only = &l;
  }
  // Idle fast path: one full-weight, whole-body, normal layer samples straight into the pose.
  const bool direct = active == 1 && !only->options.additive && only->options.jointMask.empty() && only->weight >= 1.0f;
  if (active == 0) {
    std::copy(skeleton().restPose.begin(), skeleton().restPose.end(), pose_.begin());
  } else if (direct) {
    sampleLayer(*only, pose_);
  } else {
    blendLayers();
  }
  // Morph weights, recomputed every frame: 0, then the layers in order (later
  // layers override the targets they animate), then behaviors.
  std::span<float> morphs = buffer_.writeMorphWeights();
  std::fill(morphs.begin(), morphs.end(), 0.0f);
  for (Layer& l : layers_)
    if (l.clip && !l.clip->clip.morphTracks.empty())
      sampleMorphWeights(l.clip->clip, l.clipTime, morphs);
  if (!behaviors_.empty()) {
    applyBehaviors(static_cast<float>(dt));
    behaviors_.prune(clock_);
  }

  if (move != glm::vec3(0.0f) || turn != 0.0f) {
    position_ += glm::angleAxis(heading_, glm::vec3(0, 1, 0)) * move;
    heading_ = std::remainder(heading_ + turn, 6.28318530718f);
  }
  localToModel(skeleton(), pose_, buffer_.writeModel());
  skinningPalette(buffer_.modelMatrices(), skeleton().inverseBind, buffer_.writeSkinning());
  buffer_.setWorld(worldMatrix());
  buffer_.finishFrame();
  stats_.activeLayers = active;
  stats_.sampledDirect = direct;
}

}  // namespace marionette
