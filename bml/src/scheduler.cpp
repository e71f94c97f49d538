#include "marionette/bml/scheduler.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "marionette/bml/sync_ref.hpp"

namespace marionette::bml {

std::string syncKey(std::string_view name) {
  std::string out(name);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  out.erase(std::remove(out.begin(), out.end(), '-'), out.end());  // "stroke-end" = "strokeEnd"
  return out;
}

namespace {

constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
constexpr double kEpsilon = 1e-6;

// Default sync times: proportions of a default duration, in the standard order.
SyncTemplate fromProportions(std::initializer_list<std::pair<const char*, double>> p, double duration,
                             bool stretchable = true) {
  SyncTemplate t;
  t.stretchable = stretchable;
  for (auto [name, f] : p) t.syncs.push_back({name, f * duration});
  return t;
}

// repetition="R": a whole number >= 1; anything else counts as 1. Values above
// kMaxBehaviorRepetitions are clamped (digits are read saturating, so no overflow).
int repetitionsOf(const Behavior& b) {
  const Attribute* a = b.attribute("repetition");
  if (!a || a->value.empty()) return 1;
  long long n = 0;
  for (char c : a->value) {
    if (c < '0' || c > '9') return 1;
    n = std::min<long long>(n * 10 + (c - '0'), kMaxBehaviorRepetitions);
  }
  return n < 1 ? 1 : static_cast<int>(n);
}

bool repeats(std::string_view type) { return type == "head" || type == "gesture" || type == "pointing"; }

// The full BML 1.0 phase structure with the stroke phase repeated `reps` times,
// each repetition `unit` long. The proportions of one repetition (.1 .2 .3 .5 .8 1)
// are kept at the ends; the stroke phases share the time between ready and relax,
// each starting, peaking and ending at 1/7, 2/7 and 4/7 of its period.
SyncTemplate repeatedStroke(double unit, int reps) {
  SyncTemplate t;
  t.repetitions = reps;
  t.syncs.reserve(4 + 3 * static_cast<std::size_t>(reps));
  const double total = reps * unit;
  const double ready = 0.1 * unit;
  const double period = (total - 0.3 * unit) / reps;
  t.syncs.push_back({"start", 0.0});
  t.syncs.push_back({"ready", ready});
  for (int n = 1; n <= reps; ++n) {
    const std::string suffix = n == 1 ? "" : ":" + std::to_string(n);
    const double from = ready + (n - 1) * period;
    t.syncs.push_back({"strokeStart" + suffix, from + period / 7});
    t.syncs.push_back({"stroke" + suffix, from + 2 * period / 7});
    t.syncs.push_back({"strokeEnd" + suffix, from + 4 * period / 7});
  }
  t.syncs.push_back({"relax", total - 0.2 * unit});
  t.syncs.push_back({"end", total});
  return t;
}

}  // namespace

SyncTemplate defaultSyncs(const Behavior& b, const SchedulerOptions& options) {
  const std::string& t = b.type;
  if (t == "speech") {
    SyncTemplate s;
    s.stretchable = false;  // speech keeps its own timing
    const double spc = options.speechSecondsPerCharacter;
    std::optional<SpeechTiming> said;
    if (options.speechTiming) said = options.speechTiming(b);
    if (said && !(std::isfinite(said->duration) && said->duration >= 0.0)) said.reset();
    double end = std::max(options.minimumSpeechSeconds, static_cast<double>(b.text.size()) * spc);
    if (said) end = said->duration;
    s.syncs.push_back({"start", 0.0});
    double last = 0.0;  // marks stay in text order and inside the speech
    for (const WordMark& m : b.marks) {
      double at = static_cast<double>(m.characterOffset) * spc;
      if (said)
        for (const auto& [id, time] : said->marks)
          if (id == m.id && std::isfinite(time)) at = time;
      last = std::clamp(at, last, end);
      s.syncs.push_back({m.id, last});
    }
    s.syncs.push_back({"end", end});
    return s;
  }
  if (t == "wait") return fromProportions({{"start", 0}, {"end", 1}}, 0.0);
  // An event is an instant: SmartBody times it by its stroke, BML by its start.
  if (t == "event") return fromProportions({{"start", 0}, {"stroke", 0}, {"end", 0}}, 0.0, false);
  if (t == "interrupt" || t == "activate") return fromProportions({{"start", 0}, {"end", 0}}, 0.0, false);
  // The character's own length for the behavior, when it knows one. Checked against
  // the repetition cap too, so that R times it stays finite.
  std::optional<double> natural;
  if (options.defaultDuration)
    if (auto d = options.defaultDuration(b); d && std::isfinite(*d * kMaxBehaviorRepetitions) && *d > 0) natural = *d;
  // Gestures and head movements have the full BML 1.0 phase structure.
  if (repeats(t)) return repeatedStroke(natural.value_or(t == "head" ? 1.0 : 2.0), repetitionsOf(b));
  if (t == "animation") return repeatedStroke(natural.value_or(2.0), 1);  // a gesture's phases, once
  if (t == "gaze" || t == "posture" || t == "locomotion")
    return fromProportions({{"start", 0}, {"ready", .25}, {"relax", .75}, {"end", 1}}, natural.value_or(2.0));
  if (t == "faceLexeme" || t == "faceFacs" || t == "face")
    return fromProportions({{"start", 0}, {"attackPeak", .2}, {"relax", .8}, {"end", 1}}, natural.value_or(1.5));
  // gazeShift, headDirectionShift, postureShift, faceShift: a transition to a new state.
  return fromProportions({{"start", 0}, {"end", 1}}, natural.value_or(1.0));
}

std::optional<double> ScheduledBehavior::time(std::string_view sync) const {
  const std::string key = syncKey(sync);
  for (const SyncTime& s : syncs)
    if (syncKey(s.name) == key) return s.time;
  return std::nullopt;
}

const ScheduledBehavior* Schedule::find(std::string_view id) const noexcept {
  for (const ScheduledBehavior& b : behaviors)
    if (b.id == id) return &b;
  return nullptr;
}

std::optional<double> Schedule::time(std::string_view behavior, std::string_view sync) const {
  const ScheduledBehavior* b = find(behavior);
  return b ? b->time(sync) : std::nullopt;
}

namespace {

// Union-find over pegs with offsets: time(x) = time(root(x)) + offset(x).
class PegGroups {
 public:
  int add() {
    parent_.push_back(static_cast<int>(parent_.size()));
    offset_.push_back(0.0);
    return parent_.back();
  }
  [[nodiscard]] std::size_t size() const noexcept { return parent_.size(); }
  std::pair<int, double> find(int x) {
    double off = 0.0;
    int r = x;
    while (parent_[r] != r) {
      off += offset_[r];
      r = parent_[r];
    }
    // Path compression keeping offsets exact.
    double rest = off;
    for (int y = x; parent_[y] != y;) {
      const int next = parent_[y];
      const double o = offset_[y];
      parent_[y] = r;
      offset_[y] = rest;
      rest -= o;
      y = next;
    }
    return {r, off};
  }
  // Requires time(a) + da == time(b) + db. False on a contradiction.
  bool unite(int a, double da, int b, double db) {
    auto [ra, oa] = find(a);
    auto [rb, ob] = find(b);
    // time(ra) + oa + da == time(rb) + ob + db
    if (ra == rb) return std::fabs((oa + da) - (ob + db)) < kEpsilon;
    parent_[rb] = ra;
    offset_[rb] = (oa + da) - (ob + db);
    return true;
  }

