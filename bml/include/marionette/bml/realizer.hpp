// Realizer: puts scheduled BML blocks on the scene clock and reports their
// progress. One per Scene (no global state).
//
//   bml::Realizer realizer(scene);
//   realizer.perform(text, "robot");   // parse, schedule, compose, predict
//   scene.update(dt); realizer.update();  // after each scene update: progress feedback
//
// Speech is said off the frame path (setSpeechSynthesis): a block with a <speech>
// that is not said yet waits for it, on the speech service's thread, and starts
// when it is ready.
//
// Composition: MERGE runs the block in parallel with those in progress; APPEND
// starts it when every earlier block of the character has ended; REPLACE ends
// the character's earlier blocks now, blending their behaviors out over
// replaceBlendSeconds() (back to the posture, or the rest pose). interrupt()
// ends one block by id the same way. A block may refer to sync points of the
// blocks queued before it, of any character (`otherBlock:behavior:sync`).
// Feedback (BML 1.0): predictionFeedback right after scheduling, blockProgress
// start/end, syncPointProgress for every sync point as the clock passes it, and
// warningFeedback; each both as a typed Feedback to FeedbackListeners and through
// the scene's listeners (onBehaviorProgress, onLog). Feedback::xml() gives the
// BML 1.0 XML of a message.
// Each scheduled behavior becomes a BehaviorRequest on the character's timeline
// (Character::addBehavior, the same C++ API an engine can call without BML);
// the character's controllers move the body. A behavior no controller realizes
// yet gets a CANNOT_CREATE_BEHAVIOR warning; its timing and feedback still run.
// Default durations come from the character: a gesture whose lexeme names a
// clip of the rig lasts as long as the clip (naturalDuration).
#pragma once
#include <cmath>
#include <functional>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bml/audio_files.hpp"
#include "marionette/bml/behavior_mapping.hpp"
#include "marionette/bml/scheduler.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette::bml {

struct Feedback {
  // Event: an <event message> (SmartBody's <sbm:event>) reached its stroke; `message` is
  // what the script sends (also to the scene's listeners: SceneListener::onMessage).
  enum class Kind { Prediction, BlockProgress, SyncPointProgress, Warning, Event } kind = Kind::BlockProgress;
  std::string character;
  std::string blockId;
  std::string behaviorId;  // SyncPointProgress, Prediction of a sync point, Warning
  std::string syncPoint;   // "start"/"end" for BlockProgress; the sync point's name otherwise
  double blockTime = 0.0;  // seconds from the block's start
  double sceneTime = 0.0;  // on the scene clock
  Warning warning;         // Kind::Warning
  std::string message;     // Kind::Event

  // The BML 1.0 feedback element, ids escaped for XML.
  [[nodiscard]] std::string xml() const;
};

using FeedbackListener = std::function<void(const Feedback&)>;

class Realizer {
 public:
  explicit Realizer(Scene& scene) : scene_(scene) {}

  void addFeedbackListener(FeedbackListener listener) { listeners_.push_back(std::move(listener)); }
  // Warnings also go to the scene's listeners (onLog) unless turned off, e.g. by a
  // caller that reports them itself from a FeedbackListener.
  void setForwardWarningsToScene(bool forward) noexcept { forwardWarnings_ = forward; }
  // Whether a behavior that no controller of the character realizes gets a
  // CANNOT_CREATE_BEHAVIOR warning (default on). Off only to validate BML against
  // an idealised character that has every controller (bml-check's default).
  void setReportUnrealized(bool report) noexcept { reportUnrealized_ = report; }
  // Which realizer's users wrote the blocks (document.hpp): Auto (the default) reads a block
  // in SmartBody mode when it uses SmartBody's forms; SmartBody always (blocks and behaviors
  // without ids get generated ones: the block's "sbm_block_N", N counting perform() calls);
  // Bml strictly.
  // A character's own dialect comes first: the one given as perform()'s `character`, else
  // the block's characterId (read leniently to find it), else the scene's first character.
  void setDialect(Dialect dialect) noexcept { dialect_ = dialect; }
  void setDialect(std::string_view character, Dialect dialect);
  [[nodiscard]] Dialect dialect() const noexcept { return dialect_; }
  [[nodiscard]] Dialect dialectFor(std::string_view character) const;
  // Blend-out of behaviors ended by REPLACE or interrupt() (default 0.3 s).
  void setReplaceBlendSeconds(double seconds) noexcept {
    replaceBlend_ = std::isfinite(seconds) && seconds >= 0.0 ? seconds : replaceBlend_;
  }
  [[nodiscard]] double replaceBlendSeconds() const noexcept { return replaceBlend_; }
  // The character layer that SmartBody's <blend name="STATE" x y> plays on (default 0, the
  // base layer, as SmartBody's states are the base motion): at the behavior's start the
  // profile's blend space STATE replaces what that layer played, at (x, y); a later <blend>
  // of the same space moves its parameter point only (its cycle goes on). The space keeps
  // playing after its block ends, as a SmartBody state does, until another clip or space
  // takes the layer (Character::stop ends it). docs/blend-spaces.md.
  void setBlendLayer(int layer) noexcept {
    blendLayer_ = layer >= 0 && layer < Character::kMaxLayers ? layer : blendLayer_;
  }
  [[nodiscard]] int blendLayer() const noexcept { return blendLayer_; }
  // Where behaviors' files are read (<bmlt:audiofile fileName>, audio_files.hpp): relative
  // names in `directory` (a scene's asset folder; "" = the working directory; a block's
  // SchedulerOptions::fileDirectory comes first), through `reader` (empty: the disk). Each
  // file is read when its block is realized, never per frame.
  void setFiles(FileReader reader, std::string directory = {}) {
    files_ = {std::move(reader), std::move(directory)};
  }
  [[nodiscard]] const AudioFileAccess& files() const noexcept { return files_; }

