#include "tracking_commands.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "ar_cli.hpp"
#include "marionette_ar/background_source.hpp"
#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "marionette_ar/tracking/chessboard_calibration.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"

namespace marionette::ar {

namespace {

int fail(const char* command, const std::string& message) {
  std::fprintf(stderr, "marionette-ar %s: %s\n", command, message.c_str());
  return 2;
}

bool parseNumber(const char* text, double lo, double hi, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == 0 && out >= lo && out <= hi;
}

int calibrateUsage(std::FILE* to = stderr) {
  std::fprintf(to,
               "usage: marionette-ar calibrate [--board COLSxROWS] [--square M] IMAGES... -o CAMERA.yml [--json]\n"
               "  IMAGES     photos of the chessboard; those where it is not found are skipped\n"
               "  --board    inner corners of the chessboard (default 9x6)\n"
               "  --square   the squares' side in metres (default 0.025)\n"
               "  -o, --out  the calibration to write (OpenCV calibration YAML)\n"
               "  --json     print the result as JSON\n"
               "  --help, -h this help; --version: the version\n"
               "  Writes OpenCV calibration YAML and prints the rms reprojection error.\n");
  return usageExitCode(to);
}

int calibrate(int argc, char** argv) {
  ChessboardOptions s;
  std::vector<std::string> images;
  std::string out;
  bool json = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (isHelpFlag(a)) return calibrateUsage(stdout);
    if (a == "--version") return printVersion();
    if (a == "--board" && hasValue) {
      if (std::sscanf(argv[++i], "%dx%d", &s.columns, &s.rows) != 2) return fail("calibrate", "--board needs COLSxROWS");
    } else if (a == "--square" && hasValue) {
      if (!parseNumber(argv[++i], 1e-6, 100, s.squareSize))
        return fail("calibrate", "--square needs metres in (0, 100]");
    } else if ((a == "-o" || a == "--out") && hasValue) {
      out = argv[++i];
    } else if (a == "--json") {
      json = true;
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "marionette-ar calibrate: unknown option or missing value '%s'\n", a.c_str());
      return calibrateUsage();
    } else {
      images.push_back(a);
    }
  }
  if (out.empty() || images.empty()) return calibrateUsage();
  Diagnostics d;
  const auto cal = calibrateChessboard(images, s, d);
  std::fputs(d.format().c_str(), stderr);
  if (!cal) return 2;
  const CalibrationFacts facts{.views = static_cast<int>(cal->usedImages.size()), .boardColumns = s.columns,
                               .boardRows = s.rows, .squareSize = s.squareSize,
                               .rmsReprojectionError = cal->rmsReprojectionError};
  if (Diagnostics written; !writeCameraModel(out, cal->camera, &facts, written)) {
    std::fputs(written.format().c_str(), stderr);
    return 2;
  }
  const CameraModel& c = cal->camera;
  if (json) {
    std::printf("{\"views\": %zu, \"rejected\": %zu, \"rms_px\": %.6f, \"width\": %d, \"height\": %d, "
                "\"fx\": %.6f, \"fy\": %.6f, \"cx\": %.6f, \"cy\": %.6f, "
                "\"distortion\": [%.8g, %.8g, %.8g, %.8g, %.8g], \"out\": \"%s\"}\n",
                cal->usedImages.size(), cal->rejectedImages.size(), cal->rmsReprojectionError, c.width, c.height,
                c.fx, c.fy, c.cx, c.cy, c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3],
                c.distortion[4], out.c_str());
  } else {
    std::printf("marionette-ar calibrate: %zu views (%zu without the board), rms reprojection error %.4f px\n",
                cal->usedImages.size(), cal->rejectedImages.size(), cal->rmsReprojectionError);
    std::printf("  %dx%d  fx %.3f fy %.3f cx %.3f cy %.3f  k1 %.5f k2 %.5f p1 %.5f p2 %.5f k3 %.5f -> %s\n", c.width,
                c.height, c.fx, c.fy, c.cx, c.cy, c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3],
                c.distortion[4], out.c_str());
  }
  return 0;
}

