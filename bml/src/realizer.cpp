#include "marionette/bml/realizer.hpp"

#include "marionette/core/text.hpp"

#include <algorithm>
#include <tuple>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace marionette::bml {

std::string xmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  appendXmlEscaped(out, text);
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
    case Kind::Event:  // SmartBody's form of the message; not a BML 1.0 feedback element
      return "<sbm:event xmlns:sbm=\"http://ict.usc.edu\" id=\"" + id + ":" + xmlEscape(syncPoint) + "\" time=\"" +
             number(blockTime) + "\"" + global + who + " message=\"" + xmlEscape(message) + "\"/>";
    case Kind::Warning:
      return "<warningFeedback" + ns + " id=\"" + id + "\" type=\"" + std::string(toString(warning.type)) + "\"" +
             who + ">" + xmlEscape(warning.message) + "</warningFeedback>";
  }
  return {};
}

void Realizer::emit(const Feedback& f) {
  for (const FeedbackListener& l : listeners_) l(f);
  if (f.kind == Feedback::Kind::Warning) {
    if (forwardWarnings_) scene_.log(f.warning.fatal ? LogLevel::Error : LogLevel::Warning, f.xml());
    return;
  }
  if (f.kind == Feedback::Kind::Prediction) return;
  if (f.kind == Feedback::Kind::Event) {
    if (Character* c = scene_.findCharacter(f.character))
      scene_.forEachListener([&](SceneListener& l) { l.onMessage(*c, f.message, f.sceneTime); });
    return;
  }
  if (Character* c = scene_.findCharacter(f.character)) {
    const std::string sync = f.kind == Feedback::Kind::BlockProgress ? f.syncPoint : f.behaviorId + ":" + f.syncPoint;
    scene_.forEachListener([&](SceneListener& l) { l.onBehaviorProgress(*c, f.blockId, sync, f.sceneTime); });
  }
}

namespace {
std::pair<std::string, std::string> splitRequestId(std::string_view id) {
  const std::size_t colon = id.find(':');
  if (colon == std::string_view::npos) return {std::string(id), {}};
  return {std::string(id.substr(0, colon)), std::string(id.substr(colon + 1))};
}
}  // namespace

void Realizer::warn(const std::string& character, const std::string& blockId, double sceneTime, Warning warning) {
  Feedback f;
  f.kind = Feedback::Kind::Warning;
  f.character = character;
  f.blockId = warning.blockId.empty() ? blockId : warning.blockId;
  f.behaviorId = warning.behaviorId;
  f.sceneTime = sceneTime;
  f.warning = std::move(warning);
  emit(f);
}

SchedulerOptions::ExternalSync Realizer::resolveExternal(const SyncRef& ref, double blockStart) const {
  auto block = std::find_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.blockId == ref.block; });
  if (block == blocks_.end())
    return {std::nullopt, "no block '" + ref.block + "' is queued on the realizer (it has ended, failed, or was never performed)"};
  const std::string wanted = syncKey(ref.syncPoint) + (ref.repetition > 1 ? ":" + std::to_string(ref.repetition) : "");
  bool behaviorFound = false;
  for (const Event& e : block->events) {
    if (e.behaviorId != ref.behavior) continue;
    behaviorFound = true;
    if (syncKey(e.syncPoint) == wanted) return {e.sceneTime - blockStart, {}};
  }
  if (!behaviorFound) return {std::nullopt, "block '" + ref.block + "' has no behavior '" + ref.behavior + "'"};
  return {std::nullopt, "behavior '" + ref.behavior + "' of block '" + ref.block + "' has no sync point '" + ref.syncPoint +
                            (ref.repetition > 1 ? ":" + std::to_string(ref.repetition) : "") + "'"};
}

std::pair<std::string, Character*> Realizer::performer(const ParseResult& parsed, std::string_view character) const {
  std::string who(character);
  if (who.empty() && parsed.block) who = parsed.block->characterId;
  if (who.empty() && !scene_.characters().empty()) who = scene_.characters().front()->name();
  Character* target = scene_.findCharacter(who);
  return {std::move(who), target};
}

void Realizer::setDialect(std::string_view character, Dialect dialect) {
  for (auto& [who, d] : characterDialects_)
    if (who == character) {
      d = dialect;
      return;
    }
  characterDialects_.emplace_back(character, dialect);
}

Dialect Realizer::dialectFor(std::string_view character) const {
  for (const auto& [who, d] : characterDialects_)
    if (who == character) return d;
  return dialect_;
}