 private:
  std::vector<int> parent_;
  std::vector<double> offset_;
};

struct Peg {
  int behavior;
  std::size_t sync;
};

class Scheduler {
 public:
  Scheduler(const Block& block, const SchedulerOptions& options) : block_(block), options_(options) {}

  Schedule run() {
    Schedule out;
    out.blockId = block_.id;
    out.dialect = block_.smartBody ? Dialect::SmartBody : Dialect::Bml;
    active_.assign(block_.behaviors.size(), true);
    std::size_t syncPoints = 0;
    for (const Behavior& b : block_.behaviors) {
      templates_.push_back(defaultSyncs(b, options_));
      syncPoints += templates_.back().syncs.size();
      if (syncPoints > kMaxSyncPointsPerBlock) {
        out.warnings.push_back({WarningType::ImpossibleToSchedule, block_.id, b.id, b.line, b.column,
                                "the block has more than " + std::to_string(kMaxSyncPointsPerBlock) +
                                    " sync points (repetitions included) by this behavior; the block failed "
                                    "(split it, or repeat less)",
                                true});
        out.failed = true;
        return out;
      }
      std::vector<std::string> keys;
      for (const SyncTime& sync : templates_.back().syncs) keys.push_back(syncKey(sync.name));
      keys_.push_back(std::move(keys));
    }
    // Solve, remove what cannot be met (or retry with a rigid behavior placed
    // first), solve again; each pass removes a behavior or marks one to place first.
    for (std::size_t pass = 0; pass <= 2 * block_.behaviors.size() + 1; ++pass) {
      if (solve()) break;
    }
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) {
      if (!active_[i]) continue;
      const Behavior& b = block_.behaviors[i];
      ScheduledBehavior s{b.id, b.type, {}, b.required, b.line, b.column};
      for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k) s.syncs.push_back({templates_[i].syncs[k].name, times_[i][k]});
      out.behaviors.push_back(std::move(s));
    }
    out.warnings = std::move(warnings_);
    out.failed = failed_;
    return out;
  }

