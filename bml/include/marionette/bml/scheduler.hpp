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
//
// Repetitions: a head, gesture or pointing with repetition="R" repeats its
// stroke phase R times; repetition n >= 2 names its syncs "strokeStart:n",
// "stroke:n", "strokeEnd:n", which references such as "nod1:stroke:2" reach.
// A reference to another block ("bml0:speech1:end") is a fixed time that
// SchedulerOptions::externalSync supplies, like a number.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/bml/document.hpp"
#include "marionette/bml/sync_ref.hpp"

namespace marionette::bml {

// A speech's length and its word marks' times (seconds from its start), as a speech backend says them.
struct SpeechTiming {
  double duration = 0.0;
  std::vector<std::pair<std::string, double>> marks;  // id, time
};

struct SchedulerOptions {
  // Speech duration when speechTiming gives none: seconds per character of text
  // (about 15 characters per second, a typical TTS rate), at least the minimum.
  double speechSecondsPerCharacter = 0.065;
  double minimumSpeechSeconds = 0.3;

  // Resolves a reference to another block's sync point (ref.block is set and is not
  // this block's id) to its time in seconds relative to THIS block's start (the
  // realizer knows both blocks on the scene clock). ref.offset is NOT included; the
  // scheduler adds it. Return an error text when it cannot (no such block, behavior, sync).
  // May be called more than once for the same reference (once per scheduling pass).
  struct ExternalSync {
    std::optional<double> time;
    std::string problem;
  };
  std::function<ExternalSync(const SyncRef&)> externalSync;

  // The natural duration of a behavior on the character that will perform it
  // (e.g. the length of the clip a gesture's lexeme names), or nullopt for the
  // built-in default. For head/gesture/pointing it is one repetition's length.
  // Used for every type except speech and wait; a value that is not finite and > 0 is ignored.
  std::function<std::optional<double>(const Behavior&)> defaultDuration;

  // A speech's real timing (the realizer asks the character's speech service).
  // Marks it does not name keep the per-character estimate, clamped into the speech.
  std::function<std::optional<SpeechTiming>(const Behavior&)> speechTiming;

  // Where the block's relative file names are found (<bmlt:audiofile fileName>): the BML
  // file's folder. "" = the realizer's (Realizer::setFiles). The scheduler itself reads no file.
  std::string fileDirectory;
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
  Dialect dialect = Dialect::Bml;            // how it was read: Bml, or SmartBody (given or detected)
  // The realizer holds the block until its speech is said (Realizer::SpeechSynthesis):
  // `behaviors` is empty; predictions, warnings and progress come as feedback.
  bool heldForSpeech = false;
  // BMLA preplan: planned and checked, waiting for Realizer::activate (`behaviors` as planned).
  bool preplanned = false;

  [[nodiscard]] const ScheduledBehavior* find(std::string_view id) const noexcept;
  [[nodiscard]] std::optional<double> time(std::string_view behavior, std::string_view sync) const;
};

// A repetition="R" above this is scheduled as this many repetitions: each one adds
// three sync points, so a huge R must not be able to exhaust memory.
inline constexpr int kMaxBehaviorRepetitions = 100;
// Sync points of all behaviors of one block together (repetitions included); a
// block over it fails with IMPOSSIBLE_TO_SCHEDULE. Bounds scheduling time.
inline constexpr std::size_t kMaxSyncPointsPerBlock = 20000;

// Default sync points of a behavior, relative to its start, and whether it may stretch.
struct SyncTemplate {
  std::vector<SyncTime> syncs;  // in time order
  bool stretchable = true;
  int repetitions = 1;          // of the stroke phase (head, gesture, pointing); 1 otherwise
};
[[nodiscard]] SyncTemplate defaultSyncs(const Behavior& behavior, const SchedulerOptions& options = {});

// A sync point name as schedules compare them: lower case, '-' removed
// ("stroke-end" and "strokeEnd" are one sync point).
[[nodiscard]] std::string syncKey(std::string_view name);

[[nodiscard]] Schedule scheduleBlock(const Block& block, const SchedulerOptions& options = {});
// Parse and schedule: parse warnings are carried into the schedule.
[[nodiscard]] Schedule scheduleText(std::string_view bmlText, const SchedulerOptions& options = {});
// Schedule an already parsed block; the parse warnings come first in the result.
[[nodiscard]] Schedule scheduleParsed(const ParseResult& parsed, const SchedulerOptions& options = {});

}  // namespace marionette::bml
