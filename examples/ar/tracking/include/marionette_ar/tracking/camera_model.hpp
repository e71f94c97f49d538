// A pinhole camera with OpenCV's radial-tangential distortion (k1, k2, p1, p2, k3), read
// from and written to OpenCV's calibration YAML: `image_width`, `image_height`,
// `camera_matrix` (3x3) and `distortion_coefficients` (4, 5, 8, 12 or 14 values; the
// first five are kept and the rest must be zero), as opencv-doc's
// examples/data/left_intrinsics.yml and `marionette-ar calibrate` write them.
//
// Pixel convention: OpenCV's (x right, y down, the centre of the top-left pixel at 0, 0).
#pragma once
#include <array>
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar {

struct CameraModel {
  int width = 0, height = 0;          // the image size the intrinsics are for, pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  // focal lengths and principal point, pixels
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3

  // What is wrong, empty when usable: a size below 1x1 or above 65536, a NaN or infinite
  // number, a focal length <= 0, a principal point outside the image, |k| > 100.
  [[nodiscard]] std::string problem() const;
  [[nodiscard]] bool hasDistortion() const noexcept;
  // The vertical field of view of the undistorted pinhole, degrees.
  [[nodiscard]] double fovYDegrees() const noexcept;
  // An OpenGL projection (camera looking along -Z, +Y up, clip z in [-1, 1]) that puts a
  // point where this camera's pinhole puts it, principal point included, for a viewport of
  // width x height pixels (the image scaled to it).
  [[nodiscard]] glm::mat4 glProjection(float nearZ, float farZ) const noexcept;
  // The same camera for frames scaled to another size (e.g. a calibration at 1280x960 used
  // at 640x480).
  [[nodiscard]] CameraModel scaledTo(int newWidth, int newHeight) const noexcept;
};

// Reads `file`. Errors name the file and the field: not YAML/XML OpenCV can read, a
// missing or malformed field (a word among a matrix's numbers by its place), values
// problem() refuses. YAML keys without the "%YAML:1.0" header are read as YAML 1.0.
[[nodiscard]] std::optional<CameraModel> readCameraModel(const std::string& file, Diagnostics& diagnostics);

// Extra facts `marionette-ar calibrate` records beside the model.
struct CalibrationFacts {
  int views = 0;
  int boardColumns = 0, boardRows = 0;  // inner corners
  double squareSize = 0;                // metres
  double rmsReprojectionError = -1;     // pixels; < 0: not written
};

// Writes `camera` (and `facts` when given) as OpenCV calibration YAML. False with an error in
// `diagnostics` naming the file when it cannot be written or the model has a problem().
[[nodiscard]] bool writeCameraModel(const std::string& file, const CameraModel& camera, const CalibrationFacts* facts,
                                    Diagnostics& diagnostics);

}  // namespace marionette::ar
