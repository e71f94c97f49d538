// The standard camera paths a tracker is measured on: each a deterministic list of exact
// camera-to-world poses, per-frame effects and the target's visible share, at 30 fps.
// Distances scale with the target's width (2x .. 3x it: 0.6 .. 0.9 m for a 0.30 m target,
// which then spans about a third to a half of a 640-pixel-wide image at fx 600).
//
//   orbit          slow orbit (20 deg/s), 2x..3x the width away, elevation 35..60 deg,
//                  vertical bob and a little roll, looking at the target's centre
//   static         one pose for every frame, noise sigma 2 (jitter)
//   fast_turn      fast orbit (90 deg/s) with turns of 90 deg about the camera's own vertical
//                  axis at up to ~340 deg/s (>= 180 deg/s mean); the target leaves and returns
//   blur           orbit (45 deg/s) with motion blur 9..25 px along the image motion
//   noise_jpeg     orbit with noise sigma 6 and JPEG quality 30
//   gain           orbit with the gain swinging smoothly between -1 and +1 EV
//   occluder       orbit with an occluder covering 20..60 % of the target, sweeping across
//   partial        the camera moved sideways so that 20..50 % of the target is in view
//   grazing        elevation from 50 deg down to 20 deg above the plane and back
//   lost_regained  the camera pans away about the world's vertical so that the target is out
//                  of view for about the middle third of the frames, then back
#pragma once
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "tracking/synthetic_sequence.hpp"

namespace marionette::ar::synthetic {

struct Scenario {
  std::string name;
  std::string description;
  double fps = 30;
  std::vector<glm::dmat4> cameraToWorld;
  std::vector<FrameEffects> effects;
  std::vector<double> visibleFraction;  // renderer.visibleTargetFraction of each pose
  std::vector<double> smearPx;  // stress sequences: the target centre's smear per frame (else empty)
  std::vector<double> hiddenFraction;  // stress sequences: the target's share hidden by hands (else empty)
};

// All of the above, framesPerScenario frames each (>= 2). Speeds are per second, so fewer
// frames cover a shorter stretch of a path; the phases of `grazing` and `lost_regained` are
// shares of the sequence.
[[nodiscard]] std::vector<Scenario> standardScenarios(const SequenceRenderer& renderer, int framesPerScenario = 150);

[[nodiscard]] std::vector<std::string> standardScenarioNames();

// The AR authoring demo's camera (docs/authoring.md), not one of the standard scenarios: a user
// standing 3 m from the centre of a target lying on the floor (the demo's 2 m mat), the phone at
// 1.7 m, sweeping from -15 to +15 deg around the spot behind the mat where a life-size character
// goes, so that both the whole mat and a 1.7 m character fit in the view. Absolute metres: made
// for a target about 2 m wide.
[[nodiscard]] Scenario authoringSweep(const SequenceRenderer& renderer, int frames = 150);

// `count` camera poses a relaunch starts from around `authored` (camera-to-world): the camera
// moved 0.4..1.2 m from it and its view turned 0..30 deg from the authored view, still looking
// at the target (a user back at the spot points the phone at the scene). Deterministic.
struct RelaunchPose {
  glm::dmat4 cameraToWorld{1.0};
  double moved = 0;        // metres from the authored camera
  double turnedDeg = 0;    // angle between the two viewing directions
};
[[nodiscard]] std::vector<RelaunchPose> relaunchPoses(const SequenceRenderer& renderer, const glm::dmat4& authored,
                                                      int count = 10);

// Orbit helpers, exposed for the tests and the tools. Azimuth 0 puts the camera on +Z,
// elevation is above the plane, distance in metres, roll about the view axis.
[[nodiscard]] glm::dmat4 orbitPose(double azimuthDeg, double elevationDeg, double distance, double rollDeg = 0,
                                   glm::dvec3 lookAt = glm::dvec3(0));

}  // namespace marionette::ar::synthetic
