// The error metric of clip compression (ACL's): how far apart two poses put virtual
// vertices a few centimetres from each joint, in model space. It sees what a skinned
// mesh would: a rotation error counts by the distance it swings things, and errors
// accumulate down the hierarchy as they do on screen.
#pragma once
#include <span>

#include <glm/glm.hpp>

namespace marionette {

// For each joint j: the largest distance between the two poses' positions of the joint's
// origin and of the six points `distance` along its +-x, +-y, +-z axes (axes normalized,
// so the distance is in model units whatever the joint's scale). Returns the largest over
// the joints; perJoint (when not empty) gets each joint's. The shortest span decides.
float virtualVertexError(std::span<const glm::mat4> a, std::span<const glm::mat4> b, float distance,
                         std::span<float> perJoint = {}) noexcept;

}  // namespace marionette
