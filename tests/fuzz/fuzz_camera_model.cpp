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
#include "tracking_seeds.hpp"

using namespace marionette;
using fuzz::require;

namespace {


bool same(const ar::CameraModel& a, const ar::CameraModel& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx &&
         a.cy == b.cy && a.distortion == b.distortion;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    bool ok = true;
    for (const auto& [name, text] : fuzz::kSeedCalibrations) {  // each seed must read, or the corpus starts from nothing
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
  Diagnostics error;
  require(ar::writeCameraModel(copy, *camera, nullptr, error), "writeCameraModel failed on what readCameraModel read");
  Diagnostics back;
  const std::optional<ar::CameraModel> again = ar::readCameraModel(copy, back);
  require(again.has_value() && same(*camera, *again), "the camera does not round-trip");
  return 0;
}
