#include "frame_inputs.hpp"

#include <glm/gtc/matrix_transform.hpp>

namespace marionette::ar {

struct FrameInputs::Sources {};

FrameInputs::FrameInputs() = default;
FrameInputs::~FrameInputs() = default;

bool FrameInputs::load(const ArScene& scene, std::string& error) {
  cameraSettings_ = scene.camera;
  kind_ = scene.background.kind;
  // Neutral sky until the environment module lands: constant radiance 0.8.
  irradiance_.fill(glm::vec3(0.0f));
  irradiance_[0] = glm::vec3(3.14159265f * 0.8f / 0.282095f);
  if (kind_ == ArBackground::Kind::Environment) kind_ = ArBackground::Kind::Color;
  if (kind_ == ArBackground::Kind::Image && !readImage(scene.background.file, still_, error)) return false;
  return true;
}

const Image8* FrameInputs::backgroundFrame(double /*time*/, std::string& error) {
  error.clear();
  return still_.empty() ? nullptr : &still_;
}

CameraView FrameInputs::camera(double /*time*/, float aspect) const {
  CameraView v;
  v.view = glm::lookAt(cameraSettings_.position, cameraSettings_.target, cameraSettings_.up);
  v.projection = glm::perspective(glm::radians(cameraSettings_.fovYDegrees), aspect, cameraSettings_.nearPlane,
                                  cameraSettings_.farPlane);
  return v;
}

}  // namespace marionette::ar
