// The behavior load the benchmarks share: a gaze at a point (NECK, tracking),
// a head nod applied on every frame, and a face expression, on one character;
// optionally locomotion.
#pragma once
#include <string>

#include "marionette/scene/character.hpp"

namespace marionette::test {

// `i` varies the gaze target between characters. False when the character's
// profile cannot realize one of them.
inline bool addGazeNodFace(Character& c, int i) {
  BehaviorRequest gaze;
  gaze.id = "gaze";
  gaze.kind = BehaviorKind::Gaze;
  gaze.parameters = GazeParameters{BehaviorTarget::at({static_cast<float>(i % 7 - 3), 1.5f, 2.0f}), GazeInfluence::Neck};
  gaze.syncs = {{"start", 0.0}, {"ready", 0.3}, {"relax", 1e6}, {"end", 1e6 + 1}};
  BehaviorRequest nod;
  nod.id = "nod";
  nod.kind = BehaviorKind::Head;
  nod.parameters = HeadParameters{HeadLexeme::Nod};
  // One long stroke, so the nod is applied (not skipped) on every benchmarked frame.
  nod.syncs = {{"start", 0.0}, {"strokeStart", 0.0}, {"stroke", 5e5}, {"strokeEnd", 1e6}, {"end", 1e6}};
  BehaviorRequest face;
  face.id = "face";
  face.kind = BehaviorKind::FaceLexeme;
  face.parameters = FaceParameters{"ANGER", 0.5f};
  face.syncs = {{"start", 0.0}, {"attackPeak", 0.3}, {"relax", 1e6}, {"end", 1e6 + 1}};
  return c.addBehavior(gaze).realized && c.addBehavior(nod).realized && c.addBehavior(face).realized;
}

// Locomotion at a speed between the walk and the run (both clips blended, feet
// planted), toward a point 400 m ahead so that no character arrives while
// measured. False when the character cannot walk.
inline bool addMidSpeedWalk(Character& c, int i) {
  const LocomotionSet& set = c.locomotionSet();
  BehaviorRequest walk;
  walk.id = "walk";
  walk.kind = BehaviorKind::Locomotion;
  LocomotionParameters ahead;
  ahead.waypoints = {{static_cast<float>(i % 10), 400.0f}};
  ahead.speed = 0.5f * (set.walk.groundSpeed + set.run.groundSpeed);
  walk.parameters = std::move(ahead);
  walk.syncs = {{"start", 0.0}, {"end", 1e6}};
  return c.addBehavior(walk).realized;
}

}  // namespace marionette::test
