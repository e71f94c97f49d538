// Character, behaviors: adding a request (command time: its kind's binding, in
// character_bindings.cpp, by a table over kinds) and running the controllers over the timeline
// each frame (one walk that hands each entry to its controller, then the controllers in
// DESIGN.md's fixed order).
#include "character_state.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/procedural_controllers.hpp"
#include "marionette/core/text.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

BehaviorResult Character::State::addBehavior(BehaviorRequest request) {
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
  // A locomotion lasts until the character arrives: its entry stays until a later one
  // replaces it. Its plan is checked before the request joins the timeline.
  std::shared_ptr<LocomotionPlan> plan;
  std::string warning;
  if (kind == BehaviorKind::Locomotion) {
    std::string why = bindLocomotion(request, plan, warning);
    if (!why.empty()) {
      result.message = std::move(why);
      if (scene_) scene_->log(LogLevel::Warning, "behavior request '" + request.id + "': " + result.message);
      return result;
    }
    request.persistent = true;
  }
  BehaviorTimeline::Entry& e = behaviors_.add(std::move(request));
  result.added = true;
  reserveBehaviorPasses();
  // Which controller binds each kind, in BehaviorKind order (nullptr: only a clip realizes
  // it). A request that plays a clip is realized by the clip; a kind whose controller runs
  // over its clip (controllerRunsOverClip: pointing, the clip shapes the hand, the controller
  // aims the arm) also binds it, when it has a target.
  using Bind = std::string (Character::State::*)(BehaviorTimeline::Entry&, std::string&);
  static constexpr std::array<Bind, 21> kBindings = {{
      nullptr,                              // posture
      nullptr,                              // postureShift
      &Character::State::bindLocomotionEntry,      // locomotion
      &Character::State::bindGazeEntry,            // gaze
      &Character::State::bindGazeEntry,            // gazeShift
      &Character::State::bindHeadEntry,            // head
      &Character::State::bindHeadDirectionEntry,   // headDirectionShift
      &Character::State::bindFaceEntry,            // faceLexeme
      &Character::State::bindFaceEntry,            // faceFacs
      &Character::State::bindFaceEntry,            // face
      &Character::State::bindFaceEntry,            // faceShift
      &Character::State::bindGestureEntry,         // gesture (procedural, when no clip realizes it)
      &Character::State::bindPointingEntry,        // pointing
      &Character::State::bindSpeechEntry,          // speech
      &Character::State::bindWaitEntry,            // wait
      nullptr,                              // clip
      &Character::State::bindSaccadeEntry,         // saccade
      &Character::State::bindBlinkEntry,           // blinkemitter
      &Character::State::bindBreathingEntry,       // breathingemitter
      &Character::State::bindAudioEntry,           // audio
      &Character::State::bindReachEntry,           // reach
  }};
  static_assert(static_cast<std::size_t>(BehaviorKind::Reach) + 1 == kBindings.size(), "one binding per kind");
  const Bind bind = kBindings[static_cast<std::size_t>(kind)];
  if (clip) {
    bindClipEntry(e, std::move(clip));
    result.realized = true;
    const PointingParameters* aim = e.request.as<PointingParameters>();
    if (controllerRunsOverClip(kind) && bind && aim && !aim->target.empty()) {
      const std::string why = (this->*bind)(e, warning);
      result.message = why.empty() ? warning : why + "; the clip plays without aiming";
    }
  } else if (bind) {
    if (plan) e.controller = LocomotionEntryState{std::move(plan), glm::vec3(0.0f)};
    const std::string why = (this->*bind)(e, warning);
    result.realized = why.empty();
    result.message = why.empty() ? warning : why;
  } else {
    result.message = "no controller for " + std::string(toString(kind)) +
                     " behaviors exists yet; its timing, channel and feedback run but the body does not move";
  }
  return result;
}