int trackUsage(std::FILE* to = stderr) {
  std::fprintf(to,
               "usage: marionette-ar track --camera CAMERA.yml --images PATTERN|FOLDER|IMAGE|VIDEO [--fps F]\n"
               "                           [--tracker markerless|apriltag] [--target IMAGE --target-width M]\n"
               "                           [--tag-size M] [--map MAP] [--save-map MAP] --poses OUT.csv [--json]\n"
               "                           [--threads N] [--no-smoothing]\n"
               "  --images      a printf pattern (frames/%%04d.png), a folder of images, one image (one frame),\n"
               "                or a video file\n"
               "  --fps         frame rate of an image sequence (default 30; a video's comes from the file)\n"
               "  --tracker     markerless (default): a textured planar target, --target and --target-width,\n"
               "                or a --map saved before; apriltag: 36h11 tags of --tag-size metres\n"
               "  --poses       CSV: frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg\n"
               "                (camera-to-world, camera looking along -Z with +Y up; the pose's standard\n"
               "                deviations; pose fields empty when LOST, sigmas empty when unknown)\n"
               "  --threads     OpenCV threads (default 1: the per-frame figures are for one core)\n"
               "  --json        print the counts and timings as JSON (and \"warning\")\n"
               "  --help, -h    this help; --version: the version\n"
               "  Exit status 0 whatever the tracker found (no pose in the first 30 frames is a warning),\n"
               "  2 bad input.\n");
  return usageExitCode(to);
}

struct TrackArgs {
  std::string camera, images, tracker = "markerless", target, map, saveMap, poses;
  double fps = 30, targetWidth = 0, tagSize = 0;
  int threads = 1;
  bool json = false, smoothing = true;
};

bool isVideo(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* v : {".avi", ".mp4", ".mov", ".mkv", ".webm", ".m4v", ".mpg", ".mpeg"})
    if (ext == v) return true;
  return false;
}

// Frames without a pose after which `track` warns that the map (or target) may not be the one
// these frames show: 1 s at 30 fps. A map relocalizes within a frame or two of its target coming
// into view (docs/tracking.md), so a whole second of nothing is more likely a wrong map.
constexpr std::int64_t kNoPoseWarningFrames = 30;

// `text` as a JSON string, quoted.
std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += escaped;
    } else out += c;
  }
  return out + "\"";
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}

// The percentile as JSON: null when there are no values.
std::string percentileJson(const std::vector<double>& v, double p) {
  if (v.empty()) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", percentile(v, p));
  return text;
}

