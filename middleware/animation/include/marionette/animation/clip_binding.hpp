// A clip made for one skeleton, played on another of the same joint names.
#pragma once
#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// Re-targets a clip's joint indices from one skeleton to another by exact joint
// name (same naming, e.g. a Pab motion file onto the Pab character). Tracks of
// joints the target lacks are dropped and counted in `unmatched` when given.
[[nodiscard]] Clip bindClipByName(const Clip& clip, const Skeleton& from, const Skeleton& to,
                                  int* unmatched = nullptr);

}  // namespace marionette
