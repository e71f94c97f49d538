#include "marionette_ar/tracking_state.hpp"

#include "marionette/core/enum_names.hpp"

namespace marionette::ar {

namespace {
constexpr EnumName<TrackingState> kNames[] = {
    {"TRACKING", TrackingState::Tracking}, {"LIMITED", TrackingState::Limited}, {"LOST", TrackingState::Lost}};
}  // namespace

std::string_view trackingStateName(TrackingState state) noexcept {
  return nameOfValue<TrackingState>(state, kNames, "LOST");
}

std::optional<TrackingState> trackingStateFromName(std::string_view name) noexcept {
  return valueOfName<TrackingState>(name, kNames);
}

std::string trackingStateNames() { return validNames<TrackingState>(kNames); }

}  // namespace marionette::ar
