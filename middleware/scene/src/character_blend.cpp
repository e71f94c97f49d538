// Blend-space layers (Character::playBlend): a layer that plays a BlendSpace instead of
// one clip. The frame advances the space's shared phase by dt / its cycle duration (the
// clips' durations weighted), samples each clip with a weight at the time its warp
// maps the phase to, and adds it to the layer sum at the layer's weight times its own
// (so a blend layer mixes with other layers as one clip would). Root motion is the
// clips' root motion between their warped times, weighted the same.
#include <algorithm>
#include <cmath>

#include "character_state.hpp"
#include "marionette/animation/animation_clip.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette {

// ---- the facade (character.hpp) ----

bool Character::playBlend(int layer, std::shared_ptr<const BlendSpace> space, const PlayOptions& options, float x,
                          float y) {
  return state_->playBlend(layer, std::move(space), options, x, y);
}
bool Character::playBlend(int layer, std::string_view name, const PlayOptions& options, float x, float y) {
  return state_->playBlend(layer, name, options, x, y);
}
bool Character::setBlendParameter(int layer, float x, float y) noexcept { return state_->setBlendParameter(layer, x, y); }
const BlendSpace* Character::layerBlendSpace(int layer) const noexcept {
  const State::Layer* const l = state_->layers_.find(layer);
  return l ? l->blend.space.get() : nullptr;
}
std::span<const float> Character::layerBlendWeights(int layer) const noexcept {
  const State::Layer* const l = state_->layers_.find(layer);
  if (!l) return {};
  const BlendSpaceLayer& b = l->blend;
  return b.space ? std::span<const float>(b.weights) : std::span<const float>();
}

// ---- the state ----

bool Character::State::playBlend(int layer, std::shared_ptr<const BlendSpace> space, const PlayOptions& options, float x,
                                 float y) {
  auto refuse = [&](const std::string& why) {
    if (scene_) scene_->log(LogLevel::Warning, "playBlend: " + why + "; nothing started");
    return false;
  };
  if (layer < 0 || layer >= kMaxLayers) return refuse("layer " + std::to_string(layer) + " is out of range");
  if (!space) return refuse("no blend space");
  if (options.additive) return refuse("blend space '" + space->name() + "': additive blend layers are not supported");
  const Skeleton& s = skeleton();
  for (const BlendSpace::Sample& sample : space->samples())
    if (sample.clip->pose.size() != s.jointCount())
      return refuse("blend space '" + space->name() + "': clip '" + sample.clip->clip.name +
                    "' was made for another skeleton");
  Layer& l = layers_.ensure(layer);
  const std::size_t n = s.jointCount(), samples = space->samples().size();
  l.clip.reset();  // the space replaces a clip too
  startLayer(l, options, n);
  BlendSpaceLayer& b = l.blend;
  b.space = std::move(space);
  b.phase = std::isfinite(options.startTime) ? options.startTime : 0.0;  // a blend's start is a phase (cycles)
  l.time = b.phase;
  // Everything the frame touches, sized now.
  b.weights.assign(samples, 0.0f);
  b.cursors.assign(samples, SamplingCursor{});
  b.rootCursors.assign(samples, SamplingCursor{});
  for (std::size_t i = 0; i < samples; ++i) {
    b.cursors[i].reset(b.space->samples()[i].clip->clip);
    b.rootCursors[i].reset(b.space->samples()[i].clip->inPlaceRoot);
  }
  b.x = std::isfinite(x) ? x : 0.0f;
  b.y = std::isfinite(y) ? y : 0.0f;
  b.space->weights(b.x, b.y, b.weights);
  b.eventTracks.assign(samples, nullptr);  // each sample clip's events, for the frame to send
  for (std::size_t i = 0; i < samples; ++i) {
    auto track = rig_->events(*b.space->samples()[i].clip);
    if (track && !track->empty()) b.eventTracks[i] = std::move(track);
  }
  b.eventSample = 0;
  l.eventFrom = l.eventTo = 0.0;  // nothing crossed before the first update
  if (!scratch_) {  // a character outside a scene blends in its own scratch (allocated here, at command time)
    ownScratch_ = std::make_unique<FrameScratch>();
    scratch_ = ownScratch_.get();
  }
  scratch_->reserve(n);
  notify(ChangeKind::ClipStarted, b.space->name());
  return true;
}