void Character::State::bindClipEntry(BehaviorTimeline::Entry& e, std::shared_ptr<const AnimationClip> clip) {
  const std::size_t n = skeleton().jointCount();
  e.mask.assign(n, 0.0f);
  // The in-place tracks count: they move joints the clip may hold at rest (IK feet beside the root).
  for (const Clip* c : {&clip->clip, &clip->inPlaceRoot})
    for (const JointTrack& t : c->tracks)
      if (t.joint >= 0 && static_cast<std::size_t>(t.joint) < n &&
          (!t.translation.empty() || !t.rotation.empty() || !t.scale.empty()))
        e.mask[static_cast<std::size_t>(t.joint)] = 1.0f;
  // Gestures play on the upper body, over the posture and the locomotion.
  if (e.request.kind == BehaviorKind::Gesture || e.request.kind == BehaviorKind::Pointing) {
    e.upperBody = true;
    const std::vector<float> upper = upperBodyMask();
    if (!upper.empty())
      for (std::size_t i = 0; i < n; ++i) e.mask[i] *= upper[i];
  }
  e.cursor.reset(clip->clip);
  e.rootCursor.reset(clip->inPlaceRoot);
  e.clip = std::move(clip);
  ensureScratch();
}

void Character::State::ensureScratch() {
  if (!scratch_) {
    ownScratch_ = std::make_unique<FrameScratch>();
    scratch_ = ownScratch_.get();
  }
  scratch_->reserve(skeleton().jointCount());
}

void Character::State::reserveBehaviorPasses() {
  // Command time: each frame's walk hands entries to these lists without allocating.
  const std::size_t n = behaviors_.entries().size();
  for (auto& p : passes_) p.reserve(n);
}

