// marionette_write_sequence: one standard scenario (or the AR authoring demo's authoring_sweep),
// or one stress sequence (stress_scenarios.hpp), rendered to PNG frames with its exact
// trajectory, for looking at the frames and for running other tools on them.
//
//   marionette_write_sequence --target IMAGE --target-width M --camera CAMERA.yml
//       (--scenario NAME | --stress CLASS [--seed N]) [--frames N] [--floor IMAGE [--floor-mpp M]] --out DIR
//
// Writes DIR/frame_0000.png ... (RGB) and DIR/truth.csv:
//   frame,time,state,px,py,pz,qx,qy,qz,qw
// state TRACKING when the target is in view, else LOST; camera-to-world position (metres)
// and rotation quaternion (camera axes as OpenGL's); for a stress sequence the pose at the
// exposure's middle. A stress sequence also writes DIR/stress.csv, a frame's facts:
//   frame,visible,sub_frames,image_motion_px,blur_px,angular_speed_deg,gain_ev,gain_r,gain_g,gain_b,defocus_px,hands_cover
// --seed defaults to 1, --frames to the class's length (60 or 45). Exit 0 on success, 1 on an
// error, 2 on bad arguments (an unknown scenario or class lists the known ones).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/tracking/camera_model.hpp"
#include "tracking/scenarios.hpp"
#include "tracking/stress_scenarios.hpp"
#include "tracking/synthetic_sequence.hpp"

