// libFuzzer target: camera calibrations (OpenCV FileStorage YAML, XML or JSON:
// marionette_ar/tracking/camera_model.hpp), read by readCameraModel from a temporary file.
// OpenCV's parser is not instrumented (a Debian library), so coverage comes from our field
// checks only; its crashes are still found. Contract: no crash; a refused file has an error
// and every diagnostic names the file; a camera that reads has no problem(), and
// writeCameraModel's copy of it reads back the same. With MARIONETTE_FUZZ_WRITE_SEED=folder
// the program writes small valid calibrations there (YAML as opencv-doc's
// left_intrinsics.yml, XML, JSON) and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include "fuzz_support.hpp"
#include "marionette_ar/tracking/camera_model.hpp"

using namespace marionette;
using fuzz::require;

namespace {

// Written here, not copied: the fields and layout of OpenCV's calibration samples.
constexpr const char* kSeeds[][2] = {
    {"calibration.yml", R"(%YAML:1.0
---
nframes: 13
image_width: 640
image_height: 480
board_width: 9
board_height: 6
square_size: 2.5e-02
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 6.0e+02, 0., 3.195e+02, 0.,
       6.1e+02, 2.395e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -2.0e-01, 5.0e-02,
       1.0e-03, -2.0e-03,
       1.0e-02 ]
avg_reprojection_error: 3.9e-01
)"},
    {"calibration.xml", R"(<?xml version="1.0"?>
<opencv_storage>
<image_width>320</image_width>
<image_height>240</image_height>
<camera_matrix type_id="opencv-matrix">
  <rows>3</rows>
  <cols>3</cols>
  <dt>f</dt>
  <data>
    300. 0. 159.5 0. 300. 119.5 0. 0. 1.</data></camera_matrix>
<distortion_coefficients type_id="opencv-matrix">
  <rows>1</rows>
  <cols>4</cols>
  <dt>f</dt>
  <data>
    -0.1 0.02 0. 0.</data></distortion_coefficients>
</opencv_storage>
)"},
    {"calibration.json", R"({
    "image_width": 1280,
    "image_height": 720,
    "camera_matrix": {
        "type_id": "opencv-matrix",
        "rows": 3,
        "cols": 3,
        "dt": "d",
        "data": [ 900.0, 0.0, 639.5, 0.0, 900.0, 359.5, 0.0, 0.0, 1.0 ]
    },
    "distortion_coefficients": {
        "type_id": "opencv-matrix",
        "rows": 8,
        "cols": 1,
        "dt": "d",
        "data": [ 0.1, -0.05, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0 ]
    }
}
)"},
};

bool same(const ar::CameraModel& a, const ar::CameraModel& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx &&
         a.cy == b.cy && a.distortion == b.distortion;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    bool ok = true;
    for (const auto& [name, text] : kSeeds) {  // each seed must read, or the corpus starts from nothing
      const std::string path = std::string(dir) + "/" + name;
      std::ofstream(path, std::ios::binary) << text;
      Diagnostics d;
      if (!ar::readCameraModel(path, d)) {
        std::fprintf(stderr, "the seed %s does not read:\n%s", path.c_str(), d.format().c_str());
        ok = false;
      }
    }
    std::exit(ok ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // ".yml": OpenCV picks the format from the text, and would gunzip a ".gz".
  const std::string path = fuzz::writeInput(data, size, "in.yml");
  Diagnostics d;
  const std::optional<ar::CameraModel> camera = ar::readCameraModel(path, d);
  if (!camera) {
    fuzz::requireNamedFailure(d, path);
    return 0;
  }
  require(fuzz::allName(d, path), "a diagnostic does not name the file");
  require(camera->problem().empty(), "a camera that reads has a problem()");
  const std::string copy = (fuzz::tempDir() / "copy.yml").string();
  std::string error;
  require(ar::writeCameraModel(copy, *camera, nullptr, error), "writeCameraModel failed on what readCameraModel read");
  Diagnostics back;
  const std::optional<ar::CameraModel> again = ar::readCameraModel(copy, back);
  require(again.has_value() && same(*camera, *again), "the camera does not round-trip");
  return 0;
}