  // Parses and schedules `bmlText` for `character` (the block's characterId
  // when empty) and queues it. Returns the schedule (with its warnings, which are
  // also sent as feedback). A failed block is not queued. `options` are used as
  // given, except that the realizer supplies externalSync (references to queued
  // blocks) and defaultDuration (the character's clips) when they are unset. `at` is the scene time
  // the block is sent at (default: now); a caller stepping in frames passes the
  // exact time so a block does not start a frame early.
  Schedule perform(std::string_view bmlText, std::string_view character = {}, const SchedulerOptions& options = {},
                   std::optional<double> at = std::nullopt);

  // Emits progress for what the scene clock has passed since the last call, after
  // realizing the held blocks whose speech is ready (SpeechSynthesis::Background).
  void update();

  // How a block's <speech> is said. Background (the default): perform() starts its
  // lines on the scene speech service's thread and, unless they are ready already
  // (cached), holds the block; update() realizes it, at the scene time of that call,
  // once they are. No frame waits for a synthesizer; the block starts a frame or two
  // late instead. Blocks performed while one is held are held behind it, so that
  // composition (APPEND, REPLACE) and references to other blocks keep the order of
  // perform(). A held block starts at the update after its lines are said, or at the
  // `at` it was sent for when that is later; its SchedulerOptions (and what their
  // functions capture) must live until then. A held block that fails to schedule
  // reports it as warning feedback when realized; a block that does not parse, or names
  // no character, fails at once. interrupt() drops a held block without feedback.
  // Inline: perform() says the lines itself (deterministic: offline tools and tests; a
  // new 1000-character line blocks that call for about 50 ms); blocks still held from
  // Background are waited for and realized first, in order.
  enum class SpeechSynthesis { Background, Inline };
  void setSpeechSynthesis(SpeechSynthesis mode) noexcept { speechSynthesis_ = mode; }
  [[nodiscard]] SpeechSynthesis speechSynthesis() const noexcept { return speechSynthesis_; }
  // Blocks performed and held until their speech is said.
  [[nodiscard]] std::size_t heldBlocks() const noexcept { return held_.size(); }
  // Waits until the held blocks' speech is said and realizes them now (offline, tests).
  void waitForSpeech();

  // Ends a block now (blockProgress end is sent; a held or preplanned block is dropped,
  // unsent). False if no such block is queued, held or preplanned.
  bool interrupt(std::string_view blockId);
  // Starts a preplanned block (BMLA's bmla:preplan="true": scheduled and checked when
  // performed, started only when activated) now. False if no such block waits.
  bool activate(std::string_view blockId);
  [[nodiscard]] std::size_t preplannedBlocks() const noexcept { return preplanned_.size(); }

  [[nodiscard]] std::size_t activeBlocks() const noexcept { return blocks_.size(); }
  // Scene time at which a queued block starts (APPEND may start it later than perform()).
  [[nodiscard]] std::optional<double> blockStart(std::string_view blockId) const;

  // Which behavior drives a body channel of a character at a scene time: of the
  // behaviors on that channel whose [start, end) holds the time, the one
  // performed last (within a block, the later in the text). Deterministic; it is
  // the character timeline's owner(). Returns {blockId, behaviorId}.
  [[nodiscard]] std::optional<std::pair<std::string, std::string>> channelOwner(std::string_view character,
                                                                               std::string_view channel,
                                                                               double sceneTime) const;

