#include "marionette/bml/behavior_mapping.hpp"

#include "marionette/speech/speech_service.hpp"

#include "marionette/core/number_list.hpp"
#include "marionette/core/text.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace marionette::bml {

namespace {
// The name a behavior's clip would have, if it can be realized by one.
std::string clipName(const Behavior& b) {
  if (b.type == "animation")  // SmartBody: <animation name="CLIP"/>
    if (const Attribute* a = b.attribute("name")) return a->value;
  const auto kind = behaviorKindFromName(b.type);
  if (!kind) return {};
  switch (*kind) {
    case BehaviorKind::Gesture:
    case BehaviorKind::Pointing:
    case BehaviorKind::Head:
      if (const Attribute* a = b.attribute("lexeme")) return a->value;
      return {};
    case BehaviorKind::Posture:
    case BehaviorKind::PostureShift:
      if (const Attribute* a = b.attribute("posture")) return a->value;  // SmartBody <body posture>
      if (const Attribute* a = b.attribute("lexeme")) return a->value;
      if (const Attribute* a = b.attribute("stance")) return a->value;
      return {};
    default: return {};
  }
}
}  // namespace

BodyChannel channelsOf(const Behavior& b) {
  const auto kind = behaviorKindFromName(b.type);
  if (!kind) return BodyChannel::None;
  if (*kind == BehaviorKind::Gesture || *kind == BehaviorKind::Pointing || *kind == BehaviorKind::Reach) {
    const Attribute* mode = b.attribute("mode");
    if (mode && mode->value == "LEFT_HAND") return BodyChannel::LeftHand;
    if (mode && mode->value == "RIGHT_HAND") return BodyChannel::RightHand;
    const Attribute* side = *kind == BehaviorKind::Reach ? b.attribute("reach-type") : nullptr;  // SmartBody's
    if (side && equalsIgnoringCase(side->value, "left")) return BodyChannel::LeftHand;
    if (side && equalsIgnoringCase(side->value, "right")) return BodyChannel::RightHand;
  }
  return defaultChannels(*kind);
}

std::shared_ptr<const AnimationClip> clipFor(const Behavior& b, const Rig& rig) {
  const std::string name = clipName(b);
  if (name.empty()) return nullptr;
  // The character's gesture library first (BEAT -> "ThumbsUp"), then the clip names.
  if (b.type == "gesture" || b.type == "pointing") {
    const auto& library = rig.profile().gestures;
    for (const auto& [lexeme, clip] : library)
      if (equalsIgnoringCase(lexeme, name))
        if (auto c = rig.findClip(clip)) return c;
  }
  if (auto exact = rig.findClip(name)) return exact;
  for (const auto& c : rig.clips())
    if (equalsIgnoringCase(c->clip.name, name)) return c;
  // A standing posture by its BML stance name is the character's idle clip.
  if ((b.type == "posture" || b.type == "postureShift") && !rig.profile().idle.empty())
    for (const char* stance : {"STAND", "STANDING", "IDLE"})
      if (equalsIgnoringCase(name, stance)) return rig.findClip(rig.profile().idle);
  return nullptr;
}

std::optional<double> naturalDuration(const Behavior& b, const Rig& rig) {
  if (b.type == "posture" || b.type == "postureShift") return std::nullopt;
  if (b.type == "saccade") {  // SmartBody's sbm:duration: how long one saccade holds
    const Attribute* d = b.attribute("duration");
    const auto v = d ? parseNumberList(d->value) : std::nullopt;
    if (v && v->size() == 1 && std::isfinite(v->front()) && v->front() > 0.0f) return std::min(v->front(), 3600.0f);
    return std::nullopt;
  }
  const auto clip = clipFor(b, rig);
  if (!clip || !(clip->clip.duration > 0.0f)) return std::nullopt;
  double speed = 1.0;  // SmartBody's <animation speed>: the clip plays over duration / speed
  if (const Attribute* a = b.type == "animation" ? b.attribute("speed") : nullptr)
    if (const auto v = parseNumberList(a->value); v && v->size() == 1 && std::isfinite(v->front()) && v->front() > 0.0f)
      speed = std::clamp(static_cast<double>(v->front()), 0.01, 100.0);
  return static_cast<double>(clip->clip.duration) / speed;
}

std::optional<double> naturalDuration(const Behavior& b, const Character& character) {
  if (b.type != "locomotion") return naturalDuration(b, character.rig());
  BehaviorRequest r;
  r.id = b.id;
  r.kind = BehaviorKind::Locomotion;
  r.parameters = readParameters(b, BehaviorKind::Locomotion).parameters;
  return character.estimateLocomotion(r);
}

namespace {

// What the speech service is asked for a <speech> (the same text and marks as toRequest gives).
BehaviorRequest speechRequest(const Behavior& b) {
  BehaviorRequest r;
  r.id = b.id;
  r.kind = BehaviorKind::Speech;
  r.parameters = readParameters(b, BehaviorKind::Speech).parameters;
  return r;
}

}  // namespace

