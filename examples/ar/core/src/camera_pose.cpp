#include "marionette_ar/camera_pose.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include "marionette/core/finite.hpp"

namespace marionette::ar {

namespace {
std::string str(const glm::vec3& v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}
}  // namespace

std::optional<StaticCameraPose> StaticCameraPose::create(const glm::vec3& position, const glm::vec3& target,
                                                         const glm::vec3& up, float fovYDegrees,
                                                         Diagnostics& diagnostics, const std::string& file) {
  const std::size_t errorsBefore = diagnostics.items.size();
  if (!isFinite(position)) diagnostics.error(file, "camera position " + str(position) + " is not finite");
  if (!isFinite(target)) diagnostics.error(file, "camera target " + str(target) + " is not finite");
  if (!isFinite(up)) diagnostics.error(file, "camera up " + str(up) + " is not finite");
  if (!std::isfinite(fovYDegrees) || !(fovYDegrees > 0.0f && fovYDegrees < 180.0f))
    diagnostics.error(file, "camera vertical field of view " + std::to_string(fovYDegrees) +
                                " degrees is outside (0, 180)");
  if (diagnostics.items.size() != errorsBefore) return std::nullopt;

  const glm::dvec3 look = glm::dvec3(target) - glm::dvec3(position);
  const double lookLength = glm::length(look), upLength = glm::length(glm::dvec3(up));
  if (!(lookLength > 1e-9)) {
    diagnostics.error(file, "camera target " + str(target) + " equals its position: no look direction");
    return std::nullopt;
  }
  if (!(upLength > 1e-12)) {
    diagnostics.error(file, "camera up vector is zero");
    return std::nullopt;
  }
  // sin of the angle between up and the look direction.
  const double sine = glm::length(glm::cross(look / lookLength, glm::dvec3(up) / upLength));
  if (!(sine > 1e-6)) {
    diagnostics.error(file, "camera up " + str(up) + " is parallel to the look direction " +
                                str(glm::vec3(look / lookLength)) + ": the roll is undefined");
    return std::nullopt;
  }
  CameraPose pose;
  pose.view = glm::mat4(glm::lookAt(glm::dvec3(position), glm::dvec3(target), glm::dvec3(up)));
  pose.fovYDegrees = fovYDegrees;
  return StaticCameraPose(pose, position);
}

double rotationAngleDegrees(const glm::dmat3& r) noexcept {
  // R - R^T = 2 sin(angle) [axis]x and trace(R) - 1 = 2 cos(angle): twice the sine and cosine.
  const glm::dvec3 twiceSine(r[1][2] - r[2][1], r[2][0] - r[0][2], r[0][1] - r[1][0]);
  return glm::degrees(std::atan2(glm::length(twiceSine), r[0][0] + r[1][1] + r[2][2] - 1.0));
}

double viewRotationErrorDegrees(const glm::dmat4& trueCameraToWorld, const glm::dmat4& view) noexcept {
  return rotationAngleDegrees(glm::dmat3(trueCameraToWorld * view));
}

}  // namespace marionette::ar
