#include "marionette/bml/feedback.hpp"

namespace marionette::bml {

std::string_view toString(WarningType type) noexcept {
  switch (type) {
    case WarningType::ParsingFailure: return "PARSING_FAILURE";
    case WarningType::NoSuchTarget: return "NO_SUCH_TARGET";
    case WarningType::ImpossibleToSchedule: return "IMPOSSIBLE_TO_SCHEDULE";
    case WarningType::BehaviorTypeNotSupported: return "BEHAVIOR_TYPE_NOT_SUPPORTED";
    case WarningType::CustomBehaviorNotSupported: return "CUSTOM_BEHAVIOUR_NOT_SUPPORTED";
    case WarningType::CustomAttributeNotSupported: return "CUSTOM_ATTRIBUTE_NOT_SUPPORTED";
    case WarningType::CannotCreateBehavior: return "CANNOT_CREATE_BEHAVIOR";
  }
  return "PARSING_FAILURE";
}

}  // namespace marionette::bml
