#include "marionette_ar/tracking/chessboard_calibration.hpp"

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace marionette::ar {

std::optional<ChessboardCalibration> calibrateChessboard(const std::vector<std::string>& images,
                                                         const ChessboardOptions& settings,
                                                         Diagnostics& diagnostics) {
  if (settings.columns < 2 || settings.rows < 2 || settings.columns > 1000 || settings.rows > 1000) {
    diagnostics.error("--board", "a board of " + std::to_string(settings.columns) + "x" +
                                     std::to_string(settings.rows) + " inner corners: need 2..1000 each way");
    return std::nullopt;
  }
  if (!std::isfinite(settings.squareSize) || !(settings.squareSize > 0)) {
    diagnostics.error("--square", "square size must be a positive number of metres");
    return std::nullopt;
  }
  const cv::Size board(settings.columns, settings.rows);
  std::vector<cv::Point3f> boardPoints;
  for (int r = 0; r < settings.rows; ++r)
    for (int c = 0; c < settings.columns; ++c)
      boardPoints.emplace_back(static_cast<float>(c * settings.squareSize), static_cast<float>(r * settings.squareSize), 0.f);

  ChessboardCalibration out;
  std::vector<std::vector<cv::Point2f>> imagePoints;
  cv::Size size;
  try {
    for (const std::string& file : images) {
      const cv::Mat grey = cv::imread(file, cv::IMREAD_GRAYSCALE);
      if (grey.empty()) {
        diagnostics.error(file, "cannot be read as an image");
        return std::nullopt;
      }
      std::vector<cv::Point2f> corners;
      const bool found = cv::findChessboardCorners(
          grey, board, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
      if (!found) {
        diagnostics.warning(file, "no " + std::to_string(settings.columns) + "x" + std::to_string(settings.rows) +
                                      " chessboard found: image skipped");
        out.rejectedImages.push_back(file);
        continue;
      }
      // The size is the first used image's: a skipped one may be another camera's (opencv-doc's
      // left.jpg, 612x459, which `left*.jpg` takes first).
      if (size.area() == 0) size = grey.size();
      else if (grey.size() != size) {
        diagnostics.error(file, "is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                                    " but the first image with the board (" + out.usedImages.front() + ") is " +
                                    std::to_string(size.width) + "x" + std::to_string(size.height) +
                                    ": one camera, one size");
        return std::nullopt;
      }
      // The sample's 11x11 window: corners to a tenth of a pixel.
      cv::cornerSubPix(grey, corners, cv::Size(11, 11), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
      imagePoints.push_back(std::move(corners));
      out.usedImages.push_back(file);
    }
    if (imagePoints.size() < 3) {
      diagnostics.error(images.empty() ? std::string("calibrate") : images.front(),
                        "the board was found in " + std::to_string(imagePoints.size()) +
                            " images; calibration needs at least 3 views");
      return std::nullopt;
    }
    const std::vector<std::vector<cv::Point3f>> objectPoints(imagePoints.size(), boardPoints);
    cv::Mat k = cv::Mat::eye(3, 3, CV_64F), d = cv::Mat::zeros(5, 1, CV_64F);
    std::vector<cv::Mat> rvecs, tvecs;
    const int flags = settings.fixAspectRatio ? cv::CALIB_FIX_ASPECT_RATIO : 0;
    out.rmsReprojectionError = cv::calibrateCamera(objectPoints, imagePoints, size, k, d, rvecs, tvecs, flags);
    for (std::size_t v = 0; v < imagePoints.size(); ++v) {
      std::vector<cv::Point2f> projected;
      cv::projectPoints(objectPoints[v], rvecs[v], tvecs[v], k, d, projected);
      const double err = cv::norm(imagePoints[v], projected, cv::NORM_L2);
      out.perViewRms.push_back(std::sqrt(err * err / static_cast<double>(projected.size())));
    }
    CameraModel& c = out.camera;
    c.width = size.width;
    c.height = size.height;
    c.fx = k.at<double>(0, 0);
    c.fy = k.at<double>(1, 1);
    c.cx = k.at<double>(0, 2);
    c.cy = k.at<double>(1, 2);
    for (int i = 0; i < 5; ++i) c.distortion[static_cast<std::size_t>(i)] = d.at<double>(i);
  } catch (const cv::Exception& e) {
    diagnostics.error(images.empty() ? std::string("calibrate") : images.front(),
                      std::string("OpenCV failed: ") + e.what());
    return std::nullopt;
  }
  if (const std::string p = out.camera.problem(); !p.empty()) {
    diagnostics.error(images.front(), "the calibration did not converge to a usable camera: " + p);
    return std::nullopt;
  }
  return out;
}

}  // namespace marionette::ar
