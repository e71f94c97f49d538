// Other realizers' spellings of BML behaviors, rewritten into the standard form that the
// scheduler and the behavior mapping read (issue 24, 5): SmartBody's <head type repeats>,
// <face type="facs">, <gesture name>. Private to the parser (document.cpp).
#pragma once
#include <string>

#include "marionette/bml/document.hpp"

namespace marionette::bml::detail {

// Rewrites `b` in place; returns a warning ("" when none) for what could only be read
// approximately (a fractional repeats, a face type that is not facs).
// `smartBody`: the block is read in SmartBody mode (its locomotion targets are z-up).
std::string standardizeSpellings(Behavior& b, bool smartBody);

}  // namespace marionette::bml::detail