Dialect Realizer::dialectOfBlock(std::string_view bmlText, std::string_view character) const {
  if (characterDialects_.empty()) return dialect_;
  if (!character.empty()) return dialectFor(character);
  // The performer is the block's characterId: read it as leniently as any dialect would (a
  // SmartBody block has no id to fail on), then parse the block for real in its dialect.
  const ParseResult peek = parseBlock(bmlText, ParseOptions{Dialect::SmartBody, "peek"});
  return dialectFor(performer(peek, {}).first);
}

bool Realizer::Held::ready() const noexcept {
  return std::all_of(lines.begin(), lines.end(), [](const auto& line) { return line->ready(); });
}

Schedule Realizer::perform(std::string_view bmlText, std::string_view character, const SchedulerOptions& options,
                           std::optional<double> at) {
  const ParseOptions parse{dialectOfBlock(bmlText, character), "sbm_block_" + std::to_string(++performed_)};
  if (speechSynthesis_ == SpeechSynthesis::Background) {
    if (std::optional<Schedule> held = holdForSpeech(bmlText, parse, character, options, at)) return std::move(*held);
  } else if (!held_.empty()) {
    waitForSpeech();  // held before the switch to Inline: they go first, in order
  }
  return realize(bmlText, parse, character, options, at);
}

std::optional<Schedule> Realizer::holdForSpeech(std::string_view bmlText, const ParseOptions& parse,
                                                std::string_view character,
                                                const SchedulerOptions& options, std::optional<double> at) {
  // A block without speech, with none held before it, goes straight on (and is not parsed twice).
  if (held_.empty() && bmlText.find("speech") == std::string_view::npos) return std::nullopt;
  const ParseResult parsed = parseBlock(bmlText, parse);
  const auto [who, target] = performer(parsed, character);
  if (!parsed.block || !target) return std::nullopt;  // fails now, with its reason
  Held h{std::string(bmlText), who, parsed.block->id, parse, options, at, {}};
  // Even with the caller's own speech timing: the speech behavior says its line when realized.
  for (const Behavior& b : parsed.block->behaviors)
    if (auto line = prepareSpeechTiming(b, *target)) h.lines.push_back(std::move(line));
  if (held_.empty() && h.ready()) return std::nullopt;  // said already (cached): realize now
  Schedule s;
  s.blockId = h.blockId;
  s.heldForSpeech = true;
  held_.push_back(std::move(h));
  return s;
}

void Realizer::realizeHeld() {
  // In order; realize() may call listeners that perform() again: nothing is kept across it.
  while (!held_.empty() && held_.front().ready()) {
    Held h = std::move(held_.front());
    held_.pop_front();
    // Not before the time it was sent for (a scene file's block at 5 s), nor in the past.
    const double now = scene_.time();
    struct Pinned {  // the lines as said in the background, whatever the cache did meanwhile
      speech::SpeechService& service;
      const std::vector<std::shared_ptr<const speech::SpeechService::Preparation>>& lines;
      ~Pinned() { service.unpin(lines); }
    } pinned{scene_.speech(), h.lines};
    scene_.speech().pin(h.lines);
    (void)realize(h.text, h.parse, h.character, h.options, h.at && std::isfinite(*h.at) ? std::max(*h.at, now) : now);
  }
}

void Realizer::waitForSpeech() {
  while (!held_.empty()) {
    scene_.speech().waitUntilPrepared();
    realizeHeld();
  }
}

