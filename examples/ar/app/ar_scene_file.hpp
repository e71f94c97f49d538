// AR scene files: what the reference renderer shows around a middleware scene.
//
// {
//   "scene": "walk.json",                       // required: the middleware scene (scene/scene_file.hpp)
//   "camera": { "position": [0, 1.5, 4.5], "target": [0, 0.9, 0], "up": [0, 1, 0],
//               "fovY": 45, "near": 0.05, "far": 100,
//               "tracker": { "kind": "markerless",            // optional: or "apriltag" (docs/tracking.md)
//                            "camera": "camera.yml",          // required: OpenCV calibration YAML
//                            "target": "floor.png", "width": 0.3,  // markerless: reference image, metres
//                            "map": "floor.map",              // markerless: a saved map instead of target
//                            "tagSize": 0.1,                  // apriltag: the black square's side, metres
//                            "holdSeconds": 1.0,              // when LOST keep the last pose this long,
//                            "hideWhenLost": true } },        //   then hide the characters (or keep them)
//   // or a replayed trajectory instead of a tracker: "camera": { "poses": "poses.csv",  // marionette-ar track's CSV
//   //   "camera": "camera.yml", "holdSeconds": 1.0, "hideWhenLost": true, "near": ..., "far": ... }
//   "background": { "kind": "environment" },    // or "image" / "sequence" / "video" with "file"
//                                               //   (and "fps" for a sequence), or "color" with "color": [r, g, b],
//                                               //   or "camera" with "device": 0 | "/dev/video0" | "rtsp://..."
//                                               //   (optional "width", "height", "timeoutSeconds": 5)
//   "environment": { "file": "studio.exr", "rotation": 0, "exposure": 1.0,  // optional: HDR light probe
//                    "probe": "auto",                         // or "latlong" / "mirror-ball"
//                    "prt": { "mode": "shadowed", "bands": 5, "rays": 1024,   // or "unshadowed" / "off"
//                             "cache": "dir",                 // optional: prt::defaultTransferCacheDirectory()
//                             "pose": { "clip": "walk", "time": 0.0 } } },   // optional: transfer in that pose
//   "render": { "width": 960, "height": 540, "fps": 30, "contactShadows": true, "occlusion": true },
//   "authoring": { "bml": ["wave.xml", "nod.xml"] }   // optional: the BML the authoring UI offers
// }
//
// Paths are relative to the AR scene file, or absolute. Without "environment"
// the characters get a neutral grey sky light (and no PRT). With one, they are lit
// by precomputed radiance transfer (docs/ar-renderer.md, "PRT lighting") unless
// "prt.mode" is "off", then by the environment's 9 SH irradiance coefficients. The camera is the
// static pose (position, target, up, fovY) unless "tracker" is given: then the background's
// frames (image sequence or video) feed it, the pose and the projection come from it, and the
// characters stand in the tracked world (the target's plane, metric).
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/mirror_ball.hpp"
#include "marionette/prt/transfer.hpp"

