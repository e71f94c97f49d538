// StaticCameraPose: the view matrix and the validation of its inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "marionette_ar/camera_pose.hpp"

using namespace marionette::ar;
using marionette::Diagnostics;

TEST(CameraPose, StaticPoseLooksAtTheTarget) {
  Diagnostics d;
  auto cam = StaticCameraPose::create({0, 1.5f, 3}, {0, 1, 0}, {0, 1, 0}, 45.0f, d, "scene.json");
  ASSERT_TRUE(cam) << d.format();
  const CameraPose pose = cam->poseAt(12.0);
  EXPECT_EQ(pose.fovYDegrees, 45.0f);
  // The target is on the camera's -Z axis, the camera at the origin of camera space.
  const glm::vec4 target = pose.view * glm::vec4(0, 1, 0, 1);
  EXPECT_NEAR(target.x, 0.0f, 1e-6f);
  EXPECT_NEAR(target.y, 0.0f, 1e-6f);
  EXPECT_NEAR(target.z, -std::sqrt(0.25f + 9.0f), 1e-5f);
  const glm::vec4 eye = pose.view * glm::vec4(0, 1.5f, 3, 1);
  EXPECT_NEAR(glm::length(glm::vec3(eye)), 0.0f, 1e-6f);
  // World +X is the camera's right.
  const glm::vec4 right = pose.view * glm::vec4(1, 0, 0, 0);
  EXPECT_GT(right.x, 0.99f);
}

TEST(CameraPose, InvalidInputsAreErrorsNamingTheFile) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    glm::vec3 position, target, up;
    float fov;
    const char* expect;
  } cases[] = {
      {{nan, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, "not finite"},
      {{0, 0, 0}, {0, std::numeric_limits<float>::infinity(), 0}, {0, 1, 0}, 60, "not finite"},
      {{1, 2, 3}, {1, 2, 3}, {0, 1, 0}, 60, "no look direction"},
      {{0, 0, 0}, {0, 5, 0}, {0, 1, 0}, 60, "parallel"},
      {{0, 0, 0}, {0, 0, -1}, {0, 0, 2}, 60, "parallel"},
      {{0, 0, 0}, {0, 0, -1}, {0, 0, 0}, 60, "zero"},
      {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0, "field of view"},
      {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 180, "field of view"},
      {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, nan, "field of view"},
  };
  for (const Case& c : cases) {
    Diagnostics d;
    EXPECT_FALSE(StaticCameraPose::create(c.position, c.target, c.up, c.fov, d, "scenes/ar.json")) << c.expect;
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.items[0].file, "scenes/ar.json");
    EXPECT_NE(d.format().find(c.expect), std::string::npos) << d.format();
  }
}
