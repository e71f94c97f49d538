// ViSP's AprilTag benchmark image (Debian visp-images-data) and the camera and tag settings it
// was rendered with, shared by the tracker's tests, benchmarks and allocation count.
#pragma once
#include <string>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "test_data.hpp"

namespace marionette::ar::synthetic {

inline std::string vispBenchmarkImage() {
  return test::vispImage("AprilTag/benchmark/640x480/tag36_11_640x480.png");
}
// fx = fy = 700; the principal point in OpenCV's pixel convention (ViSP's 320, 240 is
// libapriltag's, whose pixel centres sit at +0.5).
inline CameraModel vispBenchmarkCamera() {
  return {.width = 640, .height = 480, .fx = 700, .fy = 700, .cx = 319.5, .cy = 239.5};
}
// Tags 0..2 are 0.25 m including the white margin: 0.2 m black squares.
inline AprilTagSettings vispBenchmarkTagSettings() {
  AprilTagSettings settings;
  settings.tagSize = 0.2;
  settings.decimate = 2.0f;
  return settings;
}

}  // namespace marionette::ar::synthetic
