#include "marionette/bml/realizer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace marionette::bml {

std::string xmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {
std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
}  // namespace

std::string Feedback::xml() const {
  const std::string ns = " xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\"";
  const std::string id = xmlEscape(blockId) + (behaviorId.empty() ? "" : ":" + xmlEscape(behaviorId));
  const std::string global = " globalTime=\"" + number(sceneTime) + "\"";
  const std::string who = character.empty() ? "" : " characterId=\"" + xmlEscape(character) + "\"";
  switch (kind) {
    case Kind::BlockProgress:
      return "<blockProgress" + ns + " id=\"" + xmlEscape(blockId) + ":" + syncPoint + "\"" + global + who + "/>";
    case Kind::SyncPointProgress:
      return "<syncPointProgress" + ns + " id=\"" + id + ":" + xmlEscape(syncPoint) + "\" time=\"" + number(blockTime) +
             "\"" + global + who + "/>";
    case Kind::Prediction:
      return "<predictionFeedback" + ns + " id=\"" + id + ":" + xmlEscape(syncPoint) + "\" time=\"" + number(blockTime) +
             "\"" + global + who + "/>";
    case Kind::Warning:
      return "<warningFeedback" + ns + " id=\"" + id + "\" type=\"" + std::string(toString(warning.type)) + "\"" +
             who + ">" + xmlEscape(warning.message) + "</warningFeedback>";
  }
  return {};
}

std::string bodyChannel(const Behavior& b) {
  const std::string& t = b.type;
  if (t == "head" || t == "headDirectionShift") return "head";
  if (t == "gaze" || t == "gazeShift") return "gaze";
  if (t == "speech") return "voice";
  if (t == "posture" || t == "postureShift") return "posture";
  if (t == "locomotion") return "locomotion";
  if (t == "gesture" || t == "pointing") {
    const Attribute* mode = b.attribute("mode");
    if (mode && mode->value == "LEFT_HAND") return "leftHand";
    if (mode && mode->value == "RIGHT_HAND") return "rightHand";
    return "hands";
  }
  return {};  // face behaviors combine; wait drives nothing
}

namespace {
// "hands" overlaps both hands.
bool channelsOverlap(const std::string& a, const std::string& b) {
  if (a == b) return true;
  const bool handA = a == "hands" || a == "leftHand" || a == "rightHand";
  const bool handB = b == "hands" || b == "leftHand" || b == "rightHand";
  return handA && handB && (a == "hands" || b == "hands");
}
}  // namespace

void Realizer::emit(const Feedback& f) {
  for (const FeedbackListener& l : listeners_) l(f);
  if (f.kind == Feedback::Kind::Warning) {
    if (forwardWarnings_) scene_.log(f.warning.fatal ? LogLevel::Error : LogLevel::Warning, f.xml());
    return;
  }
  if (f.kind == Feedback::Kind::Prediction) return;
  if (Character* c = scene_.findCharacter(f.character)) {
    const std::string sync = f.kind == Feedback::Kind::BlockProgress ? f.syncPoint : f.behaviorId + ":" + f.syncPoint;
    scene_.forEachListener([&](SceneListener& l) { l.onBehaviorProgress(*c, f.blockId, sync, f.sceneTime); });
  }
}

Schedule Realizer::perform(std::string_view bmlText, std::string_view character, const SchedulerOptions& options,
                           std::optional<double> at) {
  const ParseResult parsed = parseBlock(bmlText);
  Schedule schedule = scheduleParsed(parsed, options);

  std::string who(character);
  if (who.empty() && parsed.block) who = parsed.block->characterId;
  if (who.empty() && !scene_.characters().empty()) who = scene_.characters().front()->name();
  if (!schedule.failed && !scene_.findCharacter(who)) {
    schedule.warnings.push_back({WarningType::NoSuchTarget, schedule.blockId, "", parsed.block->line, parsed.block->column,
                                 who.empty() ? "the scene has no character to perform the block"
                                             : "the scene has no character named '" + who + "'",
                                 true});
    schedule.failed = true;
  }
  const double now = at && std::isfinite(*at) ? *at : scene_.time();
  for (const Warning& w : schedule.warnings) {
    Feedback f;
    f.kind = Feedback::Kind::Warning;
    f.character = who;
    f.blockId = w.blockId.empty() ? schedule.blockId : w.blockId;
    f.behaviorId = w.behaviorId;
    f.sceneTime = now;
    f.warning = w;
    emit(f);
  }
  if (schedule.failed) return schedule;

  // Composition.
  double start = now;
  const std::string composition = parsed.block->composition;
  if (composition == "REPLACE") {
    for (Active& b : blocks_)
      if (b.character == who) finish(b, now);
    blocks_.erase(std::remove_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.character == who; }),
                  blocks_.end());
  } else if (composition == "APPEND") {
    for (const Active& b : blocks_)
      if (b.character == who) start = std::max(start, b.end);
  }
  Active a;
  a.character = who;
  a.blockId = schedule.blockId;
  a.start = start;
  double blockEnd = 0.0;
  for (const ScheduledBehavior& b : schedule.behaviors)
    for (const SyncTime& s : b.syncs) {
      a.events.push_back({start + s.time, b.id, s.name, s.time});
      blockEnd = std::max(blockEnd, s.time);
    }
  std::stable_sort(a.events.begin(), a.events.end(), [](const Event& x, const Event& y) { return x.sceneTime < y.sceneTime; });
  a.end = start + blockEnd;
  claimChannels(a, *parsed.block, schedule, who);
  for (const Event& e : a.events) emit(syncFeedback(Feedback::Kind::Prediction, a, e));
  blocks_.push_back(std::move(a));
  return schedule;
}