std::vector<float> Character::State::upperBodyMask() const {
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

const LocomotionSet& Character::State::locomotionSet() const {
  if (!locomotionSet_) locomotionSet_ = std::make_shared<const LocomotionSet>(makeLocomotionSet(*rig_));
  return *locomotionSet_;
}

void Character::State::setLocomotionSettings(const LocomotionSettings& settings) noexcept {
  locomotionSettings_ = settings;
  if (locomotion_) locomotion_->setSettings(settings);
}

std::string Character::State::bindLocomotion(const BehaviorRequest& request, std::shared_ptr<LocomotionPlan>& plan,
                                      std::string& warning) const {
  const LocomotionSet& set = locomotionSet();
  if (!set.usable()) {
    std::string why = "the character has no walk clip it can travel with (set \"walk\" in its profile)";
    for (const std::string& n : set.notes) why += "; " + n;
    return why;
  }
  const LocomotionParameters* parameters = request.as<LocomotionParameters>();
  if (!parameters) return "a locomotion needs a target (LocomotionParameters: waypoints or a character)";
  plan = std::make_shared<LocomotionPlan>();
  std::string why = makeLocomotionPlan(*parameters, set, locomotionSettings_, *plan, warning);
  if (!why.empty()) return why;
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (!plan->targetCharacter.empty()) {
    const Character* target = scene_ ? scene_->findCharacter(plan->targetCharacter) : nullptr;
    if (!target && scene_ && scene_->findObject(plan->targetCharacter)) {  // a place: walked onto, unless told how near
      if (!parameters->proximity) plan->proximity = 0.0f;
      return {};
    }
    if (!target)
      return "locomotion target: the scene has no character or object '" + plan->targetCharacter + "'";
    if (target == &self_) return "locomotion target: a character cannot walk to itself";
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

std::optional<double> Character::State::estimateLocomotion(const BehaviorRequest& request) const {
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
    else if (const auto o = scene_ ? scene_->findObject(plan->targetCharacter) : std::nullopt) target = {o->x, o->z};
    waypoints = std::span<const glm::vec2>(&target, 1);
  }
  return estimateLocomotionSeconds(from, *plan, waypoints, locomotionSettings_);
}

LocomotionStatus Character::State::locomotionStatus(std::string_view id) const noexcept {
  LocomotionStatus st;
  const BehaviorTimeline::Entry* e = behaviors_.find(id);
  if (!e || !e->as<LocomotionEntryState>()) return st;
  if (!locomotion_ || e->order > locomotionOrder_) st.state = LocomotionStatus::State::Pending;
  else if (e->order < locomotionOrder_) st.state = LocomotionStatus::State::Superseded;
  else if (locomotion_->moving()) st.state = LocomotionStatus::State::Moving;
  else {
    st.state = LocomotionStatus::State::Done;
    st.doneTime = locomotion_->doneTime();
  }
  return st;
}

bool Character::State::cancelBehavior(std::string_view id, double blendOut) {
  const std::vector<StoppedSound> stopped = soundsStoppedBy(id, false);
  const bool known = behaviors_.cancel(id, clock_, blendOut);
  notifySoundsStopped(stopped);
  return known;
}

std::size_t Character::State::cancelBehaviors(std::string_view idPrefix, double blendOut) {
  const std::vector<StoppedSound> stopped = soundsStoppedBy(idPrefix, true);
  const std::size_t n = behaviors_.cancelPrefix(idPrefix, clock_, blendOut);
  notifySoundsStopped(stopped);
  return n;
}

std::vector<Character::State::StoppedSound> Character::State::soundsStoppedBy(std::string_view id, bool prefix) {
  // Speech and sounds the engine was told to play that have not ended yet (each sound once).
  std::vector<StoppedSound> out;
  for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (e.cancelled() || !(prefix ? std::string_view(e.request.id).substr(0, id.size()) == id : e.request.id == id))
      continue;
    if (e.as<SpeechState>() && clock_ < e.request.end()) out.push_back({e.request.id, false});
    if (AudioState* a = e.as<AudioState>(); a && !a->stopped && clock_ < a->playEnd) {
      a->stopped = true;
      out.push_back({e.request.id, true});
    }
  }
  return out;
}

void Character::State::notifySoundsStopped(const std::vector<StoppedSound>& sounds) const {
  if (!scene_) return;
  for (const StoppedSound& s : sounds)
    scene_->forEachListener([&](SceneListener& l) {
      if (s.audio) l.onAudioStopped(self_, s.id, clock_);
      else l.onSpeechStopped(self_, s.id, clock_);
    });
}

void Character::State::applyBehaviors(float dt) noexcept {
  // One walk over the timeline hands each entry to its controller's pass, with its weight
  // (entries without weight now are left out, except speech and locomotion, which look at
  // time themselves). The passes then run in the order of enum class Controller
  // (character.hpp says why that order).
  for (auto& p : passes_) p.clear();
  const std::span<BehaviorTimeline::Entry> entries = behaviors_.entries();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    BehaviorTimeline::Entry& e = entries[i];
    const float w = BehaviorTimeline::weightAt(e, clock_);
    const ActiveEntry active{static_cast<std::uint32_t>(i), w, e.order};
    if (AudioState* a = e.as<AudioState>(); a && a->cut && !a->stopped && clock_ >= a->playEnd) {
      a->stopped = true;  // the request ended before its clip: the engine stops it where it ends
      if (scene_) scene_->forEachListener([&](SceneListener& l) { l.onAudioStopped(self_, e.request.id, a->playEnd); });
    }
    if (e.as<SpeechState>()) pass(Controller::Speech).push_back(active);
    if (e.as<LocomotionEntryState>()) pass(Controller::Locomotion).push_back(active);
    if (w <= 0.0f) continue;
    if (e.clip) pass(e.upperBody ? Controller::UpperBodyClips : Controller::ClipBehaviors).push_back(active);
    if (e.as<GazeState>()) pass(Controller::Gaze).push_back(active);
    if (const HeadMotionState* h = e.as<HeadMotionState>(); h && !h->strokes.empty()) pass(Controller::Head).push_back(active);
    if (e.as<SaccadeState>()) pass(Controller::Saccade).push_back(active);
    if (e.as<BreathingState>()) pass(Controller::Breathing).push_back(active);
    if (e.as<BlinkState>()) pass(Controller::Blink).push_back(active);
    if (e.as<GestureState>()) pass(Controller::Gesture).push_back(active);
    if (e.as<PointingState>()) pass(Controller::Pointing).push_back(active);
    if (e.as<ReachState>()) pass(Controller::Reach).push_back(active);
    if (const FaceExpressionState* f = e.as<FaceExpressionState>(); f && !(f->morphs.empty() && f->joints.empty()))
      pass(Controller::Face).push_back(active);
  }
  const bool timing = scene_ && scene_->statsEnabled();
  auto run = [&](Controller which, auto&& apply) {
    const auto k = static_cast<std::size_t>(which);
    const auto start = timing ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    if (apply()) stats_.controllerUsed[k] = true;
    if (timing)
      stats_.controllerMicros[k] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  };
  run(Controller::ClipBehaviors, [&] { return applyBehaviorClips(pass(Controller::ClipBehaviors)); });
  if (locomotion_) run(Controller::Locomotion, [&] { return applyLocomotion(dt); });
  run(Controller::UpperBodyClips, [&] { return applyBehaviorClips(pass(Controller::UpperBodyClips)); });
  // An emitter blends over the one it replaces: the later the entry, the more of the weight it takes.
  auto crossfade = [&](Controller which, auto&& apply) {
    float left = 1.0f;
    const RuntimeVector<ActiveEntry>& p = pass(which);
    for (auto it = p.rbegin(); it != p.rend() && left > 0.0f; ++it) {
      apply(behaviors_.entries()[it->index], it->weight * left);
      left *= 1.0f - it->weight;
    }
    return !p.empty();
  };
  run(Controller::Breathing, [&] {
    return crossfade(Controller::Breathing, [&](BehaviorTimeline::Entry& e, float w) {
      applyBreathing(*e.as<BreathingState>(), clock_, w, skeleton(), pose_);
    });
  });
  const glm::mat4 worldToModel = glm::inverse(worldMatrix());  // gaze and pointing targets
  run(Controller::Gaze, [&] {
    for (const ActiveEntry& a : pass(Controller::Gaze)) {
      GazeState& g = *behaviors_.entries()[a.index].as<GazeState>();
      const SpatialTarget& t = g.target;  // a target that has left the scene: hold the direction
      updateGaze(g, glm::vec3(worldToModel * glm::vec4(t.world(), 1.0f)), t.known(), a.weight, gazeSettings_,
                 skeleton(), rig_->joints(), pose_, dt);
    }
    return !pass(Controller::Gaze).empty();
  });
  run(Controller::Head, [&] {
    for (const ActiveEntry& a : pass(Controller::Head))
      applyHead(*behaviors_.entries()[a.index].as<HeadMotionState>(), a.weight, clock_, *rig_, pose_);
    return !pass(Controller::Head).empty();
  });
  run(Controller::Saccade, [&] {
    for (const ActiveEntry& a : pass(Controller::Saccade))
      updateSaccade(*behaviors_.entries()[a.index].as<SaccadeState>(), clock_, a.weight, skeleton(), pose_);
    return !pass(Controller::Saccade).empty();
  });
  run(Controller::Gesture, [&] {
    for (const ActiveEntry& a : pass(Controller::Gesture))
      updateProceduralGesture(*behaviors_.entries()[a.index].as<GestureState>(), clock_, a.weight, skeleton(), pose_);
    return !pass(Controller::Gesture).empty();
  });
  run(Controller::Pointing, [&] {
    for (const ActiveEntry& a : pass(Controller::Pointing)) {
      PointingState& p = *behaviors_.entries()[a.index].as<PointingState>();
      const SpatialTarget& t = p.target;
      updatePointing(p, glm::vec3(worldToModel * glm::vec4(t.world(), 1.0f)), t.known(), a.weight, pointingSettings_,
                     skeleton(), pose_);
    }
    return !pass(Controller::Pointing).empty();
  });
  run(Controller::Reach, [&] {
    for (const ActiveEntry& a : pass(Controller::Reach)) {
      ReachState& r = *behaviors_.entries()[a.index].as<ReachState>();
      const SpatialTarget& t = r.target;
      updateReach(r, glm::vec3(worldToModel * glm::vec4(t.world(), 1.0f)), t.known(), a.weight, reachSettings_,
                  skeleton(), pose_);
    }
    return !pass(Controller::Reach).empty();
  });
  run(Controller::Face, [&] {
    const std::span<float> morphs = buffer_.writeMorphWeights();
    for (const ActiveEntry& a : pass(Controller::Face))
      applyFace(*behaviors_.entries()[a.index].as<FaceExpressionState>(), a.weight, morphs, *rig_, pose_);
    return !pass(Controller::Face).empty();
  });
  run(Controller::Blink, [&] {
    const std::span<float> morphs = buffer_.writeMorphWeights();
    float lidsClosed = 0.0f;  // by face expressions through eyelid joints: a blink closes no further than both
    for (const ActiveEntry& a : pass(Controller::Face)) {
      const FaceExpressionState& f = *behaviors_.entries()[a.index].as<FaceExpressionState>();
      for (const FaceExpressionState::JointMove& m : f.joints)
        if (m.part == FacsFacePart::UpperLid) lidsClosed = std::max(lidsClosed, a.weight * f.amount * m.value);
    }
    return crossfade(Controller::Blink, [&](BehaviorTimeline::Entry& e, float w) {
      applyBlink(*e.as<BlinkState>(), clock_, w, morphs, *rig_, pose_, lidsClosed);
    });
  });
  run(Controller::Speech, [&] { return applySpeechEntries(); });
}

