#include "marionette_ar/tracking_state.hpp"

namespace marionette::ar {

std::string_view trackingStateName(TrackingState state) noexcept {
  switch (state) {
    case TrackingState::Tracking: return "TRACKING";
    case TrackingState::Limited: return "LIMITED";
    case TrackingState::Lost: break;
  }
  return "LOST";
}

}  // namespace marionette::ar
