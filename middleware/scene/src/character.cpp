#include "character_state.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/procedural_controllers.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/speech/speech_service.hpp"
#include "marionette/core/angles.hpp"

namespace marionette {

std::string_view controllerName(Controller controller) noexcept {
  switch (controller) {
    case Controller::ClipBehaviors: return "clip behaviors";
    case Controller::Locomotion: return "locomotion";
    case Controller::UpperBodyClips: return "upper-body clips";
    case Controller::Breathing: return "breathing";
    case Controller::Gaze: return "gaze";
    case Controller::Head: return "head";
    case Controller::Saccade: return "saccade";
    case Controller::Gesture: return "gesture";
    case Controller::Pointing: return "pointing";
    case Controller::Face: return "face";
    case Controller::Blink: return "blink";
    case Controller::Speech: return "speech";
    case Controller::Reach: return "reach";
  }
  return "?";
}

void FrameScratch::reserve(std::size_t joints) {
  if (pose.size() >= joints) return;
  pose.resize(joints);
  accumulator.reset(joints);
}

Character::State::State(Character& self, std::string name, std::shared_ptr<const Rig> rig)
    : self_(self), name_(std::move(name)), rig_(std::move(rig)) {
  const Skeleton& s = rig_->skeleton();
  pose_.assign(s.restPose.begin(), s.restPose.end());
  buffer_.resize(s.jointCount(), rig_->morphTargets().size());
  morphScratch_.resize(rig_->morphTargets().size());
}

void Character::State::notify(ChangeKind kind, std::string_view what) const {
  if (scene_) scene_->forEachListener([&](SceneListener& l) { l.onCharacterChanged(self_, kind, what); });
}

void Character::State::setPosition(const glm::vec3& p) noexcept {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    if (scene_) scene_->log(LogLevel::Warning, "setPosition: non-finite position rejected");
    return;
  }
  position_ = p;
  notify(ChangeKind::Placement, "position");
}

void Character::State::setHeading(float radians) noexcept {
  if (!std::isfinite(radians)) {
    if (scene_) scene_->log(LogLevel::Warning, "setHeading: non-finite heading rejected");
    return;
  }
  heading_ = wrapAngle(radians);
  notify(ChangeKind::Placement, "heading");
}

glm::mat4 Character::State::worldMatrix() const noexcept {
  Transform t;
  t.translation = position_;
  t.rotation = glm::angleAxis(heading_, glm::vec3(0, 1, 0));
  return t.matrix();
}

bool Character::State::fadeLayer(Layer& l, double dt) noexcept {
  if (l.fadeRate == 0.0f) return false;
  l.weight += static_cast<float>(l.fadeRate * dt);
  if (l.fadeRate > 0.0f && l.weight >= l.options.weight) {
    l.weight = l.options.weight;
    l.fadeRate = 0.0f;
  }
  return l.stopping && l.weight <= 0.0f;
}

void Character::State::startLayer(Layer& l, const PlayOptions& options, std::size_t joints) {
  l.options = options;
  if (!l.options.jointMask.empty()) l.options.jointMask.resize(joints, 0.0f);
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
}

bool Character::State::play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options) {
  if (layer < 0 || layer >= kMaxLayers || !clip) {
    if (scene_) scene_->log(LogLevel::Warning, "play: layer out of range or no clip; nothing started");
    return false;
  }
  Layer& l = layers_.ensure(layer);
  const std::size_t n = skeleton().jointCount();
  l.blend.space.reset();  // a clip replaces a blend space too
  l.clip = std::move(clip);
  startLayer(l, options, n);
  l.time = std::isfinite(options.startTime) ? options.startTime : 0.0;
  l.cursor.reset(l.clip->clip);
  l.rootCursor.reset(l.clip->inPlaceRoot);
  bindEvents(l);
  if (!scratch_) {  // a character outside a scene blends in its own scratch (allocated here, at command time)
    ownScratch_ = std::make_unique<FrameScratch>();
    scratch_ = ownScratch_.get();
  }
  scratch_->reserve(n);
  if (options.additive) {
    l.reference.resize(n);
    sampleAnimationClip(*l.clip, 0.0f, false, skeleton().restPose, l.reference);
  }
  notify(ChangeKind::ClipStarted, l.clip->clip.name);
  return true;
}

