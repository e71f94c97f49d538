// How a clip plays on a character's layer (Character::play).
#pragma once
#include <vector>

#include "marionette/animation/sampling.hpp"

namespace marionette {

struct PlayOptions {
  float weight = 1.0f;               // target weight (blend is relative; see blendPoses)
  float speed = 1.0f;                // playback rate; 0 holds, negative plays backwards
  WrapMode wrap = WrapMode::Loop;    // Clamp holds the last frame
  double startTime = 0.0;            // clip-local time to start at
  float fadeIn = 0.0f;               // seconds to reach `weight` (0: at once)
  bool additive = false;             // play as a delta against the clip's first frame
  bool rootMotion = false;           // move the character by the clip's root motion
  std::vector<float> jointMask{};    // optional per-joint weights in [0,1]; empty = whole body
};

}  // namespace marionette
