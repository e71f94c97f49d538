// libFuzzer target: AR scene files (the reference renderer's JSON around a middleware
// scene: camera, background, environment, PRT, render size), read by readArScene from
// a temporary file. Contract: no crash; a failed read has an error and every
// diagnostic names the file; a scene that reads has finite camera numbers, a positive
// size and frame rate, and PRT settings inside their documented ranges. Built by scripts/fuzz.
#include <cmath>

#include "../../examples/ar/app/ar_scene_file.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace marionette;
using fuzz::require;

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeInput(data, size, "in.ar.json");
  ar::ArScene scene;
  const Diagnostics d = readArScene(path, scene);
  require(fuzz::allName(d, path), "a diagnostic does not name the file");
  if (!d.ok()) return 0;
  const ar::ArCamera& c = scene.camera;
  require(finite3(c.position) && finite3(c.target) && finite3(c.up), "a camera vector is not finite");
  require(std::isfinite(c.fovYDegrees) && c.fovYDegrees > 0.0f && c.fovYDegrees < 180.0f, "fovY out of range");
  require(std::isfinite(c.nearPlane) && std::isfinite(c.farPlane) && c.nearPlane > 0.0f && c.farPlane > c.nearPlane,
          "near/far out of range");
  require(scene.width > 0 && scene.height > 0 && std::isfinite(scene.fps) && scene.fps > 0.0, "render size or fps");
  require(std::isfinite(scene.background.fps) && scene.background.fps > 0.0, "background fps");
  require(finite3(scene.background.color), "background colour");
  const ar::ArBackground& b = scene.background;
  require(std::isfinite(b.timeoutSeconds) && b.timeoutSeconds > 0 && b.deviceIndex >= -1 && b.captureWidth >= 0 &&
              b.captureHeight >= 0, "camera background settings");
  require(std::isfinite(c.replay.holdSeconds) && c.replay.holdSeconds >= 0, "replay hold time");
  require(c.replay.poses.empty() || c.tracker.kind == ar::ArTracker::Kind::None, "a tracker and poses at once");
  const ar::ArEnvironment& e = scene.environment;
  require(std::isfinite(e.rotationDegrees) && std::isfinite(e.exposure), "environment numbers");
  require(e.prt.bands >= 2 && e.prt.bands <= 8 && e.prt.rays >= 1 && e.prt.rays <= 65536, "PRT settings");
  require(std::isfinite(e.prt.poseTime), "PRT pose time");
  return 0;
}
