// Where the AR camera is, over scene time: StaticCameraPose is a fixed camera from the scene
// file. A tracked camera (app/tracked_camera.hpp, examples/ar/tracking) takes its pose from
// the background's frames instead, so it is not a CameraPoseSource.
// Convention: +Y up, right-handed; the view matrix maps world to camera space, the camera
// looking along its -Z (OpenGL).
#pragma once
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <optional>
#include <string>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar {

struct CameraPose {
  glm::mat4 view{1.0f};      // world -> camera
  float fovYDegrees = 60.0f;  // vertical field of view, degrees, in (0, 180)
};

class CameraPoseSource {
 public:
  virtual ~CameraPoseSource() = default;
  // The pose at scene time `seconds`.
  [[nodiscard]] virtual CameraPose poseAt(double seconds) const = 0;
};

class StaticCameraPose final : public CameraPoseSource {
 public:
  // A camera at `position` looking at `target`, `up` giving the roll. Errors (nothing
  // returned; each names `file`, e.g. the scene file, when given): a NaN or infinite
  // component, target == position (zero-length look direction), `up` zero or parallel to the
  // look direction, fovYDegrees outside (0, 180).
  [[nodiscard]] static std::optional<StaticCameraPose> create(const glm::vec3& position, const glm::vec3& target,
                                                              const glm::vec3& up, float fovYDegrees,
                                                              Diagnostics& diagnostics, const std::string& file = {});

  [[nodiscard]] CameraPose poseAt(double /*seconds*/) const override { return pose_; }
  [[nodiscard]] const glm::vec3& position() const noexcept { return position_; }

 private:
  StaticCameraPose(const CameraPose& pose, const glm::vec3& position) : pose_(pose), position_(position) {}
  CameraPose pose_;
  glm::vec3 position_{0.0f};
};

// The angle of rotation `r`, degrees in [0, 180]: atan2 of its axis-angle sine and cosine, which
// resolves 1e-7 degrees (acos of the trace reads 0 below ~1e-6 degrees in double, and a float
// matrix's trace cannot resolve a few hundredths of a degree).
[[nodiscard]] double rotationAngleDegrees(const glm::dmat3& r) noexcept;

// How far `view` (world -> camera) turns the world from the true camera's: the angle of the
// rotation of trueCameraToWorld * view, 0 for an exact view. The orientation error of anything
// drawn with `view` (the restore's placement_error_deg, docs/authoring.md). Both in double: a
// view rounded to float is already off by ~1e-5 degrees.
[[nodiscard]] double viewRotationErrorDegrees(const glm::dmat4& trueCameraToWorld, const glm::dmat4& view) noexcept;

}  // namespace marionette::ar
