// Per-frame working memory that characters share: the scene owns one, sized to
// its largest skeleton, so blending N layers on 1000 characters touches one
// scratch pose (hot in cache) instead of N poses per character.
#pragma once
#include <cstddef>
#include <vector>

#include "marionette/animation/blending.hpp"
#include "marionette/core/allocator.hpp"
#include "marionette/core/transform.hpp"

namespace marionette {

// Through the runtime allocator, the object and its arrays (core/allocator.hpp).
struct FrameScratch : RuntimeAllocated {
  RuntimeVector<Transform> pose;
  BlendAccumulator accumulator;
  void reserve(std::size_t joints);  // grows only
};

}  // namespace marionette