 private:
  // ------------------------------------------------------------------ one pass
  // Returns true when nothing had to be removed.
  bool solve() {
    groups_ = PegGroups();
    blockStart_ = groups_.add();
    pegIds_.assign(block_.behaviors.size(), {});
    dependent_.assign(block_.behaviors.size(), {});
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) dependent_[i].assign(templates_[i].syncs.size(), false);
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i)
      for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k) pegIds_[i].push_back(groups_.add());
    pegCount_ = groups_.size();
    passWarnings_.clear();
    toRemove_.clear();
    applyAttributeConstraints();
    applySynchronizeConstraints();
    if (!toRemove_.empty()) return commitRemovals();
    propagate();
    retry_ = false;
    checkBehaviors();
    if (retry_) {  // place a rigid behavior first and look again before removing anything
      toRemove_.clear();
      return false;
    }
    if (!toRemove_.empty()) return commitRemovals();
    applyOrdering();
    for (Warning& w : passWarnings_) warnings_.push_back(std::move(w));
    return true;
  }

  bool commitRemovals() {
    for (auto& [index, warning] : toRemove_) {
      if (!active_[index]) continue;
      active_[index] = false;
      const Behavior& b = block_.behaviors[index];
      warning.message += "; the behavior was removed";
      if (b.required) {
        warning.fatal = true;
        warning.message += " and, being required, made the block fail";
        failed_ = true;
      }
      warnings_.push_back(std::move(warning));
    }
    return false;
  }

  void removeBehavior(std::size_t index, WarningType type, std::string message, int line, int column) {
    if (toRemove_.count(index)) return;
    toRemove_[index] = Warning{type, block_.id, block_.behaviors[index].id, line, column, std::move(message), false};
  }

  int behaviorIndex(std::string_view id) const {
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i)
      if (active_[i] && block_.behaviors[i].id == id) return static_cast<int>(i);
    return -1;
  }

  int syncIndex(std::size_t behavior, std::string_view name) const {
    const std::string key = syncKey(name);
    const auto& keys = keys_[behavior];
    for (std::size_t k = 0; k < keys.size(); ++k)
      if (keys[k] == key) return static_cast<int>(k);
    return -1;
  }

  // Resolves a reference to (peg, offset). On failure fills `problem`.
  std::optional<std::pair<int, double>> resolve(const SyncRef& ref, std::string& problem, WarningType& type) {
    if (ref.absolute) return std::pair{blockStart_, ref.offset};
    if (!ref.block.empty() && ref.block != block_.id) {
      // Another block's sync point is a fixed time for this block, like a number.
      type = WarningType::NoSuchTarget;
      if (!options_.externalSync) {
        problem = "refers to block '" + ref.block +
                  "', which is not this block (references to other blocks need a Realizer that has that block)";
        return std::nullopt;
      }
      const SchedulerOptions::ExternalSync external = options_.externalSync(ref);
      if (external.time && std::isfinite(*external.time)) return std::pair{blockStart_, *external.time + ref.offset};
      problem = "refers to block '" + ref.block + "': " +
                (external.problem.empty() ? std::string("its sync point is not known") : external.problem);
      return std::nullopt;
    }
    const int b = behaviorIndex(ref.behavior);
    if (b < 0) {
      type = WarningType::NoSuchTarget;
      problem = "refers to behavior '" + ref.behavior + "', which the block does not have (or which was removed)";
      return std::nullopt;
    }
    const Behavior& target = block_.behaviors[b];
    int k = syncIndex(static_cast<std::size_t>(b), ref.syncPoint);
    if (k < 0) {
      type = WarningType::NoSuchTarget;
      problem = "behavior '" + ref.behavior + "' (" + target.type + ") has no sync point '" + ref.syncPoint + "'";
      return std::nullopt;
    }
    if (ref.repetition > 1) {
      // Only the stroke phase repeats; its n-th repetition's syncs carry ":n".
      const std::string key = syncKey(ref.syncPoint);
      const bool repeating = repeats(target.type) && (key == "strokestart" || key == "stroke" || key == "strokeend");
      if (repeating) k = syncIndex(static_cast<std::size_t>(b), ref.syncPoint + ":" + std::to_string(ref.repetition));
      if (!repeating || k < 0) {
        type = WarningType::NoSuchTarget;
        const int reps = templates_[b].repetitions;
        problem = "refers to repetition " + std::to_string(ref.repetition) + " of '" + ref.syncPoint + "', but behavior '" +
                  ref.behavior + "' (" + target.type + ") " +
                  (repeats(target.type) ? "has " + std::to_string(reps) + (reps == 1 ? " repetition" : " repetitions") +
                                              "; only strokeStart, stroke and strokeEnd repeat"
                                        : std::string("does not repeat"));
        return std::nullopt;
      }
    }
    return std::pair{pegIds_[b][k], ref.offset};
  }

  void applyAttributeConstraints() {
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) {
      if (!active_[i]) continue;
      const Behavior& b = block_.behaviors[i];
      for (const Attribute& a : b.attributes) {
        const int k = syncIndex(i, a.name);
        if (k < 0) continue;  // not a sync attribute (lexeme, target, ...)
        const SyncRefParse parsed = parseSyncRef(a.value);
        if (!parsed.ref) {
          removeBehavior(i, WarningType::ParsingFailure,
                         a.name + "=\"" + a.value + "\": " + parsed.error + " (expected a time or [block:]behavior:sync[+/-seconds])",
                         b.line, b.column);
          continue;
        }
        std::string problem;
        WarningType type = WarningType::NoSuchTarget;
        auto target = resolve(*parsed.ref, problem, type);
        if (!target) {
          removeBehavior(i, type, a.name + "=\"" + a.value + "\" " + problem, b.line, b.column);
          continue;
        }
        if (!parsed.ref->absolute) dependent_[i][static_cast<std::size_t>(k)] = true;
        if (!groups_.unite(pegIds_[i][k], 0.0, target->first, target->second))
          removeBehavior(i, WarningType::ImpossibleToSchedule,
                         a.name + "=\"" + a.value + "\" contradicts the block's other timing constraints", b.line, b.column);
      }
    }
  }

  void applySynchronizeConstraints() {
    for (const Constraint& c : block_.constraints) {
      if (c.kind != Constraint::Kind::Synchronize) continue;
      std::optional<std::pair<int, double>> first;
      for (const ConstraintSync& s : c.syncs) {
        auto target = resolveConstraintSync(c, s);
        if (!target) continue;
        if (!first) {
          first = target;
        } else if (!groups_.unite(first->first, first->second, target->first, target->second)) {
          passWarnings_.push_back({WarningType::ImpossibleToSchedule, block_.id, c.id, s.line, s.column,
                                   "<synchronize> on '" + s.ref + "' contradicts the block's other timing constraints; "
                                   "this sync was not synchronized",
                                   c.required});
          if (c.required) failed_ = true;
        }
      }
    }
  }

  std::optional<std::pair<int, double>> resolveConstraintSync(const Constraint& c, const ConstraintSync& s) {
    const SyncRefParse parsed = parseSyncRef(s.ref);
    std::string problem;
    WarningType type = WarningType::ParsingFailure;
    std::optional<std::pair<int, double>> target;
    if (!parsed.ref) problem = "'" + s.ref + "': " + parsed.error;
    else if (!(target = resolve(*parsed.ref, problem, type))) problem = "'" + s.ref + "' " + problem;
    if (!target) {
      passWarnings_.push_back({type, block_.id, c.id, s.line, s.column, "constraint sync " + problem + "; it was left out",
                               c.required});
      if (c.required) failed_ = true;
    }
    return target;
  }

  // ------------------------------------------------------------------ timing
  // Known group times; behaviors take their pegs' times from their defaults.
  void propagate() {
    // Indexed by peg id (dense): NaN = not timed yet, component 0 = anchored.
    known_.assign(pegCount_, kUnknown);
    component_.assign(pegCount_, 0);
    {
      auto [root, off] = groups_.find(blockStart_);
      known_[root] = -off;  // the block start is at 0
    }
    times_.assign(block_.behaviors.size(), {});
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) times_[i].assign(templates_[i].syncs.size(), kUnknown);
    std::vector<bool> done(block_.behaviors.size(), false);
    int freeComponent = 0;
    for (;;) {
      // Most constrained first: rigid behaviors (speech) and behaviors with two or
      // more timed pegs; then a behavior marked to be placed first (seeded at 0 as
      // a free group); only then a stretchable behavior with a single timed peg,
      // so that its defaults never pin a peg a more constrained behavior decides.
      bool progress = false;
      for (std::size_t i = 0; i < block_.behaviors.size(); ++i)
        if (active_[i] && !done[i] && (!templates_[i].stretchable || anchorCount(i) >= 2) && timeBehavior(i))
          done[i] = progress = true;
      if (progress) continue;
      std::size_t seed = block_.behaviors.size();
      for (std::size_t i : placeFirst_)
        if (active_[i] && !done[i] && anchorCount(i) == 0) {
          seed = i;
          break;
        }
      if (seed == block_.behaviors.size()) {
        // A behavior whose own attribute ties an untimed sync point to another
        // behavior (end="tilt:end") waits for that behavior to time it, rather
        // than pinning it with its own defaults.
        for (std::size_t i = 0; i < block_.behaviors.size() && !progress; ++i)
          if (active_[i] && !done[i] && !waitsForOthers(i) && timeBehavior(i)) done[i] = progress = true;
        for (std::size_t i = 0; i < block_.behaviors.size() && !progress; ++i)
          if (active_[i] && !done[i] && timeBehavior(i)) done[i] = progress = true;
        if (progress) continue;
        // Stalled: seed the first untimed behavior (document order) at 0, as a free group.
        for (std::size_t i = 0; i < block_.behaviors.size() && seed == block_.behaviors.size(); ++i)
          if (active_[i] && !done[i]) seed = i;
      }
      if (seed == block_.behaviors.size()) break;
      ++freeComponent;
      const int root = groups_.find(pegIds_[seed][0]).first;
      known_[root] = -groups_.find(pegIds_[seed][0]).second;
      component_[root] = freeComponent;
    }
    shiftFreeComponents();
  }

  // True if one of the behavior's own sync attributes names an absolute time or
  // it is synchronized to one (then its place is not the others' choice).
  bool anchoredDirectly(std::size_t i) {
    const int blockRoot = groups_.find(blockStart_).first;
    for (std::size_t k = 0; k < pegIds_[i].size(); ++k)
      if (groups_.find(pegIds_[i][k]).first == blockRoot) return true;
    return false;
  }

  bool waitsForOthers(std::size_t i) {
    for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k)
      if (dependent_[i][k] && std::isnan(pegTime(i, k))) return true;
    return false;
  }

  int anchorCount(std::size_t i) {
    int n = 0;
    for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k) n += !std::isnan(pegTime(i, k));
    return n;
  }

  double pegTime(std::size_t i, std::size_t k) {
    auto [root, off] = groups_.find(pegIds_[i][k]);
    return known_[root] + off;  // NaN stays NaN
  }

  // Times all of behavior i's pegs if any is known. Returns true if it did.
  bool timeBehavior(std::size_t i) {
    const auto& tpl = templates_[i].syncs;
    std::vector<std::pair<std::size_t, double>> anchors;  // (sync index, time)
    for (std::size_t k = 0; k < tpl.size(); ++k)
      if (double t = pegTime(i, k); !std::isnan(t)) anchors.emplace_back(k, t);
    if (anchors.empty()) return false;
    int comp = 0;
    for (auto [k, t] : anchors) comp = std::max(comp, componentOf(pegIds_[i][k]));
    std::vector<double>& out = times_[i];
    if (!templates_[i].stretchable || anchors.size() == 1) {
      const auto [k0, t0] = anchors.front();
      for (std::size_t k = 0; k < tpl.size(); ++k) out[k] = t0 + (tpl[k].time - tpl[k0].time);
    } else {
      // Piecewise linear between anchors; outside them, default spacing.
      for (std::size_t k = 0; k < tpl.size(); ++k) {
        auto next = std::find_if(anchors.begin(), anchors.end(), [&](const auto& a) { return a.first >= k; });
        if (next == anchors.end()) {
          const auto [ka, ta] = anchors.back();
          out[k] = ta + (tpl[k].time - tpl[ka].time);
        } else if (next == anchors.begin()) {
          const auto [kb, tb] = *next;
          out[k] = tb - (tpl[kb].time - tpl[k].time);
        } else {
          const auto [ka, ta] = *(next - 1);
          const auto [kb, tb] = *next;
          const double span = tpl[kb].time - tpl[ka].time;
          const double u = span > 0 ? (tpl[k].time - tpl[ka].time) / span
                                    : static_cast<double>(k - ka) / static_cast<double>(kb - ka);
          out[k] = ta + u * (tb - ta);
        }
      }
    }
    if (templates_[i].stretchable && comp == 0) shortenPreparation(i, anchors.front());
    // Record the times of this behavior's groups (a group already timed keeps its time;
    // a mismatch is found by checkBehaviors).
    for (std::size_t k = 0; k < tpl.size(); ++k) {
      auto [root, off] = groups_.find(pegIds_[i][k]);
      if (std::isnan(known_[root])) {
        known_[root] = out[k] - off;
        if (comp) component_[root] = comp;
      }
    }
    return true;
  }

  // stroke="0" relax="2", or a head's stroke="0.1": the first timed sync point is at or after
  // the block's start, but the default preparation before it would begin earlier. Only the
  // untimed sync points before it are moved: they are compressed into [0, first] keeping their
  // proportions (as AsapRealizer shortens a preparation), rather than the behavior removed.
  // A timed sync point before 0 still is a contradiction (checkBehaviors).
  void shortenPreparation(std::size_t i, std::pair<std::size_t, double> first) {
    const auto [kb, tb] = first;
    std::vector<double>& out = times_[i];
    if (kb == 0 || !(out[0] < -kEpsilon) || tb < -kEpsilon) return;
    const auto& tpl = templates_[i].syncs;
    const double span = tpl[kb].time - tpl[0].time;
    const double at = std::max(tb, 0.0);
    for (std::size_t k = 0; k < kb; ++k)
      out[k] = span > 0 ? at * (tpl[k].time - tpl[0].time) / span : at * static_cast<double>(k) / static_cast<double>(kb);
  }

  int componentOf(int peg) {
    return component_[groups_.find(peg).first];
  }

  // A free group of behaviors (nothing anchors it to the block start) starts at 0.
  void shiftFreeComponents() {
    std::map<int, double> earliest;
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) {
      if (!active_[i]) continue;
      for (std::size_t k = 0; k < times_[i].size(); ++k) {
        const int c = componentOf(pegIds_[i][k]);
        if (c == 0) continue;
        auto [it, inserted] = earliest.emplace(c, times_[i][k]);
        if (!inserted) it->second = std::min(it->second, times_[i][k]);
      }
    }
    shift(earliest, -1.0);
  }

  // Adds `sign * amount[component]` to every peg of the listed components.
  void shift(const std::map<int, double>& amount, double sign) {
    if (amount.empty()) return;
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) {
      if (!active_[i]) continue;
      for (std::size_t k = 0; k < times_[i].size(); ++k) {
        auto it = amount.find(componentOf(pegIds_[i][k]));
        if (it != amount.end()) times_[i][k] += sign * it->second;
      }
    }
    for (std::size_t root = 0; root < known_.size(); ++root) {
      if (component_[root] == 0 || std::isnan(known_[root])) continue;
      auto it = amount.find(component_[root]);
      if (it != amount.end()) known_[root] += sign * it->second;
    }
  }

  // Each behavior's times must match its groups, be in order, and not be negative.
  void checkBehaviors() {
    for (std::size_t i = 0; i < block_.behaviors.size(); ++i) {
      if (!active_[i]) continue;
      const Behavior& b = block_.behaviors[i];
      const auto& tpl = templates_[i].syncs;
      for (std::size_t k = 0; k < tpl.size(); ++k) {
        const double group = pegTime(i, k);
        if (!std::isnan(group) && std::fabs(group - times_[i][k]) > 1e-4) {
          removeBehavior(i, WarningType::ImpossibleToSchedule,
                         "sync point '" + tpl[k].name + "' is constrained to " + fmt(group) + " s but the behavior's timing puts it at " +
                             fmt(times_[i][k]) + " s" + (templates_[i].stretchable ? "" : " (a " + b.type + " cannot be stretched)"),
                         b.line, b.column);
          break;
        }
        if (k > 0 && times_[i][k] < times_[i][k - 1] - kEpsilon) {
          removeBehavior(i, WarningType::ImpossibleToSchedule,
                         "sync point '" + tpl[k].name + "' (" + fmt(times_[i][k]) + " s) would come before '" + tpl[k - 1].name +
                             "' (" + fmt(times_[i][k - 1]) + " s)",
                         b.line, b.column);
          break;
        }
        if (times_[i][k] < -kEpsilon) {
          // A rigid behavior placed by others' defaults: try again with it placed first.
          if (!templates_[i].stretchable && !placeFirst_.count(i) && componentOf(pegIds_[i][k]) == 0 &&
              !anchoredDirectly(i)) {
            placeFirst_.insert(i);
            retry_ = true;
            break;
          }
          removeBehavior(i, WarningType::ImpossibleToSchedule,
                         "sync point '" + tpl[k].name + "' would be at " + fmt(times_[i][k]) + " s, before the block starts",
                         b.line, b.column);
          break;
        }
      }
    }
  }

  // before/after: each sync must come before/after the anchor. A free group is
  // moved later to satisfy it; otherwise a warning.
  void applyOrdering() {
    for (const Constraint& c : block_.constraints) {
      if (c.kind == Constraint::Kind::Synchronize) continue;
      auto anchor = resolveConstraintSync(c, c.anchor);
      if (!anchor) continue;
      for (const ConstraintSync& s : c.syncs) {
        auto target = resolveConstraintSync(c, s);
        if (!target) continue;
        const double ta = timeOfPeg(anchor->first) + anchor->second;
        const double ts = timeOfPeg(target->first) + target->second;
        const bool after = c.kind == Constraint::Kind::After;
        const double deficit = after ? ta - ts : ts - ta;  // > 0: violated
        if (deficit <= kEpsilon) continue;
        const int movable = after ? componentOf(target->first) : componentOf(anchor->first);
        if (movable != 0 && movable != componentOf(after ? anchor->first : target->first)) {
          shift({{movable, deficit}}, 1.0);
          continue;
        }
        passWarnings_.push_back({WarningType::ImpossibleToSchedule, block_.id, c.id, s.line, s.column,
                                 "'" + s.ref + "' should come " + (after ? "after" : "before") + " '" + c.anchor.ref +
                                     "' but is " + fmt(std::fabs(deficit)) + " s " + (after ? "earlier" : "later") +
                                     "; the times of other constraints were kept",
                                 c.required});
        if (c.required) failed_ = true;
      }
    }
  }

  double timeOfPeg(int peg) {
    for (std::size_t i = 0; i < pegIds_.size(); ++i)
      for (std::size_t k = 0; k < pegIds_[i].size(); ++k)
        if (pegIds_[i][k] == peg) return times_[i][k];
    return 0.0;  // the block start
  }

  static std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
  }

  const Block& block_;
  const SchedulerOptions& options_;
  std::vector<SyncTemplate> templates_;
  std::vector<std::vector<std::string>> keys_;  // lower-case sync names, per behavior
  std::vector<bool> active_;
  std::vector<std::vector<int>> pegIds_;
  std::vector<std::vector<bool>> dependent_;  // sync point tied to another behavior by this behavior's own attribute
  std::vector<std::vector<double>> times_;
  PegGroups groups_;
  int blockStart_ = 0;
  std::size_t pegCount_ = 0;
  std::vector<double> known_;   // group root -> time (NaN: not yet)
  std::vector<int> component_;  // group root -> free component (0: anchored)
  std::map<std::size_t, Warning> toRemove_;
  std::vector<Warning> warnings_, passWarnings_;
  bool failed_ = false;
  bool retry_ = false;
  std::set<std::size_t> placeFirst_;
};

}  // namespace

Schedule scheduleBlock(const Block& block, const SchedulerOptions& options) { return Scheduler(block, options).run(); }

Schedule scheduleText(std::string_view bmlText, const SchedulerOptions& options) {
  return scheduleParsed(parseBlock(bmlText), options);
}

Schedule scheduleParsed(const ParseResult& parsed, const SchedulerOptions& options) {
  Schedule s;
  if (parsed.block) s = scheduleBlock(*parsed.block, options);
  s.warnings.insert(s.warnings.begin(), parsed.warnings.begin(), parsed.warnings.end());
  for (const Warning& w : parsed.warnings) s.failed |= w.fatal;
  if (!parsed.block) s.failed = true;
  return s;
}

}  // namespace marionette::bml
