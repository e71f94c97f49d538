// The default sync table's part that the scheduler reads too (default_syncs.cpp; the table
// itself is the public defaultSyncs). Private to the scheduler's files.
#pragma once
#include <string_view>

namespace marionette::bml::detail {

// Head, gesture and pointing repeat their stroke phase (repetition="R").
bool repeats(std::string_view type);

}  // namespace marionette::bml::detail
