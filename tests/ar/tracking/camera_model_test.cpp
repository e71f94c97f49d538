// The camera model: OpenCV calibration YAML in and out, validation, the GL projection.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include <glm/glm.hpp>

#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/tracker.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

std::string tempFile(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("marionette_camera_" + name);
  std::ofstream(p) << text;
  return p.string();
}

const char* kGood = R"(%YAML:1.0
---
image_width: 640
image_height: 480
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 600., 0., 319.5, 0., 610., 239.5, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -0.2, 0.05, 0.001, -0.002, 0.01 ]
)";

TEST(CameraModel, ReadsOpenCvDocsCalibration) {
  const std::string file = test::opencvData("left_intrinsics.yml");
  MARIONETTE_REQUIRE_FILE(file);
  Diagnostics d;
  const auto c = readCameraModel(file, d);
  ASSERT_TRUE(c) << d.format();
  EXPECT_EQ(c->width, 640);
  EXPECT_EQ(c->height, 480);
  EXPECT_NEAR(c->fx, 535.91573396163199, 1e-9);
  EXPECT_EQ(c->fx, c->fy);
  EXPECT_NEAR(c->cx, 342.28315473308373, 1e-9);
  EXPECT_NEAR(c->distortion[0], -0.26637260909660682, 1e-12);
  EXPECT_NEAR(c->distortion[4], 0.23839153080878486, 1e-12);
  EXPECT_TRUE(c->hasDistortion());
}

TEST(CameraModel, WriteThenReadIsExact) {
  Diagnostics d;
  const auto c = readCameraModel(tempFile("good.yml", kGood), d);
  ASSERT_TRUE(c) << d.format();
  const auto out = (std::filesystem::temp_directory_path() / "marionette_camera_out.yml").string();
  Diagnostics error;
  CalibrationFacts facts{.views = 3, .boardColumns = 9, .boardRows = 6, .squareSize = 0.025, .rmsReprojectionError = 0.4};
  ASSERT_TRUE(writeCameraModel(out, *c, &facts, error)) << error.format();
  const auto back = readCameraModel(out, d);
  ASSERT_TRUE(back) << d.format();
  EXPECT_EQ(back->fx, c->fx);
  EXPECT_EQ(back->fy, 610.0);
  EXPECT_EQ(back->cy, c->cy);
  EXPECT_EQ(back->distortion, c->distortion);
}