Schedule Realizer::realize(std::string_view bmlText, const ParseOptions& parse, std::string_view character,
                           const SchedulerOptions& options, std::optional<double> at, bool activation) {
  ParseResult parsed = parseBlock(bmlText, parse);
  // <bmlt:audiofile>: the WAVs are read now; one that cannot be played leaves the block here.
  AudioFileAccess files = files_;
  if (!options.fileDirectory.empty()) files.directory = options.fileDirectory;
  const std::vector<LoadedAudio> audio =
      parsed.block ? loadAudioFiles(*parsed.block, files, parsed.warnings) : std::vector<LoadedAudio>{};
  // Plain variables, not a structured binding: lambdas below capture them (clang 14 cannot capture bindings).
  const std::pair<std::string, Character*> performed = performer(parsed, character);
  const std::string& who = performed.first;
  Character* const target = performed.second;
  const double now = at && std::isfinite(*at) ? *at : scene_.time();

  // Composition decides the start first: references to other blocks are relative to it.
  const std::string composition = parsed.block ? parsed.block->composition : std::string();
  double start = now;
  if (composition == "APPEND")
    for (const Active& b : blocks_)
      if (b.character == who) start = std::max(start, b.end);
  const Block::Bmla noBmla;
  const Block::Bmla& bmla = parsed.block ? parsed.block->bmla : noBmla;
  std::vector<std::string> notQueued;
  start = bmlaStart(bmla, start, notQueued);
  SchedulerOptions opts = options;
  if (!opts.externalSync) opts.externalSync = [&](const SyncRef& ref) { return resolveExternal(ref, start); };
  if (!opts.defaultDuration && target)
    opts.defaultDuration = [target](const Behavior& b) { return naturalDuration(b, *target); };
  if (!opts.speechTiming && target)
    opts.speechTiming = [target](const Behavior& b) { return speechTiming(b, *target); };
  if (!audio.empty())  // a sound lasts as long as its WAV, whatever else gives durations
    opts.defaultDuration = [&audio, other = opts.defaultDuration](const Behavior& b) -> std::optional<double> {
      if (b.type != "audiofile") return other ? other(b) : std::nullopt;
      for (const LoadedAudio& a : audio)
        if (a.behaviorId == b.id) return a.clip->duration();
      return std::nullopt;
    };
  Schedule schedule = scheduleParsed(parsed, opts);

  if (!schedule.failed && !target) {
    schedule.warnings.push_back({WarningType::NoSuchTarget, schedule.blockId, "", parsed.block->line, parsed.block->column,
                                 who.empty() ? "the scene has no character to perform the block"
                                             : "the scene has no character named '" + who + "'",
                                 true});
    schedule.failed = true;
  }
  for (const std::string& id : notQueued)
    schedule.warnings.push_back({WarningType::NoSuchTarget, schedule.blockId, "", parsed.block->line, parsed.block->column,
                                 "BMLA: block '" + id + "' (appendAfter/chunkAfter) is neither queued nor finished; "
                                 "this block does not wait for it",
                                 false});
  if (!schedule.failed && !activation) {
    for (const Planned& p : preplanned_)
      if (p.blockId == schedule.blockId) {
        schedule.warnings.push_back({WarningType::ImpossibleToSchedule, schedule.blockId, "", parsed.block->line,
                                     parsed.block->column,
                                     "a preplanned block with id '" + p.blockId + "' waits for activation; block ids must be unique",
                                     true});
        schedule.failed = true;
      }
    for (const Active& b : blocks_)
      if (b.blockId == schedule.blockId && !(composition == "REPLACE" && b.character == who)) {
        schedule.warnings.push_back({WarningType::ImpossibleToSchedule, schedule.blockId, "", parsed.block->line,
                                     parsed.block->column,
                                     "a block with id '" + b.blockId + "' is still queued (for '" + b.character +
                                         "'); block ids must be unique while their blocks run",
                                     true});
        schedule.failed = true;
        break;
      }
  }
  if (!activation)  // an activated block's were said when it was planned
    for (const Warning& w : schedule.warnings) warn(who, schedule.blockId, now, w);
  if (schedule.failed) return schedule;
  if (bmla.preplan && !activation) {  // checked; realized when activated
    preplanned_.push_back({std::string(bmlText), who, schedule.blockId, parse, options});
    schedule.preplanned = true;
    return schedule;
  }
  // BMLA's interrupt and onStart act when the block starts: now, or when update() reaches it.
  const bool startsNow = start <= now + 1e-9;
  if (startsNow)
    for (const std::string& id : bmla.interrupt)
      if (id != schedule.blockId) (void)interrupt(id);

  if (composition == "REPLACE") {
    for (Active& b : blocks_)
      if (b.character == who) {
        finish(b, now);
        target->cancelBehaviors(b.blockId + ":", replaceBlend_);
      }
    blocks_.erase(std::remove_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.character == who; }),
                  blocks_.end());
  }
  Active a;
  a.character = who;
  a.blockId = schedule.blockId;
  a.start = start;
  if (!startsNow) {
    a.interruptOnStart = bmla.interrupt;
    a.activateOnStart = bmla.onStart;
  }
  double blockEnd = 0.0, relaxed = 0.0;
  for (const ScheduledBehavior& b : schedule.behaviors) {
    const auto parsedIt = std::find_if(parsed.block->behaviors.begin(), parsed.block->behaviors.end(),
                                       [&](const Behavior& p) { return p.id == b.id; });
    const bool locomotion = parsedIt != parsed.block->behaviors.end() && parsedIt->type == "locomotion";
    const std::string type = parsedIt != parsed.block->behaviors.end() ? parsedIt->type : std::string();
    // The sync point that acts, and how: an <event>'s stroke, a BMLA interrupt's or activate's start.
    const auto [actsAt, action, argumentName] =
        type == "event"       ? std::tuple{"stroke", Event::Action::Message, "message"}
        : type == "interrupt" ? std::tuple{"start", Event::Action::Interrupt, "target"}
        : type == "activate"  ? std::tuple{"start", Event::Action::Activate, "target"}
        : type == "blend"     ? std::tuple{"start", Event::Action::Blend, "name"}
                              : std::tuple{"", Event::Action::None, ""};
    for (const SyncTime& s : b.syncs) {
      const bool acts = action != Event::Action::None && s.name == actsAt;
      const Attribute* argument = acts ? parsedIt->attribute(argumentName) : nullptr;
      a.events.push_back({start + s.time, b.id, s.name, s.time, locomotion && s.name == "end",
                          acts ? action : Event::Action::None, argument ? argument->value : std::string()});
      if (acts && action == Event::Action::Blend) {  // the point, read as toRequest reads it
        const SmartBodyBlend blend = readSmartBodyBlend(*parsedIt, target->rig());
        a.events.back().x = blend.x;
        a.events.back().y = blend.y;
      }
      blockEnd = std::max(blockEnd, s.time);
      if (s.name == (b.time("relax") ? "relax" : "end")) relaxed = std::max(relaxed, s.time);
    }
  }
  std::stable_sort(a.events.begin(), a.events.end(), [](const Event& x, const Event& y) { return x.sceneTime < y.sceneTime; });
  a.end = start + blockEnd;
  a.relaxed = start + relaxed;
  if (!submit(*target, a, *parsed.block, schedule, audio)) return schedule;
  for (const Event& e : a.events) emit(syncFeedback(Feedback::Kind::Prediction, a, e));
  blocks_.push_back(std::move(a));
  if (startsNow)
    for (const std::string& id : bmla.onStart) (void)activate(id);
  return schedule;
}

