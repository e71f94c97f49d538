// The procedural controllers that need no clip: head movements (NOD, SHAKE,
// TILT, additive on neck and head) and face expressions (lexemes and FACS
// units to morph weights through the rig's profile). Stateless: a character
// that has no such request pays nothing. bind*() runs at command time (may
// allocate) and says why a request cannot be realized; apply*() is per-frame.
#pragma once
#include <functional>
#include <span>
#include <string_view>
#include <string>

#include "marionette/behavior/behavior_timeline.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

// Empty when the rig can perform the head request (its state is stored in the
// entry's controller), else why not (the entry is left as it was). `warning` gets a note on a bad parameter that was replaced.
[[nodiscard]] std::string bindHead(BehaviorTimeline::Entry& entry, const Rig& rig, std::string& warning);
// A face expression the profile's face table lacks goes through FACS (rig/facs.hpp): a unit
// (AU12, AU46_L) or a named expression (WINK, RAISE_LEFT_BROW) to the units' morphs or joints,
// with one warning naming what shows each unit.
[[nodiscard]] std::string bindFace(BehaviorTimeline::Entry& entry, const Rig& rig, std::string& warning);
// Each reads its kind's parameters (HeadParameters, FaceParameters, GazeParameters);
// a gaze at a character without a joint looks at its head. `findJoint` answers the joint index of a named character (-2: no such character).
[[nodiscard]] std::string bindGaze(BehaviorTimeline::Entry& entry, const Rig& rig,
                                   const TargetJointFinder& findJoint,
                                   std::string& warning);

void applyHead(const HeadMotionState& head, float weight, double t, const Rig& rig, std::span<Transform> pose) noexcept;
// Morph weights add up (each clamped to [0, 1]); eyelid and brow joints move in the model frame.
void applyFace(const FaceExpressionState& face, float weight, std::span<float> morphWeights, const Rig& rig,
               std::span<Transform> pose) noexcept;

}  // namespace marionette
