// The solver's timing of the pegs: known group times propagated through the behaviors' defaults,
// free groups moved to 0, each behavior checked, before/after constraints applied.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "block_scheduler.hpp"

namespace marionette::bml::detail {

namespace {

constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

}  // namespace

// Known group times; behaviors take their pegs' times from their defaults.
void Scheduler::propagate() {
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
bool Scheduler::anchoredDirectly(std::size_t i) {
  const int blockRoot = groups_.find(blockStart_).first;
  for (std::size_t k = 0; k < pegIds_[i].size(); ++k)
    if (groups_.find(pegIds_[i][k]).first == blockRoot) return true;
  return false;
}

bool Scheduler::waitsForOthers(std::size_t i) {
  for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k)
    if (dependent_[i][k] && std::isnan(pegTime(i, k))) return true;
  return false;
}

int Scheduler::anchorCount(std::size_t i) {
  int n = 0;
  for (std::size_t k = 0; k < templates_[i].syncs.size(); ++k) n += !std::isnan(pegTime(i, k));
  return n;
}

double Scheduler::pegTime(std::size_t i, std::size_t k) {
  auto [root, off] = groups_.find(pegIds_[i][k]);
  return known_[root] + off;  // NaN stays NaN
}

// Times all of behavior i's pegs if any is known. Returns true if it did.
bool Scheduler::timeBehavior(std::size_t i) {
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
void Scheduler::shortenPreparation(std::size_t i, std::pair<std::size_t, double> first) {
  const auto [kb, tb] = first;
  std::vector<double>& out = times_[i];
  if (kb == 0 || !(out[0] < -kEpsilon) || tb < -kEpsilon) return;
  const auto& tpl = templates_[i].syncs;
  const double span = tpl[kb].time - tpl[0].time;
  const double at = std::max(tb, 0.0);
  for (std::size_t k = 0; k < kb; ++k)
    out[k] = span > 0 ? at * (tpl[k].time - tpl[0].time) / span : at * static_cast<double>(k) / static_cast<double>(kb);
}

int Scheduler::componentOf(int peg) {
  return component_[groups_.find(peg).first];
}

// A free group of behaviors (nothing anchors it to the block start) starts at 0.
void Scheduler::shiftFreeComponents() {
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
void Scheduler::shift(const std::map<int, double>& amount, double sign) {
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
void Scheduler::checkBehaviors() {
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
void Scheduler::applyOrdering() {
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

double Scheduler::timeOfPeg(int peg) {
  for (std::size_t i = 0; i < pegIds_.size(); ++i)
    for (std::size_t k = 0; k < pegIds_[i].size(); ++k)
      if (pegIds_[i][k] == peg) return times_[i][k];
  return 0.0;  // the block start
}

std::string Scheduler::fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace marionette::bml::detail