bool Realizer::submit(Character& character, const Active& a, const Block& block, Schedule& schedule,
                      const std::vector<LoadedAudio>& audio) {
  const double now = scene_.time();
  for (const ScheduledBehavior& sb : schedule.behaviors) {
    auto parsedIt = std::find_if(block.behaviors.begin(), block.behaviors.end(),
                                 [&](const Behavior& b) { return b.id == sb.id; });
    if (parsedIt == block.behaviors.end() || sb.syncs.empty()) continue;
    MappedRequest mapped = toRequest(*parsedIt, sb, a.blockId, a.start, character.rig());
    for (const LoadedAudio& sound : audio)  // the clip read for it (realize)
      if (sound.behaviorId == sb.id) mapped.request.parameters = AudioParameters{sound.clip, sound.file};
    BehaviorResult res = character.addBehavior(std::move(mapped.request));
    // The attributes' own reasons come first: the character saw only what could be read of them.
    if (!mapped.error.empty()) {  // e.g. a saccade: on the timeline as a wait, yet nothing moves
      res.realized = false;
      res.message = mapped.error;
    }
    if (res.realized && !mapped.warning.empty())
      res.message = res.message.empty() ? mapped.warning : mapped.warning + "; " + res.message;
    if (!res.added) {
      Warning w{WarningType::CannotCreateBehavior, a.blockId, sb.id, sb.line, sb.column, res.message, sb.required};
      if (sb.required) {
        w.message += "; being required, it made the block fail";
        character.cancelBehaviors(a.blockId + ":", 0.0);
        schedule.failed = true;
      }
      schedule.warnings.push_back(w);
      warn(a.character, a.blockId, now, std::move(w));
      if (schedule.failed) return false;
      continue;
    }
    const std::span<const BehaviorTimeline::Entry> entries = character.behaviors().entries();
    reportConflicts(character, a, entries.back(), *parsedIt, schedule);
    if (res.realized && !res.message.empty()) {  // realized with a bad parameter replaced
      Warning w{WarningType::ParsingFailure, a.blockId, sb.id, sb.line, sb.column, res.message, false};
      schedule.warnings.push_back(w);
      warn(a.character, a.blockId, now, std::move(w));
    }
    if (!res.realized && reportUnrealized_) {
      Warning w{WarningType::CannotCreateBehavior, a.blockId, sb.id, sb.line, sb.column,
                "character '" + character.name() + "': " + res.message, false};
      schedule.warnings.push_back(w);
      warn(a.character, a.blockId, now, std::move(w));
    }
  }
  return true;
}