int track(int argc, char** argv) {
  TrackArgs a;
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    const bool hasValue = i + 1 < argc;
    auto text = [&](std::string& out) { out = argv[++i]; };
    auto number = [&](const char* what, double lo, double hi, double& out) {
      if (!parseNumber(argv[++i], lo, hi, out)) {
        std::fprintf(stderr, "marionette-ar track: %s '%s' is not a number in [%g, %g]\n", what, argv[i], lo, hi);
        return false;
      }
      return true;
    };
    double n = 0;
    if (isHelpFlag(s)) return trackUsage(stdout);
    if (s == "--version") return printVersion();
    if (s == "--camera" && hasValue) text(a.camera);
    else if (s == "--images" && hasValue) text(a.images);
    else if (s == "--tracker" && hasValue) text(a.tracker);
    else if (s == "--target" && hasValue) text(a.target);
    else if (s == "--map" && hasValue) text(a.map);
    else if (s == "--save-map" && hasValue) text(a.saveMap);
    else if (s == "--poses" && hasValue) text(a.poses);
    else if (s == "--fps" && hasValue) {
      if (!number("--fps", 1e-3, 1e4, a.fps)) return 2;
    } else if (s == "--target-width" && hasValue) {
      if (!number("--target-width", 1e-4, 1e4, a.targetWidth)) return 2;
    } else if (s == "--tag-size" && hasValue) {
      if (!number("--tag-size", 1e-4, 1e3, a.tagSize)) return 2;
    } else if (s == "--threads" && hasValue) {
      if (!number("--threads", 1, 256, n) || n != std::floor(n)) return 2;
      a.threads = static_cast<int>(n);
    } else if (s == "--json") a.json = true;
    else if (s == "--no-smoothing") a.smoothing = false;
    else {
      std::fprintf(stderr, "marionette-ar track: unknown option or missing value '%s'\n", s.c_str());
      return trackUsage();
    }
  }
  if (a.camera.empty() || a.images.empty() || a.poses.empty()) return trackUsage();
  if (a.tracker != "markerless" && a.tracker != "apriltag")
    return fail("track", "--tracker '" + a.tracker + "' is neither markerless nor apriltag");
  cv::setNumThreads(a.threads);

  Diagnostics d;
  const auto camera = readCameraModel(a.camera, d);
  if (!camera) {
    std::fputs(d.format().c_str(), stderr);
    return 2;
  }
  std::unique_ptr<Tracker> tracker;
  MarkerlessTracker* markerless = nullptr;
  if (a.tracker == "markerless") {
    MarkerlessSettings settings;
    settings.smoothing = a.smoothing;
    if (!a.map.empty()) {
      auto map = readPlanarMap(a.map, d);
      if (map) tracker = MarkerlessTracker::fromMap(*camera, std::move(*map), a.map, settings, d);
    } else if (!a.target.empty()) {
      if (!(a.targetWidth > 0)) return fail("track", "--target needs --target-width M (the printed width in metres)");
      tracker = MarkerlessTracker::fromTarget(*camera, a.target, a.targetWidth, settings, d);
    } else {
      return fail("track", "the markerless tracker needs --target IMAGE --target-width M, or --map MAP");
    }
    markerless = static_cast<MarkerlessTracker*>(tracker.get());
  } else {
    if (!(a.tagSize > 0)) return fail("track", "--tracker apriltag needs --tag-size M (the black square's side)");
    AprilTagSettings settings;
    settings.tagSize = a.tagSize;
    tracker = AprilTagTracker::create(*camera, settings, d);
  }
  std::fputs(d.format().c_str(), stderr);
  if (!tracker) return 2;
  if (!a.saveMap.empty() && !markerless) return fail("track", "--save-map is for the markerless tracker");

  const BackgroundKind kind = isVideo(a.images) ? BackgroundKind::Video : BackgroundKind::Sequence;
  Diagnostics sd;
  auto source = openBackground(kind, a.images, a.fps, sd, Playback::Hold);
  std::fputs(sd.format().c_str(), stderr);
  if (!source) return 2;
  if (source->width() != camera->width || source->height() != camera->height)
    return fail("track", a.images + " has " + std::to_string(source->width()) + "x" + std::to_string(source->height()) +
                             " frames but " + a.camera + " is for " + std::to_string(camera->width) + "x" +
                             std::to_string(camera->height));
  const double fps = source->fps() > 0 ? source->fps() : a.fps;

  std::FILE* csv = std::fopen(a.poses.c_str(), "w");
  if (!csv) return fail("track", a.poses + ": cannot be written");
  std::fprintf(csv, "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg\n");
  std::vector<double> ms, positionSigmas, rotationSigmas;
  long tracked = 0, limited = 0, relocalizations = 0;
  std::string warning;     // no pose in the first kNoPoseWarningFrames frames
  bool foundLate = false;  // a pose came after the warning
  const std::int64_t frames = source->frameCount();
  for (std::int64_t k = 0; k < frames; ++k) {
    const double t = static_cast<double>(k) / fps;
    const BackgroundFrame& f = source->frameAt(t + 0.25 / fps, sd);
    if (!sd.ok()) {
      std::fputs(sd.format().c_str(), stderr);
      std::fclose(csv);
      return 2;
    }
    const ImageView view{f.rgb.data(), f.width, f.height, 3, 0};
    const auto t0 = std::chrono::steady_clock::now();
    const TrackedPose p = tracker->update(view, t);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (markerless && markerless->lastFrame().relocalized) ++relocalizations;
    tracked += p.state == TrackingState::Tracking;
    limited += p.state == TrackingState::Limited;
    if (markerless && k + 1 == kNoPoseWarningFrames && tracked + limited == 0) {
      warning = a.map.empty() ? a.target + ": no frame matched the target image in " +
                                    std::to_string(kNoPoseWarningFrames) + " frames: do these frames show this target?"
                              : a.map + ": no frame matched the map's keyframes in " +
                                    std::to_string(kNoPoseWarningFrames) + " frames: is this the map of this target?";
      std::fprintf(stderr, "marionette-ar track: warning: %s\n", warning.c_str());
    } else if (!warning.empty() && !foundLate && tracked + limited > 0) {
      foundLate = true;  // the warning was early: said, and taken back in the report
      std::fprintf(stderr, "marionette-ar track: frame %lld has a pose after all\n", static_cast<long long>(k));
    }
    const std::string_view state = trackingStateName(p.state);
    if (p.state == TrackingState::Lost) {
      std::fprintf(csv, "%lld,%.6f,%.*s,,,,,,,,,\n", static_cast<long long>(k), t, static_cast<int>(state.size()),
                   state.data());
    } else {
      const glm::dvec3 pos = p.position();
      const glm::dquat q = p.orientation();
      std::fprintf(csv, "%lld,%.6f,%.*s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,", static_cast<long long>(k), t,
                   static_cast<int>(state.size()), state.data(), pos.x, pos.y, pos.z, q.x, q.y, q.z, q.w);
      if (p.positionSigmaM > 0) {  // 0: the tracker gives none (AprilTag)
        std::fprintf(csv, "%.6g,%.6g\n", p.positionSigmaM, p.rotationSigmaDeg);
        positionSigmas.push_back(p.positionSigmaM);
        rotationSigmas.push_back(p.rotationSigmaDeg);
      } else {
        std::fputs(",\n", csv);
      }
    }
  }
  std::fclose(csv);
  if (Diagnostics written; !a.saveMap.empty() && !writePlanarMap(a.saveMap, markerless->map(), written)) {
    std::fputs(written.format().c_str(), stderr);
    return 2;
  }
  const double median = percentile(ms, 0.5), p95 = percentile(ms, 0.95);
  const std::size_t keyframes = markerless ? markerless->map().keyframes.size() : 0;
  if (a.json) {
    std::printf("{\"frames\": %lld, \"tracked\": %ld, \"limited\": %ld, \"lost\": %lld, \"relocalizations\": %ld, "
                "\"keyframes\": %zu, \"ms_per_frame_median\": %.3f, \"ms_per_frame_p95\": %.3f, \"threads\": %d, "
                "\"tracker\": \"%s\", \"poses\": \"%s\", \"warning\": %s, \"sigma_position_m_median\": %s, "
                "\"sigma_position_m_max\": %s, \"sigma_rotation_deg_median\": %s, \"sigma_rotation_deg_max\": %s}\n",
                static_cast<long long>(frames), tracked, limited, static_cast<long long>(frames) - tracked - limited,
                relocalizations, keyframes, median, p95, a.threads, a.tracker.c_str(), a.poses.c_str(),
                warning.empty() || foundLate ? "null" : jsonString(warning).c_str(),
                percentileJson(positionSigmas, 0.5).c_str(), percentileJson(positionSigmas, 1.0).c_str(),
                percentileJson(rotationSigmas, 0.5).c_str(), percentileJson(rotationSigmas, 1.0).c_str());
  } else {
    std::printf("marionette-ar track: %lld frames, %ld TRACKING, %ld LIMITED, %lld LOST; %.2f ms per frame median, "
                "%.2f p95 (%d thread%s) -> %s\n",
                static_cast<long long>(frames), tracked, limited, static_cast<long long>(frames) - tracked - limited,
                median, p95, a.threads, a.threads == 1 ? "" : "s", a.poses.c_str());
    if (!a.saveMap.empty()) std::printf("marionette-ar track: map of %zu keyframes -> %s\n", keyframes, a.saveMap.c_str());
  }
  return 0;
}

}  // namespace

int runTrackingCommand(int argc, char** argv) {
  if (argc < 2) return -1;
  if (std::strcmp(argv[1], "calibrate") == 0) return calibrate(argc, argv);
  if (std::strcmp(argv[1], "track") == 0) return track(argc, argv);
  return -1;
}

}  // namespace marionette::ar