bool Character::State::applySpeechEntries() noexcept {
  bool any = false;
  // Overlapping speech on one character: the one added last of those speaking now moves the
  // lips (a speech that could not be said takes nothing from the others).
  std::uint64_t voice = 0;
  bool hasVoice = false;
  for (const ActiveEntry& a : pass(Controller::Speech)) {
    const BehaviorTimeline::Entry& e = behaviors_.entries()[a.index];
    if (clock_ >= e.request.start() && clock_ < e.finishTime()) voice = a.order, hasVoice = true;
  }
  std::array<float, speech::kLipChannelCount> channels{};
  const std::span<float> morphs = buffer_.writeMorphWeights();
  // The listeners called below may add or cancel behaviors, which moves the entries (a
  // cancel erases one that had not started) and may grow this pass: a pass entry is found
  // again by its timeline order after every call, and skipped once it is gone.
  auto find = [this](const ActiveEntry& a) -> BehaviorTimeline::Entry* {
    const std::span<BehaviorTimeline::Entry> entries = behaviors_.entries();
    if (a.index < entries.size() && entries[a.index].order == a.order) return &entries[a.index];
    for (BehaviorTimeline::Entry& e : entries)  // moved down by an erase: the order ascends along the list
      if (e.order == a.order) return &e;
    return nullptr;
  };
  for (std::size_t k = 0; k < pass(Controller::Speech).size(); ++k) {
    const ActiveEntry a = pass(Controller::Speech)[k];
    const BehaviorTimeline::Entry* e = find(a);
    if (!e) continue;
    const std::shared_ptr<const speech::SpokenLine> line = e->as<SpeechState>()->line;
    const double start = e->request.start();
    const double local = clock_ - start;
    // Visemes of the phonemes that started by now, once each, also for a line whose lips another
    // owns (the engine hears it) and for phonemes a long frame stepped over; not those after
    // the line was cut off.
    const std::vector<speech::Phoneme>& phonemes = line->utterance->phonemes;
    const double cutoff = e->finishTime() - start;
    for (BehaviorTimeline::Entry* now = find(a); now; now = find(a)) {
      SpeechState& st = *now->as<SpeechState>();
      if (st.nextPhoneme >= phonemes.size() || phonemes[st.nextPhoneme].start > local ||
          phonemes[st.nextPhoneme].start >= cutoff)
        break;
      const speech::Phoneme& p = phonemes[st.nextPhoneme++];
      line->curves.evaluate(0.5 * (p.start + p.end), channels);
      const float peak = channels[static_cast<std::size_t>(p.cls.viseme)];
      scene_->forEachListener([&](SceneListener& l) {
        l.onViseme(self_, speech::visemeName(p.cls.viseme), peak, start + p.start);
      });
    }
    BehaviorTimeline::Entry* now = find(a);
    if (!now || !hasVoice || a.order != voice || a.weight <= 0.0f) continue;
    applySpeech(*now->as<SpeechState>(), a.weight, local, *rig_, channels, morphs, pose_);
    any = true;
  }
  return any;
}