void Realizer::claimChannels(Active& a, const Block& block, const Schedule& schedule, const std::string& who) {
  // Claims in text order; each new claim that overlaps an earlier one (this
  // block's or a queued block's) on the same channel wins there, with a warning.
  for (const ScheduledBehavior& sb : schedule.behaviors) {
    auto parsedIt = std::find_if(block.behaviors.begin(), block.behaviors.end(),
                                 [&](const Behavior& b) { return b.id == sb.id; });
    if (parsedIt == block.behaviors.end() || sb.syncs.empty()) continue;
    const std::string channel = bodyChannel(*parsedIt);
    if (channel.empty()) continue;
    Claim claim{channel, sb.id, a.start + sb.syncs.front().time, a.start + sb.syncs.back().time, ++order_};
    auto report = [&](const std::string& otherBlock, const Claim& other) {
      const double from = std::max(claim.start, other.start), to = std::min(claim.end, other.end);
      if (to <= from) return;
      Feedback f;
      f.kind = Feedback::Kind::Warning;
      f.character = who;
      f.blockId = a.blockId;
      f.behaviorId = sb.id;
      f.sceneTime = scene_.time();
      char span[64];
      std::snprintf(span, sizeof span, "%.3g s to %.3g s", from - a.start, to - a.start);
      f.warning = {WarningType::ImpossibleToSchedule, a.blockId, sb.id, parsedIt->line, parsedIt->column,
                   "overlaps behavior '" + other.behaviorId + "'" + (otherBlock == a.blockId ? "" : " of block '" + otherBlock + "'") +
                       " on the " + channel + " channel from " + span + " (block time); the later behavior, '" + sb.id +
                       "', drives the channel there",
                   false};
      emit(f);
    };
    for (const Active& other : blocks_)
      if (other.character == who)
        for (const Claim& c : other.claims)
          if (channelsOverlap(c.channel, channel)) report(other.blockId, c);
    for (const Claim& c : a.claims)
      if (channelsOverlap(c.channel, channel)) report(a.blockId, c);
    a.claims.push_back(std::move(claim));
  }
}

std::optional<std::pair<std::string, std::string>> Realizer::channelOwner(std::string_view character,
                                                                         std::string_view channel,
                                                                         double sceneTime) const {
  const Claim* best = nullptr;
  const Active* bestBlock = nullptr;
  for (const Active& b : blocks_) {
    if (b.character != character) continue;
    for (const Claim& c : b.claims)
      if (channelsOverlap(c.channel, std::string(channel)) && c.start <= sceneTime && sceneTime <= c.end &&
          (!best || c.order > best->order)) {
        best = &c;
        bestBlock = &b;
      }
  }
  if (!best) return std::nullopt;
  return std::pair{bestBlock->blockId, best->behaviorId};
}

Feedback Realizer::syncFeedback(Feedback::Kind kind, const Active& block, const Event& e) {
  Feedback f;
  f.kind = kind;
  f.character = block.character;
  f.blockId = block.blockId;
  f.behaviorId = e.behaviorId;
  f.syncPoint = e.syncPoint;
  f.blockTime = e.blockTime;
  f.sceneTime = e.sceneTime;
  return f;
}

void Realizer::finish(Active& block, double sceneTime) {
  Feedback f;
  f.kind = Feedback::Kind::BlockProgress;
  f.character = block.character;
  f.blockId = block.blockId;
  f.syncPoint = "end";
  f.sceneTime = sceneTime;
  f.blockTime = sceneTime - block.start;
  emit(f);
}

void Realizer::update() {
  const double now = scene_.time();
  for (Active& b : blocks_) {
    if (!b.started && now >= b.start) {
      b.started = true;
      Feedback f;
      f.kind = Feedback::Kind::BlockProgress;
      f.character = b.character;
      f.blockId = b.blockId;
      f.syncPoint = "start";
      f.sceneTime = b.start;
      emit(f);
    }
    while (b.started && b.next < b.events.size() && b.events[b.next].sceneTime <= now) {
      emit(syncFeedback(Feedback::Kind::SyncPointProgress, b, b.events[b.next++]));
    }
  }
  // Blocks whose last sync point has passed end now.
  for (Active& b : blocks_)
    if (b.started && b.next == b.events.size() && now >= b.end) finish(b, b.end);
  blocks_.erase(std::remove_if(blocks_.begin(), blocks_.end(),
                               [&](const Active& b) { return b.started && b.next == b.events.size() && now >= b.end; }),
                blocks_.end());
}

bool Realizer::interrupt(std::string_view blockId) {
  auto it = std::find_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.blockId == blockId; });
  if (it == blocks_.end()) return false;
  finish(*it, scene_.time());
  blocks_.erase(it);
  return true;
}

std::optional<double> Realizer::blockStart(std::string_view blockId) const {
  for (const Active& b : blocks_)
    if (b.blockId == blockId) return b.start;
  return std::nullopt;
}

}  // namespace marionette::bml
