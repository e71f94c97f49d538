// A measured locomotion walk on a rig with a profile: the one definition of
// foot skating, arrival and facing error and planted-foot error, shared by the
// import tests and the work-precision program (no gtest here).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "marionette/scene/scene.hpp"

namespace marionette::test {

struct WalkSpec {
  glm::vec2 target{0.0f};
  float facingDegrees = 0.0f;
  LocomotionManner manner = LocomotionManner::Walk;
  float speed = 0.0f;  // m/s; 0: the manner's preset
};

struct WalkMeasure {
  bool realized = false;  // the request was accepted and has a controller
  std::string message;    // why not, when !realized
  bool done = false;      // arrived and turned
  float seconds = 0.0f;   // clock of the arrival
  float arrivalError = 0.0f, facingError = 0.0f;  // m, rad
  int frames = 0, contactFrames = 0, skatingFrames = 0;
  float skatingRatio = 1.0f;  // skating over contact frames
  // Largest horizontal distance of a planted foot (as drawn) from where it was on
  // the frame it locked; the same over the locks made at full gait weight (not
  // while the gait blends in over the posture); and the IK's own largest miss.
  // 0 when nothing planted.
  float plantedDrift = 0.0f, plantedDriftFullGait = 0.0f, ikResidual = 0.0f;
  int locks = 0;          // feet planted (each touch-down once)
  int fullGaitLocks = 0;  // of them made at full gait weight (none: the gait never got there)
  int steps = 0;          // catch-up steps (a planted foot the leg could no longer reach)
  // The cruise: the frames at the top speed of the walk (within 1 %) with the gait
  // at full weight; the run clip's weight over them, and skating counted on them
  // alone (the ground as for the whole walk).
  float topSpeed = 0.0f;
  int cruiseFrames = 0;
  float cruiseRunWeightMin = 0.0f, cruiseRunWeightMax = 0.0f;
  int cruiseContactFrames = 0, cruiseSkatingFrames = 0;
  // Sums over the frames, when the scene's stats are on (CharacterStats).
  double updateMicros = 0.0, locomotionMicros = 0.0;
};

// Walks from the origin (facing +Z, the idle clip playing) to `spec.target` with
// `settings` at a fixed step `dt`, until arrived and the gait has blended out (at
// most 30 s). A frame skates when a foot is within 5 cm of its lowest height in
// the trace and moves faster than 0.5 m/s horizontally; the ratio is skating
// frames over such ground-contact frames. `timing` turns the scene's stats on.
inline WalkMeasure measureWalk(const std::shared_ptr<const Rig>& rig, const WalkSpec& spec, float dt,
                               const LocomotionSettings& settings = {}, bool timing = false) {
  constexpr float kPi = 3.14159265f;
  WalkMeasure result;
  Scene scene;
  scene.setStatsEnabled(timing);
  Character* c = scene.addCharacter("c", rig);
  c->setLocomotionSettings(settings);
  if (!rig->profile().idle.empty()) c->play(0, rig->profile().idle);
  BehaviorRequest r;
  r.id = "walk";
  r.kind = BehaviorKind::Locomotion;
  r.syncs = {{"start", 0.0}, {"end", 5.0}};
  LocomotionParameters where;
  where.waypoints = {spec.target};
  where.manner = spec.manner;
  where.facing = spec.facingDegrees * (kPi / 180.0f);
  if (spec.speed > 0.0f) where.speed = spec.speed;
  r.parameters = std::move(where);
  const BehaviorResult added = c->addBehavior(r);
  result.realized = added.realized;
  result.message = added.message;
  const int feet[2] = {rig->joints().leftLeg.end, rig->joints().rightLeg.end};
  if (!added.realized || feet[0] < 0 || feet[1] < 0) return result;

  std::vector<glm::vec3> trace[2];
  std::vector<int> planted[2];
  std::vector<float> gaitWeight, speed, runWeight;
  glm::vec3 lockedAt[2]{};
  bool lockedAtFullGait[2] = {false, false};
  const int maxFrames = static_cast<int>(30.0f / dt);
  for (int frame = 0; frame < maxFrames; ++frame) {
    scene.update(dt);
    ++result.frames;
    result.updateMicros += c->stats().lastUpdateMicros;
    result.locomotionMicros += c->stats().micros(Controller::Locomotion);
    const LocomotionController* loco = c->locomotion();
    for (int f = 0; f < 2; ++f) {
      const glm::vec3 p(c->transformBuffer().worldMatrix() *
                        c->transformBuffer().modelMatrices()[static_cast<std::size_t>(feet[f])][3]);
      trace[f].push_back(p);
      const bool isPlanted = loco && loco->feet().planted(f);
      if (isPlanted && (planted[f].empty() || !planted[f].back())) {
        lockedAt[f] = p;
        ++result.locks;
        lockedAtFullGait[f] = loco->weight() >= 0.99f;
        result.fullGaitLocks += lockedAtFullGait[f];
      }
      if (isPlanted) {
        const float drift = std::hypot(p.x - lockedAt[f].x, p.z - lockedAt[f].z);
        result.plantedDrift = std::max(result.plantedDrift, drift);
        if (lockedAtFullGait[f]) result.plantedDriftFullGait = std::max(result.plantedDriftFullGait, drift);
      }
      planted[f].push_back(isPlanted);
    }
    if (loco && (loco->feet().planted(0) || loco->feet().planted(1)))
      result.ikResidual = std::max(result.ikResidual, loco->feet().lastResidual());
    gaitWeight.push_back(loco ? loco->weight() : 0.0f);
    speed.push_back(loco ? loco->steering().speed : 0.0f);
    runWeight.push_back(loco ? loco->runWeight() : 0.0f);
    const LocomotionStatus st = c->locomotionStatus("walk");
    if (st.state == LocomotionStatus::State::Done && !result.done) {
      result.done = true;
      result.seconds = static_cast<float>(st.doneTime);
    }
    if (result.done && loco && loco->weight() == 0.0f) break;
  }
  if (const LocomotionController* loco = c->locomotion()) result.steps = loco->feet().steps();
  for (float v : speed) result.topSpeed = std::max(result.topSpeed, v);
  std::vector<bool> cruise(speed.size(), false);
  result.cruiseRunWeightMin = 1.0f;
  for (std::size_t k = 0; k < speed.size(); ++k) {
    cruise[k] = result.topSpeed > 0.0f && speed[k] >= 0.99f * result.topSpeed && gaitWeight[k] >= 0.99f;
    if (!cruise[k]) continue;
    ++result.cruiseFrames;
    result.cruiseRunWeightMin = std::min(result.cruiseRunWeightMin, runWeight[k]);
    result.cruiseRunWeightMax = std::max(result.cruiseRunWeightMax, runWeight[k]);
  }
  if (result.cruiseFrames == 0) result.cruiseRunWeightMin = 0.0f;
  result.arrivalError = glm::length(glm::vec2(c->position().x, c->position().z) - spec.target);
  result.facingError = std::fabs(std::remainder(c->heading() - spec.facingDegrees * kPi / 180.0f, 2.0f * kPi));
  const bool debug = std::getenv("MARIONETTE_DEBUG_SKATING") != nullptr;
  for (int f = 0; f < 2; ++f) {
    float lowest = 1e9f;
    for (const glm::vec3& p : trace[f]) lowest = std::min(lowest, p.y);
    for (std::size_t k = 1; k < trace[f].size(); ++k) {
      if (trace[f][k].y - lowest > 0.05f) continue;
      ++result.contactFrames;
      result.cruiseContactFrames += cruise[k];
      const glm::vec3 d = trace[f][k] - trace[f][k - 1];
      if (std::hypot(d.x, d.z) / dt > 0.5f) {
        ++result.skatingFrames;
        result.cruiseSkatingFrames += cruise[k];
        if (debug)
          std::printf("skate foot %d frame %zu h %.3f v %.2f planted %d/%d w %.2f\n", f, k, trace[f][k].y - lowest,
                      std::hypot(d.x, d.z) / dt, planted[f][k - 1], planted[f][k], gaitWeight[k]);
      }
    }
  }
  result.skatingRatio = result.contactFrames
                            ? static_cast<float>(result.skatingFrames) / static_cast<float>(result.contactFrames)
                            : 1.0f;
  return result;
}

}  // namespace marionette::test
