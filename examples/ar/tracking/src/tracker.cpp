#include "marionette_ar/tracking/tracker.hpp"

#include <glm/gtc/matrix_access.hpp>

namespace marionette::ar {

glm::dquat TrackedPose::orientation() const noexcept { return glm::quat_cast(glm::dmat3(cameraToWorld)); }

glm::dmat4 cameraToWorldFromOpenCv(const glm::dmat3& worldToCvCameraRotation,
                                   const glm::dvec3& worldToCvCameraTranslation) noexcept {
  // OpenCV camera -> world: R^T, position -R^T t. The renderer's camera axes are OpenCV's
  // with Y and Z negated, i.e. the second and third columns of the rotation flip sign.
  const glm::dmat3 cvCameraToWorld = glm::transpose(worldToCvCameraRotation);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(cvCameraToWorld[0], 0.0);
  m[1] = glm::dvec4(-cvCameraToWorld[1], 0.0);
  m[2] = glm::dvec4(-cvCameraToWorld[2], 0.0);
  m[3] = glm::dvec4(-(cvCameraToWorld * worldToCvCameraTranslation), 1.0);
  return m;
}

}  // namespace marionette::ar
