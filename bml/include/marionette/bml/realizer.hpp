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
#include <optional>
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

 private:
  struct Event {
    double sceneTime;
    std::string behaviorId, syncPoint;
    double blockTime;
  };
  struct Active {
    std::string character, blockId;
    double start = 0.0, end = 0.0;  // scene time
    std::vector<Event> events;      // sync points, sorted by time
    std::size_t next = 0;
    bool started = false;
  };
  void emit(const Feedback& f);
  static Feedback syncFeedback(Feedback::Kind kind, const Active& block, const Event& event);
  void finish(Active& block, double sceneTime);

  Scene& scene_;
  std::vector<FeedbackListener> listeners_;
  std::vector<Active> blocks_;
};

// Escapes &, <, >, " and ' for XML attribute values.
[[nodiscard]] std::string xmlEscape(std::string_view text);

}  // namespace marionette::bml