bool Character::State::play(int layer, std::string_view clipName, const PlayOptions& options) {
  auto clip = rig_->findClip(clipName);
  if (!clip) {
    if (scene_) scene_->log(LogLevel::Warning, "play: no clip of that name in the character's rig");
    return false;
  }
  return play(layer, std::move(clip), options);
}

void Character::State::stop(int layer, float fadeOut) {
  Layer* const found = layers_.find(layer);
  if (!found || (!found->clip && !found->blend.space)) return;
  Layer& l = *found;
  if (fadeOut > 0.0f && std::isfinite(fadeOut)) {
    l.stopping = true;
    l.fadeRate = -std::max(l.weight, 1e-6f) / fadeOut;
    return;
  }
  if (l.blend.space) {
    notify(ChangeKind::ClipStopped, l.blend.space->name());
    l.blend.space.reset();
    return;
  }
  notify(ChangeKind::ClipStopped, l.clip->clip.name);
  l.clip.reset();
}

int Character::State::layerCount() const noexcept {
  int n = 0;
  for (const Layer& l : layers_) n += l.clip || l.blend.space ? 1 : 0;
  return n;
}

double Character::State::layerTime(int layer) const noexcept {
  const Layer* const l = layers_.find(layer);
  return l ? l->time : 0.0;
}

void Character::State::sampleLayer(Layer& layer, std::span<Transform> out) noexcept {
  const AnimationClip& ac = *layer.clip;
  const float t = layer.clipTime;
  sampleAnimationClip(ac, t, layer.options.rootMotion, out, &layer.cursor, &layer.rootCursor);
  if (layer.options.additive) makeAdditiveDelta(out, layer.reference, out);
}

void Character::State::blendLayers() noexcept {
  // Normal layers are summed one at a time through the scratch pose, then the
  // additive layers are applied in order on the result (as blendPoses does).
  const std::span<const Transform> rest = skeleton().restPose;
  const std::span<Transform> scratch = std::span<Transform>(scratch_->pose).first(rest.size());
  scratch_->accumulator.reset(rest.size());  // no allocation: sized at play time
  for (Layer& l : layers_) {
    if (l.blend.space) {  // its clips go into the sum one by one, each at its weight in the space
      accumulateBlendLayer(l, scratch);
      continue;
    }
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

void Character::State::applyRootMotion(const Layer& layer, double t0, double t1, float weight, glm::vec3& move,
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

void Character::State::update(double dt) noexcept {
  const glm::vec3 startPosition = position_;
  const float startHeading = heading_;
  clock_ += dt;
  std::fill(std::begin(stats_.controllerMicros), std::end(stats_.controllerMicros), 0.0);
  glm::vec3 move(0.0f);
  float turn = 0.0f;
  int active = 0;
  Layer* only = nullptr;
  for (Layer& l : layers_) {
    if (l.blend.space) {  // fades, phase and root motion of a blend space (character_blend.cpp)
      if (advanceBlendLayer(l, dt, move, turn)) ++active, only = &l;
      continue;
    }
    if (!l.clip) continue;
    if (fadeLayer(l, dt)) {
      notify(ChangeKind::ClipStopped, l.clip->clip.name);
      l.clip.reset();
      continue;
    }
    const double t0 = l.time;
    l.time += dt * l.options.speed;
    l.eventFrom = t0, l.eventTo = t0 + dt * l.options.speed;
    if (l.options.wrap == WrapMode::Clamp) l.time = std::clamp(l.time, 0.0, static_cast<double>(l.clip->clip.duration));
    l.clipTime = wrapClipTime(l.time, l.clip->clip.duration, l.options.wrap);
    applyRootMotion(l, t0, l.time, l.weight, move, turn);
    ++active;
    only = &l;
  }
  // Idle fast path: one full-weight, whole-body, normal layer samples straight into the pose.
  const bool direct = active == 1 && !only->blend.space && !only->options.additive && only->options.jointMask.empty() && only->weight >= 1.0f;
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
    heading_ = wrapAngle(heading_ + turn);
  }
  localToModelAndPalette(skeleton(), pose_, buffer_.writeModel(), buffer_.writeSkinning(), &rig_->paletteBasis());
  lastMotion_ = PlacementDelta{position_ - startPosition, wrapAngle(heading_ - startHeading)};
  buffer_.setWorld(worldMatrix());
  buffer_.finishFrame();
  sendAnimationEvents(dt);
  stats_.activeLayers = active;
  stats_.sampledDirect = direct;
}

}  // namespace marionette