void Realizer::reportConflicts(const Character& character, const Active& a, const BehaviorTimeline::Entry& added,
                               const Behavior& behavior, Schedule& schedule) {
  // The new request overlaps earlier ones (of this block or another) on a
  // channel: it wins there (the timeline blends it over), with one warning that
  // names the latest of them (one per behavior, so warnings stay linear in the input).
  const BodyChannel bits = added.request.channelBits();
  if (!any(bits)) return;
  const BehaviorTimeline::Entry* latest = nullptr;
  double from = 0.0, to = 0.0;
  std::size_t others = 0;
  const auto entries = character.behaviors().entries();
  for (auto it = entries.rbegin(); it != entries.rend(); ++it) {
    const BehaviorTimeline::Entry& other = *it;
    if (other.order >= added.order || !any(other.request.channelBits() & bits)) continue;
    const double f = std::max(added.request.start(), other.request.start());
    const double t = std::min(added.request.end(), std::min(other.request.end(), other.finishTime()));
    if (t <= f) continue;
    if (latest) {
      ++others;
      continue;
    }
    latest = &other;
    from = f;
    to = t;
  }
  if (!latest) return;
  const auto [otherBlock, otherBehavior] = splitRequestId(latest->request.id);
  char span[64];
  std::snprintf(span, sizeof span, "%.3g s to %.3g s", from - a.start, to - a.start);
  Warning w{WarningType::ImpossibleToSchedule, a.blockId, behavior.id, behavior.line, behavior.column,
            "overlaps behavior '" + otherBehavior + "'" + (otherBlock == a.blockId ? "" : " of block '" + otherBlock + "'") +
                (others ? " (and " + std::to_string(others) + " other" + (others > 1 ? "s" : "") + ")" : "") +
                " on the " + channelNames(latest->request.channelBits() & bits) + " channel from " + span +
                " (block time); the later behavior, '" + behavior.id + "', drives the channel there",
            false};
  schedule.warnings.push_back(w);
  warn(a.character, a.blockId, scene_.time(), std::move(w));
}

std::optional<std::pair<std::string, std::string>> Realizer::channelOwner(std::string_view character,
                                                                         std::string_view channel,
                                                                         double sceneTime) const {
  Character* c = scene_.findCharacter(character);
  const BodyChannel bits = channelFromName(channel);
  if (!c || !any(bits)) return std::nullopt;
  const BehaviorRequest* owner = c->behaviors().owner(bits, sceneTime);
  if (!owner) return std::nullopt;
  return splitRequestId(owner->id);
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
  finished_.push_back(block.blockId);
  if (finished_.size() > kFinishedKept) finished_.pop_front();
  Feedback f;
  f.kind = Feedback::Kind::BlockProgress;
  f.character = block.character;
  f.blockId = block.blockId;
  f.syncPoint = "end";
  f.sceneTime = sceneTime;
  f.blockTime = sceneTime - block.start;
  emit(f);
}

bool Realizer::arrived(Active& b, Event& e, double now) {
  // The scheduled end was an estimate; the character says when it arrived. A
  // locomotion that was replaced, cancelled or never started ends now.
  const Character* c = scene_.findCharacter(b.character);
  const LocomotionStatus st = c ? c->locomotionStatus(b.blockId + ":" + e.behaviorId) : LocomotionStatus{};
  if (st.state == LocomotionStatus::State::Pending || st.state == LocomotionStatus::State::Moving) return false;
  const double at = st.state == LocomotionStatus::State::Done && st.doneTime >= 0.0 ? st.doneTime : now;
  e.blockTime += at - e.sceneTime;
  e.sceneTime = at;
  b.end = std::max(b.end, at);
  return true;
}