std::shared_ptr<const speech::SpeechService::Preparation> prepareSpeechTiming(const Behavior& b,
                                                                            const Character& character) {
  if (b.type != "speech") return nullptr;
  return character.prepareSpeechInBackground(speechRequest(b));
}

std::optional<SpeechTiming> speechTiming(const Behavior& b, const Character& character) {
  if (b.type != "speech") return std::nullopt;
  Diagnostics unsaid;  // reported again when the request is added (addBehavior)
  const auto line = character.prepareSpeech(speechRequest(b), unsaid);
  if (!line) return std::nullopt;
  SpeechTiming t;
  t.duration = line->utterance->duration;
  for (const speech::Mark& m : line->utterance->marks) t.marks.push_back({m.id, m.time});
  return t;
}

SmartBodyBlend readSmartBodyBlend(const Behavior& b, const Rig& rig) {
  SmartBodyBlend out;
  const Attribute* name = b.attribute("name");
  out.name = name ? name->value : std::string();
  std::string spaces;
  for (const auto& s : rig.blendSpaces()) spaces += (spaces.empty() ? "'" : ", '") + s->name() + "'";
  if (out.name.empty()) {
    out.error = "SmartBody's <blend> names no blend space (name=\"...\")";
    return out;
  }
  const auto space = rig.findBlendSpace(out.name);
  if (!space) {
    out.error = "SmartBody's <blend name=\"" + out.name + "\">: the character's profile has no blend space of that name (" +
                (spaces.empty() ? std::string("it has none: add \"blendSpaces\" to its profile") : "it has " + spaces) + ")";
    return out;
  }
  // x, y, z: numbers, or empty (SmartBody writes x="" for a parameter it leaves alone: 0 here).
  float* values[] = {&out.x, &out.y, nullptr};
  const char* names[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const Attribute* a = b.attribute(names[k]);
    if (!a || a->value.empty()) continue;
    const auto v = parseNumberList(a->value);
    if (!v || v->size() != 1 || !std::isfinite(v->front())) {
      out.warning += std::string(out.warning.empty() ? "" : "; ") + names[k] + "=\"" + a->value + "\" is not a number: 0 used";
      continue;
    }
    if (!values[k]) {
      out.warning += std::string(out.warning.empty() ? "" : "; ") +
                     "z ignored: blend spaces have 1 or 2 parameters (x, y)";
      continue;
    }
    *values[k] = v->front();
    if (k == 1 && space->dimensions() == 1)
      out.warning += std::string(out.warning.empty() ? "" : "; ") + "y ignored: blend space '" + out.name + "' has 1 parameter";
  }
  return out;
}

MappedRequest toRequest(const Behavior& b, const ScheduledBehavior& s, const std::string& blockId, double blockStart,
                        const Rig& rig) {
  MappedRequest m;
  BehaviorRequest& r = m.request;
  r.id = blockId + ":" + b.id;
  // SmartBody's <animation> plays its clip; an <event> is realized by the realizer's feedback
  // (a message at its stroke), on the timeline as a wait.
  r.kind = b.type == "animation" ? BehaviorKind::Clip : behaviorKindFromName(b.type).value_or(BehaviorKind::Wait);
  r.channels = channelsOf(b);
  double last = -std::numeric_limits<double>::infinity();
  for (const SyncTime& sync : s.syncs) {
    // The scheduler allows 1e-6 s of disorder; the timeline does not.
    last = std::max(last, blockStart + sync.time);
    r.syncs.push_back({sync.name, last});
  }
  if (auto clip = clipFor(b, rig)) r.clip = clip->clip.name;
  else if (r.kind == BehaviorKind::Clip) r.clip = clipName(b);  // not the rig's: the character names what it has
  if (r.clip.empty() || controllerRunsOverClip(r.kind)) {
    ReadParameters read = readParameters(b, r.kind);
    r.parameters = std::move(read.parameters);
    m.error = std::move(read.error);
    m.warning = std::move(read.warning);
  }
  if (r.kind == BehaviorKind::Reach && r.as<PointingParameters>()) r.kind = BehaviorKind::Pointing;  // sbm:action="point-at"
  // SmartBody's parametric state: a blend space of the character's profile, played by the
  // realizer at the behavior's start (Realizer: blendLayer()); on the timeline as a wait.
  if (b.type == "blend") {
    const SmartBodyBlend blend = readSmartBodyBlend(b, rig);
    m.error = blend.error;
    m.warning = blend.warning;
  }
  r.loop = r.kind == BehaviorKind::Posture || r.kind == BehaviorKind::PostureShift;
  // A saccade model runs (and a finish holds) until a later saccade request replaces it; so do
  // the idle-life emitters.
  const SaccadeParameters* saccade = r.as<SaccadeParameters>();
  r.persistent = (saccade && (saccade->mode != SaccadeMode::None || saccade->finish)) ||
                 r.kind == BehaviorKind::BlinkEmitter || r.kind == BehaviorKind::BreathingEmitter ||
                 r.kind == BehaviorKind::PostureShift || r.kind == BehaviorKind::FaceShift ||
                 r.kind == BehaviorKind::GazeShift || r.kind == BehaviorKind::HeadDirectionShift;
  return m;
}

}  // namespace marionette::bml
