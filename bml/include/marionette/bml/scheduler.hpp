// Scheduling a parsed BML block: every sync point of every behavior gets a time
// in seconds from the block's start.
//
// Model (time pegs, in the style of AsapRealizer): each sync point is a peg.
// Equalities (sync attributes, <synchronize>, numbers) join pegs into groups
// with fixed offsets (union-find); a group holding a number is anchored to the
// block start. Each behavior has default relative times for its sync points
// (`defaultSyncs`); a behavior with one timed peg takes its defaults from it,
// one with two or more is stretched between them (when its type allows, speech
// does not). Groups that nothing anchors are placed so that their earliest
// sync point is at 0. Then before/after constraints are checked (a free group
// is moved later to satisfy them). A behavior whose timing cannot be met
// (end before start, a contradiction, a negative time, a missing target) is
// removed with a warning; if it was required, the block fails.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bml/document.hpp"

namespace marionette::bml {

struct SchedulerOptions {
  // Speech duration until a speech backend provides it: seconds per character
  // of text (about 15 characters per second, a typical TTS rate), at least the minimum.
  double speechSecondsPerCharacter = 0.065;
  double minimumSpeechSeconds = 0.3;
};

struct SyncTime {
  std::string name;  // as the behavior defines it ("start", "stroke", a speech word mark id)
  double time = 0.0; // seconds from the block's start
};

struct ScheduledBehavior {
  std::string id, type;
  std::vector<SyncTime> syncs;  // in the behavior's order (start ... end)
  bool required = false;
  int line = 0, column = 0;
  // Sync point time by name (case-insensitive), if the behavior has it.
  [[nodiscard]] std::optional<double> time(std::string_view sync) const;
};

struct Schedule {
  std::string blockId;
  std::vector<ScheduledBehavior> behaviors;  // removed behaviors are not here
  std::vector<Warning> warnings;             // parse warnings first, then scheduling ones
  bool failed = false;                       // the block failed as a whole

  [[nodiscard]] const ScheduledBehavior* find(std::string_view id) const noexcept;
  [[nodiscard]] std::optional<double> time(std::string_view behavior, std::string_view sync) const;
};

// Default sync points of a behavior, relative to its start, and whether it may stretch.
struct SyncTemplate {
  std::vector<SyncTime> syncs;
  bool stretchable = true;
};
[[nodiscard]] SyncTemplate defaultSyncs(const Behavior& behavior, const SchedulerOptions& options = {});

[[nodiscard]] Schedule scheduleBlock(const Block& block, const SchedulerOptions& options = {});
// Parse and schedule: parse warnings are carried into the schedule.
[[nodiscard]] Schedule scheduleText(std::string_view bmlText, const SchedulerOptions& options = {});
// Schedule an already parsed block; the parse warnings come first in the result.
[[nodiscard]] Schedule scheduleParsed(const ParseResult& parsed, const SchedulerOptions& options = {});

}  // namespace marionette::bml
