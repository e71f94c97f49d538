// Writing a skeleton and a clip as a BVH motion file (Biovision hierarchy).
//
// BVH has no rest rotations and no scale, so the file carries:
//  - OFFSET: each joint's rest translation, in file units (BvhWriteOptions::unitScale).
//  - Per frame, the joint's full local rotation (the rest rotation included when the
//    clip does not animate the joint) as Euler angles in degrees, channel order
//    "Zrotation Xrotation Yrotation": R = Rz(z) * Rx(x) * Ry(y) applied to column
//    vectors, which is how Assimp (and most readers) compose the channels in the
//    order they are listed.
//  - Position channels "Xposition Yposition Zposition" on the root and on every
//    joint whose translation the clip moves away from rest. They hold the full
//    local translation (they replace OFFSET, as Assimp and Blender read them).
//  - Skeleton::rootTransform baked into the root's channels; a uniform scale in it
//    scales every length. Mirroring, non-uniform scale or shear there is an error.
//  - Several roots: wrapped under one synthetic ROOT "MarionetteRoot" (warning).
//  - Names: whitespace, braces and control characters become '_', empty names
//    "joint_N", duplicates get "_2", "_3"... (warning naming them).
//  - Joint scale other than 1: dropped, with a warning naming the joints.
// Euler angles stay continuous between frames (the closer of the two Euler
// solutions, unwrapped by 360 degrees towards the previous frame), so readers that
// interpolate channels do not spin, and are exact at gimbal lock (|x| = 90).
#pragma once
#include <string>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct BvhWriteOptions {
  // Frames per second. 0: 30 if the clip has no key spacing (no keys, or one key
  // per track), else the densest track's mean key spacing, capped at 120.
  float frameRate = 0.0f;
  float unitScale = 1.0f;  // file units per metre (skeleton lengths are metres), e.g. 100 for cm
  int precision = 6;       // decimals of every number in the file (0..9)
};

// Name given to the synthetic root that holds several skeleton roots.
inline constexpr const char* kBvhSyntheticRoot = "MarionetteRoot";

// Writes `clip` (bound to `skeleton`) to `path`. Never throws. Errors name the file
// and the problem; on error nothing is written (the file is written whole or not at
// all, through a temporary beside it). Warnings say what BVH could not hold.
[[nodiscard]] Diagnostics writeBvh(const std::string& path, const Skeleton& skeleton, const Clip& clip,
                                   const BvhWriteOptions& options = {});

// The file's text, or empty with an error in `diagnostics` (which name `file`).
[[nodiscard]] std::string bvhText(const Skeleton& skeleton, const Clip& clip, const BvhWriteOptions& options,
                                  Diagnostics& diagnostics, const std::string& file = {});

// The name each skeleton joint gets in the file (sanitized, unique), by joint index.
[[nodiscard]] std::vector<std::string> bvhJointNames(const Skeleton& skeleton);

// Euler angles of the BVH channels, in degrees: R = Rz(z) * Rx(x) * Ry(y).
struct BvhEuler {
  double z = 0.0, x = 0.0, y = 0.0;
};

// The angles of `rotation`; with `previous`, the solution nearest to it (each angle
// unwrapped by multiples of 360 towards it). At gimbal lock (cos x = 0) only z -/+ y
// is defined: y keeps its previous value (0 without one).
[[nodiscard]] BvhEuler toBvhEuler(const glm::quat& rotation, const BvhEuler* previous = nullptr) noexcept;
[[nodiscard]] glm::dquat fromBvhEuler(const BvhEuler& angles) noexcept;

}  // namespace marionette
