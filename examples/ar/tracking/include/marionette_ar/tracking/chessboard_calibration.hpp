// Camera calibration from photos of a chessboard (Zhang's method through OpenCV's
// calibrateCamera), as `marionette-ar calibrate` runs it.
//
// Settings follow OpenCV's calibration sample that made opencv-doc's left_intrinsics.yml
// (square pixels: the aspect ratio fixed at 1; k1 k2 p1 p2 k3), so the two can be
// compared: on opencv-doc's left01..14.jpg the rms reprojection error comes within 10 % of
// that file's 0.393 px (tests/ar/tracking/chessboard_calibration_test.cpp).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar {

struct ChessboardOptions {
  int columns = 9, rows = 6;  // inner corners along a row and along a column
  double squareSize = 0.025;  // metres
  bool fixAspectRatio = true;  // fx = fy
};

struct ChessboardCalibration {
  CameraModel camera;
  double rmsReprojectionError = 0;        // pixels, over every corner of every used view
  std::vector<std::string> usedImages;     // in the order given
  std::vector<double> perViewRms;          // pixels, one per used image
  std::vector<std::string> rejectedImages;  // the board was not found (a warning names each)
};

// Errors (nothing returned) name the image or the setting: an unreadable image, images with
// the board of different sizes, fewer than 3 views where the whole board was found, a board
// below 2x2 inner corners or a square size that is not positive and finite. Images where the
// board is not found are skipped with a warning, whatever their size: the calibration's size
// is the first image's where the board is found.
[[nodiscard]] std::optional<ChessboardCalibration> calibrateChessboard(const std::vector<std::string>& images,
                                                                       const ChessboardOptions& settings,
                                                                       Diagnostics& diagnostics);

}  // namespace marionette::ar
