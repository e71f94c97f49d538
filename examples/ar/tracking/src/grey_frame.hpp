// A tracker's view of the camera frame: grey, and undistorted to the camera's pinhole (same
// K) when the camera has lens distortion, so that everything downstream is a pinhole. The
// buffers are sized by the first frame and reused.
#pragma once
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
    cv::initUndistortRectifyMap(k, d, cv::noArray(), k, cv::Size(camera.width, camera.height), CV_16SC2, map1_, map2_);
  }

  // False (and nothing changed) for an invalid view or one of another size than the camera's.
  bool load(const ImageView& v) {
    if (!v.valid() || v.width != camera_.width || v.height != camera_.height) return false;
    const int type = v.channels == 1 ? CV_8UC1 : v.channels == 3 ? CV_8UC3 : CV_8UC4;
    const cv::Mat in(v.height, v.width, type, const_cast<std::uint8_t*>(v.pixels), static_cast<std::size_t>(v.rowBytes()));
    if (v.channels == 1) in.copyTo(grey_);
    else cv::cvtColor(in, grey_, v.channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
    if (distorted_) cv::remap(grey_, pinhole_, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    return true;
  }
  [[nodiscard]] const cv::Mat& pinhole() const noexcept { return distorted_ ? pinhole_ : grey_; }

 private:
  CameraModel camera_;
  bool distorted_ = false;
  cv::Mat map1_, map2_, grey_, pinhole_;
};

}  // namespace marionette::ar