TEST(CameraModel, BadFilesAreErrorsNamingTheFileAndField) {
  struct Case { const char* name; std::string text; const char* expect; };
  const std::string good = kGood;
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const Case cases[] = {
      {"empty", "", "empty"},
      {"garbage", "\x01\x02 not yaml {{{", "OpenCV"},
      {"no_width", replace("image_width: 640\n", ""), "image_width"},
      {"zero_width", replace("image_width: 640", "image_width: 0"), "image_width"},
      {"fraction_width", replace("image_width: 640", "image_width: 640.5"), "whole number"},
      {"nan_fx", replace("600., 0., 319.5", ".nan, 0., 319.5"), "NaN"},
      {"negative_fx", replace("600., 0., 319.5", "-600., 0., 319.5"), "focal length"},
      {"skew", replace("600., 0., 319.5", "600., 3., 319.5"), "skew"},
      {"outside_cx", replace("319.5, 0., 610.", "9000, 0., 610."), "principal point"},
      {"k_matrix_2x2", replace("rows: 3\n   cols: 3\n   dt: d\n   data: [ 600., 0., 319.5, 0., 610., 239.5, 0., 0., 1. ]",
                               "rows: 2\n   cols: 2\n   dt: d\n   data: [ 600., 0., 0., 610. ]"), "not 3x3"},
      {"dist_count", replace("rows: 5\n   cols: 1\n   dt: d\n   data: [ -0.2, 0.05, 0.001, -0.002, 0.01 ]",
                             "rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.2, 0.05, 0.001 ]"), "4, 5, 8, 12 or 14"},
      {"dist_huge", replace("-0.2, 0.05", "-1e9, 0.05"), "beyond"},
      {"truncated", good.substr(0, good.size() / 2), ""},
      // A word among the numbers: the field and the value, not OpenCV's "readRawData can only be
      // used to read plain sequences of numbers".
      {"k_word", replace("600., 0., 319.5", "600., zero, 319.5"),
       "'camera_matrix': data[1] is \"zero\", not a number"},
      {"dist_word", replace("-0.2, 0.05", "-0.2, k2"), "'distortion_coefficients': data[1] is \"k2\", not a number"},
      {"k_nested", replace("600., 0., 319.5", "600., [ 0. ], 319.5"),
       "'camera_matrix': data[1] is a list, not a number"},
      {"k_no_data", replace("   data: [ 600., 0., 319.5, 0., 610., 239.5, 0., 0., 1. ]\n", ""),
       "'camera_matrix': 'data' is missing or not a list of numbers"},
      {"k_short", replace("0., 0., 1. ]", "0., 0. ]"), "'camera_matrix': 'data' has 8 numbers but rows x cols is 9"},
      // Neither YAML (header or keys), XML nor JSON: what is expected is said.
      {"prose", "My camera: a phone, 640 by 480.\nfx is about 600.\n", "not OpenCV calibration YAML"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string file = tempFile(std::string("bad_") + c.name + ".yml", c.text);
    Diagnostics d;
    EXPECT_FALSE(readCameraModel(file, d));
    ASSERT_FALSE(d.ok());
    const std::string text = d.format();
    EXPECT_NE(text.find(file), std::string::npos) << text;
    EXPECT_NE(text.find(c.expect), std::string::npos) << text;
  }
  Diagnostics d;
  EXPECT_FALSE(readCameraModel("/nonexistent/camera.yml", d));
  EXPECT_NE(d.format().find("does not exist"), std::string::npos);
}

// YAML written by hand often starts with its keys: without "%YAML:1.0" (and "---") OpenCV says
// "Unsupported file storage format"; the reader takes it as YAML 1.0.
TEST(CameraModel, YamlWithoutItsHeaderIsRead) {
  const std::string good = kGood;
  const std::string body = good.substr(good.find("---\n") + 4);
  for (const auto& [name, text] : {std::pair{"no_directive.yml", good.substr(good.find("---"))},
                                   std::pair{"keys_only.yml", body},
                                   std::pair{"comment_first.yml", "# my phone\n\n" + body}}) {
    SCOPED_TRACE(name);
    Diagnostics d;
    const auto c = readCameraModel(tempFile(name, text), d);
    ASSERT_TRUE(c) << d.format();
    EXPECT_EQ(c->width, 640);
    EXPECT_EQ(c->fy, 610.0);
    EXPECT_EQ(c->distortion[4], 0.01);
  }
  // The shape checks apply to it too, with the file's own line numbers.
  Diagnostics d;
  EXPECT_FALSE(readCameraModel(tempFile("keys_two_documents.yml", body + "---\nimage_width: 1\n"), d));
  EXPECT_NE(d.format().find("a second YAML document (line 13)"), std::string::npos) << d.format();
}

TEST(CameraModel, GlProjectionPutsPointsWherePinholeDoes) {
  CameraModel c{.width = 640, .height = 480, .fx = 600, .fy = 610, .cx = 300.25, .cy = 250.5};
  const glm::mat4 p = c.glProjection(0.1f, 100.0f);
  // A point in OpenGL camera space (looking along -Z, +Y up).
  for (const glm::dvec3 q : {glm::dvec3(0.1, 0.2, -1.5), glm::dvec3(-0.4, -0.1, -3.0), glm::dvec3(0, 0, -2)}) {
    const glm::vec4 clip = p * glm::vec4(glm::vec3(q), 1.0f);
    const double xNdc = clip.x / clip.w, yNdc = clip.y / clip.w;
    // Window pixel centres are at +0.5; image rows go down.
    const double u = (xNdc + 1) * 0.5 * c.width - 0.5, v = (1 - yNdc) * 0.5 * c.height - 0.5;
    // OpenCV pinhole: x right, y down, z forward.
    const double uCv = c.fx * q.x / -q.z + c.cx, vCv = c.fy * -q.y / -q.z + c.cy;
    EXPECT_NEAR(u, uCv, 1e-3);
    EXPECT_NEAR(v, vCv, 1e-3);
    EXPECT_GT(clip.z / clip.w, -1.0f);
    EXPECT_LT(clip.z / clip.w, 1.0f);
  }
  EXPECT_NEAR(c.fovYDegrees(), 2 * std::atan(240.0 / 610.0) * 180 / M_PI, 1e-9);
}

TEST(CameraModel, ScalingKeepsTheFieldOfView) {
  CameraModel c{.width = 1280, .height = 960, .fx = 1000, .fy = 1000, .cx = 639.5, .cy = 479.5};
  const CameraModel half = c.scaledTo(640, 480);
  EXPECT_DOUBLE_EQ(half.fx, 500);
  EXPECT_DOUBLE_EQ(half.cx, 319.5);
  EXPECT_DOUBLE_EQ(half.cy, 239.5);
  EXPECT_NEAR(half.fovYDegrees(), c.fovYDegrees(), 1e-9);
}

TEST(CameraModel, OpenCvPoseConversionFlipsYAndZ) {
  // An OpenCV camera 1 m above the origin looking straight down (+Z_cv = -Y world), image
  // down (+Y_cv) along +Z world: the target is seen unmirrored with image right = +X.
  const glm::dmat3 worldToCv(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));  // columns
  // rows of worldToCv: x_cv = X, y_cv = Z, z_cv = -Y; t so that the camera sits at (0, 1, 0).
  const glm::dvec3 t = -(worldToCv * glm::dvec3(0, 1, 0));
  const glm::dmat4 m = cameraToWorldFromOpenCv(worldToCv, t);
  EXPECT_NEAR(glm::length(glm::dvec3(m[3]) - glm::dvec3(0, 1, 0)), 0, 1e-12);
  EXPECT_NEAR(glm::length(glm::dvec3(m[2]) - glm::dvec3(0, 1, 0)), 0, 1e-12);   // GL +Z (back) = world up
  EXPECT_NEAR(glm::length(glm::dvec3(m[1]) - glm::dvec3(0, 0, -1)), 0, 1e-12);  // GL +Y (up) = image up = -Z
  EXPECT_NEAR(glm::length(glm::dvec3(m[0]) - glm::dvec3(1, 0, 0)), 0, 1e-12);
  EXPECT_NEAR(glm::determinant(glm::dmat3(m)), 1.0, 1e-12);
  EXPECT_EQ(trackingStateName(TrackingState::Limited), "LIMITED");
}

}  // namespace