namespace marionette::ar {

struct ArTracker {
  enum class Kind { None, Markerless, AprilTag } kind = Kind::None;
  std::string camera;  // calibration YAML, resolved
  std::string target;  // markerless: reference image, resolved
  double width = 0;    // markerless: the target's width, metres
  std::string map;     // markerless: a saved map, resolved
  double tagSize = 0;  // apriltag: metres
  double holdSeconds = 1.0;
  bool hideWhenLost = true;
};

// "camera": {"poses": ...}: the view from a recorded trajectory (marionette_ar/pose_track.hpp),
// the projection from the calibration, LOST rows held and hidden like a tracker's LOST.
struct ArPoseReplay {
  std::string poses;   // the CSV, resolved; empty: no replay
  std::string camera;  // calibration YAML, resolved
  double holdSeconds = 1.0;
  bool hideWhenLost = true;
};

struct ArCamera {
  glm::vec3 position{0.0f, 1.5f, 4.0f};
  glm::vec3 target{0.0f, 1.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;
  float nearPlane = 0.05f, farPlane = 100.0f;
  ArTracker tracker;
  ArPoseReplay replay;
};

struct ArBackground {
  enum class Kind { Environment, Image, Sequence, Video, Color, Camera } kind = Kind::Environment;
  std::string file;
  double fps = 30.0;
  glm::vec3 color{0.2f};
  // Camera: a V4L2 index (>= 0), else `device` (a /dev/ path or a stream URL), read live
  // (marionette_ar/live_camera.hpp); a capture size to ask for (0: the device's), the timeout.
  int deviceIndex = -1;
  std::string device;
  int captureWidth = 0, captureHeight = 0;
  double timeoutSeconds = 5.0;
};

enum class PrtMode { Shadowed, Unshadowed, Off };

struct ArPrt {
  PrtMode mode = PrtMode::Shadowed;
  int bands = prt::kDefaultTransferBands;  // 2..8
  int rays = 1024;                         // 1..65536 (shadowed)
  std::string cache;                       // empty: prt::defaultTransferCacheDirectory()
  std::string poseClip;                    // empty: the rest pose
  float poseTime = 0.0f;                   // clip-local seconds
};

struct ArEnvironment {
  std::string file;  // empty: no map (neutral sky light, no PRT)
  float rotationDegrees = 0.0f;
  float exposure = 1.0f;
  prt::LightProbeKind probe = prt::LightProbeKind::Auto;
  ArPrt prt;
  // "estimate": "camera": the light estimated from the camera's frames (camera_light_estimate.hpp);
  // with a map too, the map keeps its shape and takes the camera's level and colour.
  bool estimateFromCamera = false;
};

// Contact shadows on the floor (docs/ar-renderer.md, "Contact shadows"; marionette_ar/contact_shadow.hpp).
struct ContactShadowSettings {
  bool enabled = false;
  // Multiplies the darkening the light model predicts (1: the floor loses exactly the light
  // the character blocks; 0: no shadow). 0..1.
  float strength = 1.0f;
  // The dominant light's angular radius: the penumbra widens by tan(softness) per metre between
  // the occluder and the floor. 9 coefficients say nothing of a light's size, so it is a setting.
  float softnessDegrees = 6.0f;
};

// Occlusion over the target (docs/ar-renderer.md, "Occlusion over the target"): where something
// real hides the tracked target (a hand), the characters' parts drawn over it are not drawn.
struct ArOcclusion {
  bool enabled = false;  // on by default with a markerless tracker (the one tracker with a mask)
  bool asked = false;    // the file turned it on (a camera without a mask is then warned about)
  // "height": the occluder is taken to reach this many metres above the floor: the characters'
  // parts higher up are in front of it. Absent (< 0): everything drawn over the mask is behind it.
  float heightLimit = -1.0f;
  // "masks": a folder of grey images, one per background frame in name order (white: hidden),
  // used instead of the tracker's (a segmentation made elsewhere; the tests' true masks). Resolved.
  std::string masks;
};

struct ArScene {
  std::string path;   // the AR scene file
  std::string scene;  // the middleware scene, resolved
  ArCamera camera;
  ArBackground background;
  ArEnvironment environment;
  int width = 960, height = 540;
  double fps = 30.0;
  // "render": {"contactShadows": true | false | {"strength": 1, "softness": 6}}; on by default
  // when the camera is tracked or replayed (the world's floor is then a real surface).
  ContactShadowSettings contactShadows;
  // "render": {"occlusion": true | false | {"enabled", "height", "masks"}}.
  ArOcclusion occlusion;
  std::vector<std::string> authoringBml;  // resolved
};

// Reads an AR scene file; every problem names the file and the key.
[[nodiscard]] Diagnostics readArScene(const std::string& path, ArScene& out);

[[nodiscard]] const char* prtModeName(PrtMode mode) noexcept;
// "shadowed" / "unshadowed" / "off"; false for anything else.
[[nodiscard]] bool parsePrtMode(const std::string& name, PrtMode& out) noexcept;

}  // namespace marionette::ar
