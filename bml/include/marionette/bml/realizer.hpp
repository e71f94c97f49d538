// Realizer: puts scheduled BML blocks on the scene clock and reports their
// progress. One per Scene (no global state).
//
//   bml::Realizer realizer(scene);
//   realizer.perform(text, "robot");   // parse, schedule, compose, predict
//   scene.update(dt); realizer.update();  // after each scene update: progress feedback
//
// Composition: MERGE runs the block in parallel with those in progress; APPEND
// starts it when every earlier block of the character has ended; REPLACE ends
// the character's earlier blocks now. interrupt() ends one block by id.
// Feedback (BML 1.0): predictionFeedback right after scheduling, blockProgress
// start/end, syncPointProgress for every sync point as the clock passes it, and
// warningFeedback; each both as a typed Feedback to FeedbackListeners and through
// the scene's listeners (onBehaviorProgress, onLog). Feedback::xml() gives the
// BML 1.0 XML of a message.
// Moving the body is the controllers' job (issue 4); this layer hands each
// scheduled behavior to them through Scene/Character once they exist.
#pragma once
#include <functional>
#include <cstdint>
#include <optional>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bml/scheduler.hpp"
#include "marionette/scene/scene.hpp"

namespace marionette::bml {

struct Feedback {
  enum class Kind { Prediction, BlockProgress, SyncPointProgress, Warning } kind = Kind::BlockProgress;
  std::string character;
  std::string blockId;
  std::string behaviorId;  // SyncPointProgress, Prediction of a sync point, Warning
  std::string syncPoint;   // "start"/"end" for BlockProgress; the sync point's name otherwise
  double blockTime = 0.0;  // seconds from the block's start
  double sceneTime = 0.0;  // on the scene clock
  Warning warning;         // Kind::Warning

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

  // Parses and schedules `bmlText` for `character` (the block's characterId
  // when empty) and queues it. Returns the schedule (with its warnings, which are
  // also sent as feedback). A failed block is not queued. `at` is the scene time
  // the block is sent at (default: now); a caller stepping in frames passes the
  // exact time so a block does not start a frame early.
  Schedule perform(std::string_view bmlText, std::string_view character = {}, const SchedulerOptions& options = {},
                   std::optional<double> at = std::nullopt);

  // Emits progress for what the scene clock has passed since the last call.
  void update();

  // Ends a block now (blockProgress end is sent). False if no such block is queued.
  bool interrupt(std::string_view blockId);

  [[nodiscard]] std::size_t activeBlocks() const noexcept { return blocks_.size(); }
  // Scene time at which a queued block starts (APPEND may start it later than perform()).
  [[nodiscard]] std::optional<double> blockStart(std::string_view blockId) const;

  // Which behavior drives a body channel of a character at a scene time: of the
  // queued behaviors on that channel whose [start, end] holds the time, the one
  // performed last (within a block, the later in the text). Deterministic; the
  // controllers follow it. Returns {blockId, behaviorId}.
  [[nodiscard]] std::optional<std::pair<std::string, std::string>> channelOwner(std::string_view character,
                                                                               std::string_view channel,
                                                                               double sceneTime) const;

 private:
  struct Event {
    double sceneTime;
    std::string behaviorId, syncPoint;
    double blockTime;
  };
  struct Claim {  // a behavior's hold on a body channel
    std::string channel, behaviorId;
    double start, end;     // scene time
    std::uint64_t order;   // perform order, then text order: the larger wins
  };
  struct Active {
    std::string character, blockId;
    std::vector<Claim> claims;
    double start = 0.0, end = 0.0;  // scene time
    std::vector<Event> events;      // sync points, sorted by time
    std::size_t next = 0;
    bool started = false;
  };
  void emit(const Feedback& f);
  static Feedback syncFeedback(Feedback::Kind kind, const Active& block, const Event& event);
  void claimChannels(Active& block, const Block& parsed, const Schedule& schedule, const std::string& character);
  void finish(Active& block, double sceneTime);

  Scene& scene_;
  std::vector<FeedbackListener> listeners_;
  std::vector<Active> blocks_;
  std::uint64_t order_ = 0;
  bool forwardWarnings_ = true;
};

// The body channel a behavior drives, for conflicts between behaviors that run
// at once: "head", "gaze", "leftHand", "rightHand", "hands" (both), "voice",
// "posture", "locomotion"; empty for behaviors that combine freely (face
// lexemes add up, wait drives nothing).
[[nodiscard]] std::string bodyChannel(const Behavior& behavior);

// Escapes &, <, >, " and ' for XML attribute values.
[[nodiscard]] std::string xmlEscape(std::string_view text);

}  // namespace marionette::bml