void Realizer::update() {
  if (!held_.empty()) realizeHeld();
  const double now = scene_.time();
  // Interrupting and activating change blocks_: collected here, run after the walk.
  std::vector<Action> actions;
  for (Active& b : blocks_) {
    if (!b.started && now >= b.start) {
      b.started = true;
      for (std::string& id : b.interruptOnStart)
        if (id != b.blockId) actions.emplace_back(Event::Action::Interrupt, std::move(id));
      for (std::string& id : b.activateOnStart) actions.emplace_back(Event::Action::Activate, std::move(id));
      Feedback f;
      f.kind = Feedback::Kind::BlockProgress;
      f.character = b.character;
      f.blockId = b.blockId;
      f.syncPoint = "start";
      f.sceneTime = b.start;
      emit(f);
    }
    while (b.started && b.next < b.events.size() && b.events[b.next].sceneTime <= now) {
      Event& e = b.events[b.next];
      if (e.onArrival && !arrived(b, e, now)) break;  // holds this block's later feedback too, keeping order
      emit(syncFeedback(Feedback::Kind::SyncPointProgress, b, e));
      if (e.action == Event::Action::Message) {
        Feedback f = syncFeedback(Feedback::Kind::Event, b, e);
        f.message = e.argument;
        emit(f);
      } else if (e.action == Event::Action::Blend) {
        startBlend(b.character, e);
      } else if (e.action != Event::Action::None) {
        actions.emplace_back(e.action, e.argument);
      }
      ++b.next;
    }
  }
  // Blocks whose last sync point has passed end now.
  for (Active& b : blocks_)
    if (b.started && b.next == b.events.size() && now >= b.end) finish(b, b.end);
  blocks_.erase(std::remove_if(blocks_.begin(), blocks_.end(),
                               [&](const Active& b) { return b.started && b.next == b.events.size() && now >= b.end; }),
                blocks_.end());
  run(actions);
}

void Realizer::startBlend(const std::string& character, const Event& e) {
  Character* c = scene_.findCharacter(character);
  if (!c) return;
  // The same space goes on with a new point; another replaces the layer (the character logs
  // a space its rig has not: toRequest reported it already as CANNOT_CREATE_BEHAVIOR).
  const BlendSpace* playing = c->layerBlendSpace(blendLayer_);
  if (playing && playing->name() == e.argument) (void)c->setBlendParameter(blendLayer_, e.x, e.y);
  else if (c->rig().findBlendSpace(e.argument)) (void)c->playBlend(blendLayer_, e.argument, {}, e.x, e.y);
}

void Realizer::run(const std::vector<Action>& actions) {
  for (const auto& [action, block] : actions) {
    if (action == Event::Action::Interrupt) (void)interrupt(block);
    if (action == Event::Action::Activate) (void)activate(block);
  }
}

double Realizer::bmlaStart(const Block::Bmla& bmla, double start, std::vector<std::string>& unknown) const {
  auto after = [&](const std::vector<std::string>& ids, bool chunk) {
    for (const std::string& id : ids) {
      const auto it = std::find_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.blockId == id; });
      if (it != blocks_.end()) start = std::max(start, chunk ? it->relaxed : it->end);
      else if (!finishedRecently(id)) unknown.push_back(id);
    }
  };
  after(bmla.appendAfter, false);
  after(bmla.chunkAfter, true);
  return start;
}

bool Realizer::finishedRecently(std::string_view blockId) const {
  return std::find(finished_.begin(), finished_.end(), blockId) != finished_.end();
}

bool Realizer::activate(std::string_view blockId) {
  const auto it = std::find_if(preplanned_.begin(), preplanned_.end(), [&](const Planned& p) { return p.blockId == blockId; });
  if (it == preplanned_.end()) return false;
  Planned p = std::move(*it);
  preplanned_.erase(it);
  (void)realize(p.text, p.parse, p.character, p.options, scene_.time(), true);
  return true;
}

bool Realizer::interrupt(std::string_view blockId) {
  const auto planned =
      std::find_if(preplanned_.begin(), preplanned_.end(), [&](const Planned& p) { return p.blockId == blockId; });
  if (planned != preplanned_.end()) {  // never started: dropped without feedback
    preplanned_.erase(planned);
    return true;
  }
  auto it = std::find_if(blocks_.begin(), blocks_.end(), [&](const Active& b) { return b.blockId == blockId; });
  if (it == blocks_.end()) {  // not running: perhaps held, never started (no feedback was sent for it)
    const auto held = std::find_if(held_.begin(), held_.end(), [&](const Held& h) { return h.blockId == blockId; });
    if (held == held_.end()) return false;
    held_.erase(held);
    return true;
  }
  finish(*it, scene_.time());
  if (Character* c = scene_.findCharacter(it->character)) c->cancelBehaviors(it->blockId + ":", replaceBlend_);
  blocks_.erase(it);
  return true;
}

std::optional<double> Realizer::blockStart(std::string_view blockId) const {
  for (const Active& b : blocks_)
    if (b.blockId == blockId) return b.start;
  return std::nullopt;
}

}  // namespace marionette::bml
