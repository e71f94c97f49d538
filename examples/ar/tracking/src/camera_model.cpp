#include "marionette_ar/tracking/camera_model.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>

#include "marionette/core/limits.hpp"

namespace marionette::ar {

namespace {

constexpr int kMaxCameraSide = 65536;

bool finite(double v) { return std::isfinite(v); }

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::string CameraModel::problem() const {
  if (width < 1 || height < 1 || width > kMaxCameraSide || height > kMaxCameraSide)
    return "image size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1x1 .. 65536x65536";
  for (double v : {fx, fy, cx, cy})
    if (!finite(v)) return "camera matrix has a NaN or infinite value";
  for (double v : distortion)
    if (!finite(v)) return "distortion coefficients have a NaN or infinite value";
  if (!(fx > 0) || !(fy > 0)) return "focal length (fx " + num(fx) + ", fy " + num(fy) + ") is not positive";
  if (cx < 0 || cy < 0 || cx > width || cy > height)
    return "principal point (" + num(cx) + ", " + num(cy) + ") is outside the " + std::to_string(width) + "x" +
           std::to_string(height) + " image";
  for (double v : distortion)
    if (std::abs(v) > 100) return "distortion coefficient " + num(v) + " is beyond +-100";
  return {};
}

bool CameraModel::hasDistortion() const noexcept {
  for (double v : distortion)
    if (v != 0.0) return true;
  return false;
}

double CameraModel::fovYDegrees() const noexcept {
  return 2.0 * std::atan2(0.5 * height, fy) * 180.0 / 3.14159265358979323846;
}

glm::mat4 CameraModel::glProjection(float nearZ, float farZ) const noexcept {
  // x_ndc = (2 (fx X/Z' + cx) / w - 1) with Z' = -Z; y flips because pixel rows go down.
  glm::mat4 p(0.0f);
  p[0][0] = static_cast<float>(2.0 * fx / width);
  p[1][1] = static_cast<float>(2.0 * fy / height);
  p[2][0] = static_cast<float>(1.0 - 2.0 * (cx + 0.5) / width);
  p[2][1] = static_cast<float>(2.0 * (cy + 0.5) / height - 1.0);
  p[2][2] = -(farZ + nearZ) / (farZ - nearZ);
  p[2][3] = -1.0f;
  p[3][2] = -2.0f * farZ * nearZ / (farZ - nearZ);
  return p;
}

CameraModel CameraModel::scaledTo(int newWidth, int newHeight) const noexcept {
  CameraModel c = *this;
  const double sx = static_cast<double>(newWidth) / width, sy = static_cast<double>(newHeight) / height;
  c.width = newWidth;
  c.height = newHeight;
  // Pixel centres at integers: scale about the image corner (-0.5, -0.5).
  c.fx = fx * sx;
  c.fy = fy * sy;
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  return c;
}

std::optional<CameraModel> readCameraModel(const std::string& file, Diagnostics& diagnostics) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    diagnostics.error(file, "camera file does not exist or is not a file");
    return std::nullopt;
  }
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size > (1u << 20)) {
    diagnostics.error(file, "camera file is larger than 1 MiB: not a calibration");
    return std::nullopt;
  }
  CameraModel c;
  try {
    cv::FileStorage fs(file, cv::FileStorage::READ | cv::FileStorage::FORMAT_AUTO);
    if (!fs.isOpened()) {
      diagnostics.error(file, "OpenCV cannot read it as calibration YAML or XML");
      return std::nullopt;
    }
    auto integer = [&](const char* key, int& out) {
      const cv::FileNode n = fs[key];
      if (n.empty() || !(n.isInt() || n.isReal())) {
        diagnostics.error(file, std::string("'") + key + "' is missing or not a number");
        return false;
      }
      const double v = n.real();
      if (!(v >= 1 && v <= kMaxCameraSide) || v != std::floor(v)) {
        diagnostics.error(file, std::string("'") + key + "' " + num(v) + " is not a whole number in 1..65536");
        return false;
      }
      out = static_cast<int>(v);
      return true;
    };
    if (!integer("image_width", c.width) || !integer("image_height", c.height)) return std::nullopt;
    cv::Mat k, d;
    const cv::FileNode kn = fs["camera_matrix"], dn = fs["distortion_coefficients"];
    if (kn.empty() || !kn.isMap()) {
      diagnostics.error(file, "'camera_matrix' is missing or not an !!opencv-matrix");
      return std::nullopt;
    }
    kn >> k;
    if (k.rows != 3 || k.cols != 3 || k.channels() != 1) {
      diagnostics.error(file, "'camera_matrix' is " + std::to_string(k.rows) + "x" + std::to_string(k.cols) +
                                  ", not 3x3");
      return std::nullopt;
    }
    k.convertTo(k, CV_64F);
    if (k.at<double>(0, 1) != 0 || k.at<double>(1, 0) != 0 || k.at<double>(2, 0) != 0 || k.at<double>(2, 1) != 0 ||
        k.at<double>(2, 2) != 1) {
      diagnostics.error(file, "'camera_matrix' is not [fx 0 cx; 0 fy cy; 0 0 1] (skew or a last row other than 0 0 1)");
      return std::nullopt;
    }
    c.fx = k.at<double>(0, 0);
    c.fy = k.at<double>(1, 1);
    c.cx = k.at<double>(0, 2);
    c.cy = k.at<double>(1, 2);
    if (!dn.empty()) {
      if (!dn.isMap()) {
        diagnostics.error(file, "'distortion_coefficients' is not an !!opencv-matrix");
        return std::nullopt;
      }
      dn >> d;
      const int n = static_cast<int>(d.total());
      if (d.channels() != 1 || (d.rows != 1 && d.cols != 1) || !(n == 4 || n == 5 || n == 8 || n == 12 || n == 14)) {
        diagnostics.error(file, "'distortion_coefficients' has " + std::to_string(n) +
                                    " values; OpenCV's models have 4, 5, 8, 12 or 14");
        return std::nullopt;
      }
      d.convertTo(d, CV_64F);
      for (int i = 0; i < n; ++i) {
        const double v = d.at<double>(i);
        if (i < 5) c.distortion[static_cast<std::size_t>(i)] = v;
        else if (v != 0.0) {
          diagnostics.error(file, "'distortion_coefficients' value " + std::to_string(i + 1) + " is " + num(v) +
                                      ": only k1 k2 p1 p2 k3 are supported (the rational and prism terms must be 0)");
          return std::nullopt;
        }
      }
    }
  } catch (const cv::Exception& e) {
    diagnostics.error(file, std::string("OpenCV cannot parse it: ") + e.what());
    return std::nullopt;
  }
  if (const std::string p = c.problem(); !p.empty()) {
    diagnostics.error(file, p);
    return std::nullopt;
  }
  return c;
}

bool writeCameraModel(const std::string& file, const CameraModel& camera, const CalibrationFacts* facts,
                      std::string& error) {
  if (const std::string p = camera.problem(); !p.empty()) {
    error = file + ": not written: " + p;
    return false;
  }
  try {
    cv::FileStorage fs(file, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) {
      error = file + ": cannot be written";
      return false;
    }
    if (facts) fs << "nframes" << facts->views;
    fs << "image_width" << camera.width << "image_height" << camera.height;
    if (facts) {
      fs << "board_width" << facts->boardColumns << "board_height" << facts->boardRows;
      fs << "square_size" << facts->squareSize;
    }
    const cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    cv::Mat d(5, 1, CV_64F);
    for (int i = 0; i < 5; ++i) d.at<double>(i) = camera.distortion[static_cast<std::size_t>(i)];
    fs << "camera_matrix" << k << "distortion_coefficients" << d;
    if (facts && facts->rmsReprojectionError >= 0) fs << "avg_reprojection_error" << facts->rmsReprojectionError;
    fs.release();
  } catch (const cv::Exception& e) {
    error = file + ": cannot be written: " + e.what();
    return false;
  }
  return true;
}

}  // namespace marionette::ar