void Character::State::resolveExternalTargets() noexcept {
  if (!scene_) return;
  for (BehaviorTimeline::Entry& e : behaviors_.entries())
    if (LocomotionEntryState* l = e.as<LocomotionEntryState>();
        l && e.order >= locomotionOrder_ && !l->plan->targetCharacter.empty()) {
      if (const Character* t = scene_->findCharacter(l->plan->targetCharacter)) {
        l->resolvedTarget = t->position();
      } else if (const auto o = scene_->findObject(l->plan->targetCharacter)) {
        l->resolvedTarget = glm::vec3(o->x, 0.0f, o->z);
      }
    }
  auto resolve = [this](SpatialTarget& target) { resolveTarget(target); };
  for (BehaviorTimeline::Entry& e : behaviors_.entries()) {
    if (GazeState* g = e.as<GazeState>()) resolve(g->target);
    if (PointingState* p = e.as<PointingState>()) resolve(p->target);
    if (ReachState* r = e.as<ReachState>()) resolve(r->target);
  }
}

void Character::State::resolveTarget(SpatialTarget& target) const noexcept {
  if (!scene_ || !target.external()) return;
  const Character* t = scene_->findCharacter(target.character);
  if (!t) {  // an object (a place), or gone: then the direction holds
    const auto o = scene_->findObject(target.character);
    target.resolvedKnown = o.has_value();
    if (o) target.resolvedPoint = *o;
    return;
  }
  target.resolvedKnown = true;
  const auto models = t->transformBuffer().modelMatrices();
  const auto j = static_cast<std::size_t>(target.jointIndex);
  target.resolvedPoint = target.jointIndex >= 0 && j < models.size()
                             ? glm::vec3(t->worldMatrix() * models[j][3])
                             : glm::vec3(t->worldMatrix() * glm::vec4(0.0f, t->rig().joints().eyeHeight, 0.0f, 1.0f));
}

