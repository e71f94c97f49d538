// BML 1.0 feedback: warning types and the warning record every problem yields.
#pragma once
#include <string>
#include <string_view>

namespace marionette::bml {

// The BML 1.0 warningFeedback types.
enum class WarningType {
  ParsingFailure,               // PARSING_FAILURE
  NoSuchTarget,                 // NO_SUCH_TARGET
  ImpossibleToSchedule,         // IMPOSSIBLE_TO_SCHEDULE
  BehaviorTypeNotSupported,     // BEHAVIOR_TYPE_NOT_SUPPORTED
  CustomBehaviorNotSupported,   // CUSTOM_BEHAVIOUR_NOT_SUPPORTED
  CustomAttributeNotSupported,  // CUSTOM_ATTRIBUTE_NOT_SUPPORTED
  CannotCreateBehavior,         // CANNOT_CREATE_BEHAVIOR
};

[[nodiscard]] std::string_view toString(WarningType type) noexcept;

struct Warning {
  WarningType type = WarningType::ParsingFailure;
  std::string blockId;     // may be empty when the block id itself is missing
  std::string behaviorId;  // empty for block-level problems
  int line = 0, column = 0;
  std::string message;
  bool fatal = false;  // the block failed as a whole (malformed XML, no id, a required part failed)
};

}  // namespace marionette::bml
