// StaticCameraPose: the view matrix and the validation of its inputs. The angle of a rotation and
// of a view's error, from a ten-millionth of a degree to a half turn.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

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

TEST(CameraPose, RotationAngleFromATenMillionthOfADegreeToAHalfTurn) {
  // acos of the trace read 0 below ~1e-6 degrees in double (its cosine rounds to 1).
  const glm::dvec3 axes[] = {{0, 0, 1}, glm::normalize(glm::dvec3(1, -2, 0.5)), glm::normalize(glm::dvec3(-0.3, 0.2, 0.9))};
  for (const double degrees : {1e-7, 1e-6, 1e-4, 0.01, 1.0, 45.0, 90.0, 179.0, 179.9999, 180.0})
    for (const glm::dvec3& axis : axes) {
      const glm::dmat3 r = glm::mat3_cast(glm::angleAxis(glm::radians(degrees), axis));
      const double got = rotationAngleDegrees(r);
      EXPECT_NEAR(got, degrees, 1e-9) << degrees << " degrees";
      EXPECT_NEAR(got / degrees, 1.0, 1e-6) << degrees << " degrees";
    }
  EXPECT_EQ(rotationAngleDegrees(glm::dmat3(1.0)), 0.0);
}

TEST(CameraPose, ViewRotationErrorResolvesATenThousandthOfADegree) {
  // A camera 2.4 m from the origin looking at it, rolled: its camera-to-world matrix, and views
  // turned from it by tiny angles about an oblique axis of the camera. The restore's
  // placement_error_deg printed exactly 0 for such views (acos of the trace of a float matrix
  // cannot resolve a few hundredths of a degree).
  const glm::dmat4 worldToCamera = glm::lookAt(glm::dvec3(0.3, 1.2, 2.0), glm::dvec3(0.0), glm::dvec3(0.2, 1, 0));
  const glm::dmat4 cameraToWorld = glm::inverse(worldToCamera);
  EXPECT_NEAR(viewRotationErrorDegrees(cameraToWorld, worldToCamera), 0.0, 1e-9);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.4, -1, 0.7));
  for (const double degrees : {1e-4, 1e-3, 0.02, 0.5, 5.0}) {
    const glm::dmat4 turned = glm::mat4_cast(glm::angleAxis(glm::radians(degrees), axis));
    const glm::dmat4 view = glm::inverse(cameraToWorld * turned);
    EXPECT_NEAR(viewRotationErrorDegrees(cameraToWorld, view), degrees, 1e-6 * degrees) << degrees << " degrees";
  }
}
