// A tracker's view of the camera frame: grey, and undistorted to the camera's pinhole (same
// K) when the camera has lens distortion, so that everything downstream is a pinhole. The
// buffers are sized by the first frame and reused.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/image_view.hpp"

namespace marionette::ar {

class GreyFrame {
 public:
  void configure(const CameraModel& camera) {
    camera_ = camera;
    distorted_ = camera.hasDistortion();
    if (!distorted_) return;
    const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const cv::Mat d(1, 5, CV_64F, const_cast<double*>(camera.distortion.data()));
    cv::Mat mapX, mapY;
    cv::initUndistortRectifyMap(k, d, cv::noArray(), k, cv::Size(camera.width, camera.height), CV_32FC1, mapX, mapY);
    // Per pinhole pixel: the distorted pixel's top-left tap and bilinear weights in 1/32 (as
    // OpenCV's fixed-point remap); taps outside the image read 0. cv::remap allocates per call.
    taps_.resize(static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height));
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const float sx = mapX.at<float>(y, x), sy = mapY.at<float>(y, x);
        Tap& t = taps_[static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(x)];
        const int fx32 = static_cast<int>(std::lround(sx * 32)), fy32 = static_cast<int>(std::lround(sy * 32));
        t.x = fx32 >> 5;
        t.y = fy32 >> 5;
        t.ax = static_cast<std::uint8_t>(fx32 & 31);
        t.ay = static_cast<std::uint8_t>(fy32 & 31);
        t.inside = std::isfinite(sx) && std::isfinite(sy) && t.x >= 0 && t.y >= 0 && t.x + 1 < camera.width &&
                   t.y + 1 < camera.height;
      }
    pinhole_.create(camera.height, camera.width, CV_8UC1);
  }

  // False (and nothing changed) for an invalid view or one of another size than the camera's.
  // Allocates nothing after the first frame.
  bool load(const ImageView& v) {
    if (!v.valid() || v.width != camera_.width || v.height != camera_.height) return false;
    const int type = v.channels == 1 ? CV_8UC1 : v.channels == 3 ? CV_8UC3 : CV_8UC4;
    const cv::Mat in(v.height, v.width, type, const_cast<std::uint8_t*>(v.pixels), static_cast<std::size_t>(v.rowBytes()));
    if (v.channels == 1) in.copyTo(grey_);
    else cv::cvtColor(in, grey_, v.channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
    if (distorted_) undistort();
    return true;
  }
  [[nodiscard]] const cv::Mat& pinhole() const noexcept { return distorted_ ? pinhole_ : grey_; }
  // The last frame in grey as it came (not undistorted): the occlusion mask's input.
  [[nodiscard]] const cv::Mat& raw() const noexcept { return grey_; }

 private:
  struct Tap {
    int x = 0, y = 0;
    std::uint8_t ax = 0, ay = 0;
    bool inside = false;
  };

  void undistort() noexcept {
    const std::size_t w = static_cast<std::size_t>(camera_.width);
    for (int y = 0; y < camera_.height; ++y) {
      std::uint8_t* out = pinhole_.ptr<std::uint8_t>(y);
      const Tap* row = taps_.data() + static_cast<std::size_t>(y) * w;
      for (std::size_t x = 0; x < w; ++x) {
        const Tap& t = row[x];
        if (!t.inside) {
          out[x] = 0;
          continue;
        }
        const std::uint8_t* p0 = grey_.ptr<std::uint8_t>(t.y) + t.x;
        const std::uint8_t* p1 = p0 + grey_.step[0];
        const int top = p0[0] * (32 - t.ax) + p0[1] * t.ax, bottom = p1[0] * (32 - t.ax) + p1[1] * t.ax;
        out[x] = static_cast<std::uint8_t>((top * (32 - t.ay) + bottom * t.ay + 512) >> 10);
      }
    }
  }

  CameraModel camera_;
  bool distorted_ = false;
  std::vector<Tap> taps_;
  cv::Mat grey_, pinhole_;
};

}  // namespace marionette::ar