bool Character::State::applyLocomotion(float dt) noexcept {
  // Follow the newest locomotion request that has started; stop when it is cancelled.
  bool cancelled = false;
  for (const ActiveEntry& a : pass(Controller::Locomotion)) {
    const BehaviorTimeline::Entry& e = behaviors_.entries()[a.index];
    const LocomotionEntryState& l = *e.as<LocomotionEntryState>();
    if (e.request.start() > clock_) continue;
    if (e.order > locomotionOrder_) {
      locomotion_->start(l.plan, position_, heading_);
      locomotionOrder_ = e.order;
    }
    if (e.order != locomotionOrder_) continue;
    if (!l.plan->targetCharacter.empty()) locomotion_->setTargetPosition(l.resolvedTarget);
    if (e.cancelled() && clock_ >= e.cancelAt) cancelled = true;
  }
  if (cancelled && locomotion_->moving()) locomotion_->stop();
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(pose_.size());
  locomotion_->update(dt, clock_, position_, heading_, skeleton(), pose_, scratch);
  return true;
}

bool Character::State::applyBehaviorClips(std::span<const ActiveEntry> pass) noexcept {
  const std::span<const Transform> rest = skeleton().restPose;
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(rest.size());
  const std::span<float> morphs = buffer_.writeMorphWeights();
  for (const ActiveEntry& a : pass) {
    BehaviorTimeline::Entry& e = behaviors_.entries()[a.index];
    const float w = a.weight;
    const AnimationClip& ac = *e.clip;
    const double start = e.request.start(), span = e.request.end() - start;
    const float t = e.request.loop || span <= 0.0
                        ? wrapClipTime(clock_ - start, ac.clip.duration, e.request.loop ? WrapMode::Loop : WrapMode::Clamp)
                        : static_cast<float>(std::clamp((clock_ - start) / span, 0.0, 1.0) * ac.clip.duration);
    // A clip that travels is played in place: behaviors do not move the character.
    sampleAnimationClip(ac, t, true, scratch, &e.cursor, &e.rootCursor);
    blendOver(pose_, scratch, w, e.mask);
    if (!ac.clip.morphTracks.empty() && !morphs.empty()) {
      std::copy(morphs.begin(), morphs.end(), morphScratch_.begin());
      sampleMorphWeights(ac.clip, t, morphScratch_);
      for (std::size_t i = 0; i < morphs.size(); ++i) morphs[i] += w * (morphScratch_[i] - morphs[i]);
    }
  }
  return !pass.empty();
}

}  // namespace marionette
