// Scheduling a block (the public entry points, a pass of the solver: the block's equalities
// joined into peg groups, removals committed) and the schedule's lookups.
#include "marionette/bml/scheduler.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "block_scheduler.hpp"
#include "default_syncs.hpp"
#include "marionette/bml/sync_ref.hpp"

namespace marionette::bml {

std::string syncKey(std::string_view name) {
  std::string out(name);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  out.erase(std::remove(out.begin(), out.end(), '-'), out.end());  // "stroke-end" = "strokeEnd"
  return out;
}

namespace {

// syncKey(name) == key, without building the key of `name` (a speech has a sync per word mark:
// a search over them must not allocate per mark).
bool hasSyncKey(std::string_view name, std::string_view key) noexcept {
  std::size_t k = 0;
  for (const char c : name) {
    if (c == '-') continue;
    const char lower = c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;  // ASCII, as syncKey's names are
    if (k == key.size() || lower != key[k]) return false;
    ++k;
  }
  return k == key.size();
}

}  // namespace

std::optional<double> ScheduledBehavior::time(std::string_view sync) const {
  const std::string key = syncKey(sync);
  for (const SyncTime& s : syncs)
    if (hasSyncKey(s.name, key)) return s.time;
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

namespace detail {

Schedule Scheduler::run() {
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

// Returns true when nothing had to be removed.
bool Scheduler::solve() {
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

bool Scheduler::commitRemovals() {
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

void Scheduler::removeBehavior(std::size_t index, WarningType type, std::string message, int line, int column) {
  if (toRemove_.count(index)) return;
  toRemove_[index] = Warning{type, block_.id, block_.behaviors[index].id, line, column, std::move(message), false};
}

int Scheduler::behaviorIndex(std::string_view id) const {
  for (std::size_t i = 0; i < block_.behaviors.size(); ++i)
    if (active_[i] && block_.behaviors[i].id == id) return static_cast<int>(i);
  return -1;
}

int Scheduler::syncIndex(std::size_t behavior, std::string_view name) const {
  const std::string key = syncKey(name);
  const auto& keys = keys_[behavior];
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (keys[k] == key) return static_cast<int>(k);
  return -1;
}

// Resolves a reference to (peg, offset). On failure fills `problem`.
std::optional<std::pair<int, double>> Scheduler::resolve(const SyncRef& ref, std::string& problem, WarningType& type) {
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

void Scheduler::applyAttributeConstraints() {
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

void Scheduler::applySynchronizeConstraints() {
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

std::optional<std::pair<int, double>> Scheduler::resolveConstraintSync(const Constraint& c, const ConstraintSync& s) {
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

}  // namespace detail

Schedule scheduleBlock(const Block& block, const SchedulerOptions& options) {
  return detail::Scheduler(block, options).run();
}

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
