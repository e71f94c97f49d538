// The constraint solver that schedules one block (scheduleBlock): its passes in scheduler.cpp,
// the timing of the pegs in scheduler_timing.cpp. Private to the scheduler's files.
#pragma once
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/bml/scheduler.hpp"
#include "marionette/bml/sync_ref.hpp"
#include "peg_groups.hpp"

namespace marionette::bml::detail {

class Scheduler {
 public:
  Scheduler(const Block& block, const SchedulerOptions& options) : block_(block), options_(options) {}

  Schedule run();

 private:
  // ------------------------------------------------------------------ one pass
  bool solve();
  bool commitRemovals();
  void removeBehavior(std::size_t index, WarningType type, std::string message, int line, int column);
  int behaviorIndex(std::string_view id) const;
  int syncIndex(std::size_t behavior, std::string_view name) const;
  std::optional<std::pair<int, double>> resolve(const SyncRef& ref, std::string& problem, WarningType& type);
  void applyAttributeConstraints();
  void applySynchronizeConstraints();
  std::optional<std::pair<int, double>> resolveConstraintSync(const Constraint& c, const ConstraintSync& s);

  // ------------------------------------------------------------------ timing
  void propagate();
  bool anchoredDirectly(std::size_t i);
  bool waitsForOthers(std::size_t i);
  int anchorCount(std::size_t i);
  double pegTime(std::size_t i, std::size_t k);
  bool timeBehavior(std::size_t i);
  void shortenPreparation(std::size_t i, std::pair<std::size_t, double> first);
  int componentOf(int peg);
  void shiftFreeComponents();
  void shift(const std::map<int, double>& amount, double sign);
  void checkBehaviors();
  void applyOrdering();
  double timeOfPeg(int peg);
  static std::string fmt(double v);

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

}  // namespace marionette::bml::detail