 private:
  struct Event {
    double sceneTime;
    std::string behaviorId, syncPoint;
    double blockTime;
    bool onArrival = false;  // a locomotion's end: fires when the character arrives
    // What passing it does besides feedback: an <event>'s stroke sends its message; BMLA's
    // <bmla:interrupt>/<bmla:activate> start interrupts or activates the `argument` block.
    // SmartBody's <blend>'s start plays the profile's blend space `argument` at (x, y).
    enum class Action : std::uint8_t { None, Message, Interrupt, Activate, Blend } action = Action::None;
    std::string argument;
    float x = 0.0f, y = 0.0f;
  };
  struct Active {
    std::string character, blockId;
    double start = 0.0, end = 0.0;  // scene time
    double relaxed = 0.0;           // when every behavior has passed its relax (BMLA chunkAfter)
    std::vector<Event> events;      // sync points, sorted by time
    std::size_t next = 0;
    bool started = false;
    std::vector<std::string> interruptOnStart, activateOnStart;  // BMLA, when it starts later
  };
  struct Planned {  // BMLA preplan: checked when performed, realized when activated
    std::string text, character, blockId;
    ParseOptions parse;
    SchedulerOptions options;
  };
  using Action = std::pair<Event::Action, std::string>;
  struct Held {  // performed, waiting for its speech
    std::string text, character, blockId;
    ParseOptions parse;
    SchedulerOptions options;
    std::optional<double> at;
    std::vector<std::shared_ptr<const speech::SpeechService::Preparation>> lines;
    [[nodiscard]] bool ready() const noexcept;
  };
  [[nodiscard]] std::optional<Schedule> holdForSpeech(std::string_view bmlText, const ParseOptions& parse,
                                                      std::string_view character, const SchedulerOptions& options,
                                                      std::optional<double> at);
  void realizeHeld();
  // `activation`: a preplanned block starting (its planning warnings were said already).
  Schedule realize(std::string_view bmlText, const ParseOptions& parse, std::string_view character,
                   const SchedulerOptions& options, std::optional<double> at, bool activation = false);
  // BMLA: the block's start after the blocks it appends or chunks after, naming those not queued.
  double bmlaStart(const Block::Bmla& bmla, double start, std::vector<std::string>& unknown) const;
  void run(const std::vector<Action>& actions);
  [[nodiscard]] bool finishedRecently(std::string_view blockId) const;
  [[nodiscard]] std::pair<std::string, Character*> performer(const ParseResult& parsed, std::string_view character) const;
  [[nodiscard]] Dialect dialectOfBlock(std::string_view bmlText, std::string_view character) const;
  void emit(const Feedback& f);
  bool arrived(Active& block, Event& event, double now);
  static Feedback syncFeedback(Feedback::Kind kind, const Active& block, const Event& event);
  void warn(const std::string& character, const std::string& blockId, double sceneTime, Warning warning);
  bool submit(Character& character, const Active& block, const Block& parsed, Schedule& schedule,
              const std::vector<LoadedAudio>& audio);
  void reportConflicts(const Character& character, const Active& block, const BehaviorTimeline::Entry& added,
                       const Behavior& behavior, Schedule& schedule);
  [[nodiscard]] SchedulerOptions::ExternalSync resolveExternal(const SyncRef& ref, double blockStart) const;
  void finish(Active& block, double sceneTime);

  Scene& scene_;
  std::vector<FeedbackListener> listeners_;
  std::vector<Active> blocks_;
  std::deque<Held> held_;
  std::vector<Planned> preplanned_;
  std::deque<std::string> finished_;  // the last kFinishedKept block ids that ended
  static constexpr std::size_t kFinishedKept = 256;
  SpeechSynthesis speechSynthesis_ = SpeechSynthesis::Background;
  bool forwardWarnings_ = true;
  bool reportUnrealized_ = true;
  Dialect dialect_ = Dialect::Auto;
  std::vector<std::pair<std::string, Dialect>> characterDialects_;  // setDialect(character, ...)
  std::size_t performed_ = 0;  // perform() calls: generated block ids
  double replaceBlend_ = 0.3;
  int blendLayer_ = 0;  // SmartBody's <blend> (setBlendLayer)
  AudioFileAccess files_;  // setFiles
  void startBlend(const std::string& character, const Event& e);
};

// Escapes &, <, >, " and ' for XML attribute values.
[[nodiscard]] std::string xmlEscape(std::string_view text);

}  // namespace marionette::bml