namespace {

using namespace marionette::ar;

int usage(const char* why) {
  std::fprintf(stderr,
               "marionette_write_sequence: %s\n"
               "usage: marionette_write_sequence --target IMAGE --target-width M --camera CAMERA.yml\n"
               "         (--scenario NAME | --stress CLASS [--seed N]) [--frames N] [--floor IMAGE [--floor-mpp M]]\n"
               "         --out DIR\n"
               "e.g.   marionette_write_sequence --target /usr/share/doc/opencv-doc/examples/data/graf1.png\n"
               "         --target-width 0.3 --camera assets/cameras/synthetic_640x480.yml --scenario orbit\n"
               "         --frames 30 --out /tmp/orbit\n",
               why);
  return 2;
}

bool readRgb(const std::string& path, cv::Mat& rgb) {
  const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty()) return false;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string target, camera, scenario, out, floor, stress;
  double width = 0, floorMpp = 0.002;
  int frames = 0;
  unsigned long long seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage(("missing value after " + a).c_str());
    const std::string v = argv[++i];
    char* end = nullptr;
    if (a == "--target") target = v;
    else if (a == "--camera") camera = v;
    else if (a == "--scenario") scenario = v;
    else if (a == "--stress") stress = v;
    else if (a == "--seed") {
      seed = std::strtoull(v.c_str(), &end, 10);
      if (*end != '\0' || v.empty() || v[0] == '-') return usage("--seed needs a whole number >= 0");
    }
    else if (a == "--out") out = v;
    else if (a == "--floor") floor = v;
    else if (a == "--target-width" || a == "--floor-mpp") {
      const double d = std::strtod(v.c_str(), &end);
      if (*end != '\0' || !(d > 0)) return usage((a + " needs a positive number of metres").c_str());
      (a == "--target-width" ? width : floorMpp) = d;
    } else if (a == "--frames") {
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end != '\0' || n < 2 || n > 100000) return usage("--frames needs a whole number in 2..100000");
      frames = static_cast<int>(n);
    } else {
      return usage(("unknown option " + a).c_str());
    }
  }
  if (target.empty() || camera.empty() || scenario.empty() == stress.empty() || out.empty() || width <= 0)
    return usage("--target, --target-width, --camera, --out and one of --scenario and --stress are required");

  const std::optional<synthetic::StressClass> stressClass = synthetic::stressClassNamed(stress);
  if (!stress.empty() && !stressClass) {
    std::fprintf(stderr, "marionette_write_sequence: unknown stress class '%s'; known:", stress.c_str());
    for (const synthetic::StressClass k : synthetic::kStressClasses)
      std::fprintf(stderr, " %s", std::string(synthetic::stressClassName(k)).c_str());
    std::fprintf(stderr, "\n");
    return 2;
  }
  if (stressClass && frames == 0) frames = synthetic::defaultStressFrames(*stressClass);
  if (stressClass && frames < 30) return usage("a stress sequence needs --frames 30 or more");
  if (frames == 0) frames = 150;
  auto names = synthetic::standardScenarioNames();
  names.push_back("authoring_sweep");  // the AR authoring demo's (docs/authoring.md)
  if (!stressClass && std::find(names.begin(), names.end(), scenario) == names.end()) {
    std::fprintf(stderr, "marionette_write_sequence: unknown scenario '%s'; known:", scenario.c_str());
    for (const std::string& n : names) std::fprintf(stderr, " %s", n.c_str());
    std::fprintf(stderr, "\n");
    return 2;
  }

  marionette::Diagnostics diagnostics;
  const std::optional<CameraModel> model = readCameraModel(camera, diagnostics);
  if (!model) {
    std::fprintf(stderr, "%s\n", diagnostics.format().c_str());
    return 1;
  }
  synthetic::PlanarScene scene;
  scene.targetWidth = width;
  scene.floorMetresPerPixel = floorMpp;
  if (!readRgb(target, scene.target)) {
    std::fprintf(stderr, "marionette_write_sequence: %s: cannot read the target image\n", target.c_str());
    return 1;
  }
  if (!floor.empty() && !readRgb(floor, scene.floor)) {
    std::fprintf(stderr, "marionette_write_sequence: %s: cannot read the floor image\n", floor.c_str());
    return 1;
  }
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "marionette_write_sequence: %s: cannot create: %s\n", out.c_str(), ec.message().c_str());
    return 1;
  }

  const synthetic::SequenceRenderer renderer(scene, *model);
  // Only the wanted scenario's poses matter; building all of them costs a few milliseconds.
  synthetic::Scenario chosen;
  std::optional<synthetic::StressSequence> stressed;
  if (stressClass) {
    stressed = synthetic::stressSequence(renderer, *stressClass, seed, frames);
    chosen = stressed->scenario;
    scenario = chosen.name;
  } else if (scenario == "authoring_sweep") {
    chosen = synthetic::authoringSweep(renderer, frames);
  }
  for (synthetic::Scenario& s : chosen.cameraToWorld.empty() ? synthetic::standardScenarios(renderer, frames)
                                                             : std::vector<synthetic::Scenario>{})
    if (s.name == scenario) chosen = std::move(s);

  const std::string csvPath = out + "/truth.csv";
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "marionette_write_sequence: %s: cannot be written\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "frame,time,state,px,py,pz,qx,qy,qz,qw\n");
  std::FILE* facts = nullptr;
  if (stressed) {
    const std::string factsPath = out + "/stress.csv";
    facts = std::fopen(factsPath.c_str(), "w");
    if (!facts) {
      std::fprintf(stderr, "marionette_write_sequence: %s: cannot be written\n", factsPath.c_str());
      std::fclose(csv);
      return 1;
    }
    std::fprintf(facts, "frame,visible,sub_frames,image_motion_px,blur_px,angular_speed_deg,gain_ev,gain_r,gain_g,gain_b,"
                        "defocus_px,hands_cover\n");
  }
  cv::Mat rgb, bgr;
  int visible = 0;
  for (std::size_t i = 0; i < chosen.cameraToWorld.size(); ++i) {
    const glm::dmat4& m = chosen.cameraToWorld[i];
    if (stressed) {
      synthetic::renderStressFrame(renderer, *stressed, static_cast<int>(i), rgb);
      const synthetic::StressFrame& f = stressed->frames[i];
      const synthetic::FrameEffects& fx = chosen.effects[i];
      std::fprintf(facts, "%zu,%.4f,%zu,%.2f,%.2f,%.2f,%.3f,%.4f,%.4f,%.4f,%.3f,%.4f\n", i, chosen.visibleFraction[i],
                   f.subFrames.size(), f.imageMotionPx, f.blurPx, f.angularSpeedDeg, fx.gainEv, fx.channelGain[0],
                   fx.channelGain[1], fx.channelGain[2], fx.defocusPx, f.handsCover);
    } else {
      renderer.render(m, chosen.effects[i], rgb);
    }
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%04zu.png", i);
    if (!cv::imwrite(out + name, bgr)) {
      std::fprintf(stderr, "marionette_write_sequence: %s%s: cannot be written\n", out.c_str(), name);
      std::fclose(csv);
      if (facts) std::fclose(facts);
      return 1;
    }
    const glm::dquat q = glm::quat_cast(glm::dmat3(m));
    const bool seen = chosen.visibleFraction[i] > 0;
    visible += seen;
    std::fprintf(csv, "%zu,%.9g,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", i, static_cast<double>(i) / chosen.fps, seen ? "TRACKING" : "LOST",
                 m[3].x + 0.0, m[3].y + 0.0, m[3].z + 0.0, q.x + 0.0, q.y + 0.0, q.z + 0.0, q.w + 0.0);  // no "-0"
  }
  if (facts && std::fclose(facts) != 0) {
    std::fprintf(stderr, "marionette_write_sequence: %s/stress.csv: write failed\n", out.c_str());
    std::fclose(csv);
    return 1;
  }
  if (std::fclose(csv) != 0) {
    std::fprintf(stderr, "marionette_write_sequence: %s: write failed\n", csvPath.c_str());
    return 1;
  }
  std::printf("%s (%s): %zu frames, %d with the target in view, in %s\n", scenario.c_str(),
              chosen.description.c_str(), chosen.cameraToWorld.size(), visible, out.c_str());
  return 0;
}