bool Character::State::playBlend(int layer, std::string_view name, const PlayOptions& options, float x, float y) {
  auto space = rig_->findBlendSpace(name);
  if (!space) {
    if (scene_) scene_->log(LogLevel::Warning, "playBlend: no blend space named '" + std::string(name) + "' in the character's rig");
    return false;
  }
  return playBlend(layer, std::move(space), options, x, y);
}

bool Character::State::setBlendParameter(int layer, float x, float y) noexcept {
  Layer* const l = layers_.find(layer);
  if (!l) return false;
  BlendSpaceLayer& b = l->blend;
  if (!b.space || !std::isfinite(x) || !std::isfinite(y)) return false;
  b.x = x;
  b.y = y;
  b.space->weights(x, y, b.weights);  // sized at play: no allocation
  return true;
}

namespace {

// Root motion of one clip from clip time t0 to t1 (either way), as a clip layer has it.
void clipRootMotion(const RootMotion& rm, double t0, double t1, WrapMode wrap, float weight, glm::vec3& move,
                    float& turn) noexcept {
  if (rm.empty() || t0 == t1 || !(weight > 0.0f)) return;
  glm::vec3 d;
  float y;
  if (t1 > t0) {
    rm.between(t0, t1, wrap, d, y);
  } else {  // backwards: the inverse of the forward motion from t1 to t0
    rm.between(t1, t0, wrap, d, y);
    d = glm::angleAxis(-y, glm::vec3(0, 1, 0)) * -d;
    y = -y;
  }
  move += d * weight;
  turn += y * weight;
}

}  // namespace

bool Character::State::advanceBlendLayer(Layer& l, double dt, glm::vec3& move, float& turn) noexcept {
  BlendSpaceLayer& b = l.blend;
  if (fadeLayer(l, dt)) {
    notify(ChangeKind::ClipStopped, b.space->name());
    b.space.reset();
    return false;
  }
  const BlendSpace& space = *b.space;
  const double cycle = space.cycleDuration(b.weights);
  const double p0 = b.phase;
  if (cycle > 0.0) b.phase += dt * static_cast<double>(l.options.speed) / cycle;
  if (l.options.wrap == WrapMode::Clamp) b.phase = std::clamp(b.phase, 0.0, 1.0);
  l.time = b.phase;
  // The events the heaviest sample's clip crossed, in its own (warped) time.
  b.eventSample = static_cast<std::size_t>(std::max_element(b.weights.begin(), b.weights.end()) - b.weights.begin());
  if (b.eventSample < b.eventTracks.size() && b.eventTracks[b.eventSample]) {
    l.eventFrom = space.clipTime(b.eventSample, p0);
    l.eventTo = space.clipTime(b.eventSample, b.phase);
  } else {
    l.eventFrom = l.eventTo = 0.0;
  }
  if (l.options.rootMotion && b.phase != p0) {
    const auto samples = space.samples();
    for (std::size_t i = 0; i < samples.size(); ++i)
      clipRootMotion(samples[i].clip->rootMotion, space.clipTime(i, p0), space.clipTime(i, b.phase), l.options.wrap,
                     l.weight * b.weights[i], move, turn);
  }
  return true;
}

void Character::State::accumulateBlendLayer(Layer& l, std::span<Transform> scratch) noexcept {
  const BlendSpaceLayer& b = l.blend;
  const BlendSpace& space = *b.space;
  const auto samples = space.samples();
  const std::span<const Transform> rest = skeleton().restPose;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const float w = b.weights[i];
    if (!(w > 0.0f)) continue;  // at most 3 clips have a weight (2 in 1D)
    const AnimationClip& clip = *samples[i].clip;
    const float t = wrapClipTime(space.clipTime(i, b.phase), clip.clip.duration, l.options.wrap);
    sampleAnimationClip(clip, t, l.options.rootMotion, scratch, &l.blend.cursors[i], &l.blend.rootCursors[i]);
    scratch_->accumulator.addNormal(scratch, l.weight * w, l.options.jointMask, rest);
  }
}

}  // namespace marionette
