// A synthetic rig: a 4-joint chain with a walking clip (root moves +Z 1 m per
// 1 s cycle, sways in x) and a waving clip on the top joint.
#pragma once
#include <memory>

#include "marionette/rig/rig.hpp"
#include "synthetic.hpp"

namespace marionette::test {

inline std::shared_ptr<const Rig> makeSyntheticRig() {
  auto asset = std::make_shared<Asset>();
  asset->skeleton = makeChain(4);
  asset->morphTargets = {"smile", "blink"};
  Clip walk;
  walk.name = "walk";
  JointTrack root;
  root.joint = 0;
  for (int k = 0; k <= 10; ++k) {
    const float t = static_cast<float>(k) * 0.1f;
    root.translation.times.push_back(t);
    root.translation.values.push_back({0.05f * std::sin(6.2831853f * t), 1.0f, t});
  }
  walk.tracks.push_back(root);
  walk.tracks.push_back(rotationTrack(1, {0.0f, 0.5f, 1.0f}, {0.0f, 0.4f, 0.0f}, {1, 0, 0}));
  MorphTrack m;
  m.targets = {1};
  m.times = {0.0f, 1.0f};
  m.weights = {0.0f, 1.0f};
  walk.morphTracks.push_back(m);
  walk.updateDuration();
  Clip wave;
  wave.name = "wave";
  wave.tracks.push_back(rotationTrack(3, {0.0f, 0.25f, 0.5f}, {0.0f, 1.2f, 0.0f}, {0, 0, 1}));
  wave.updateDuration();
  asset->clips = {walk, wave};
  return std::make_shared<Rig>(*asset);
}

}  // namespace marionette::test
