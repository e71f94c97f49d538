#include "ar_scene_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marionette/core/text_file.hpp"

namespace marionette::ar {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class Reader {
 public:
  Reader(const std::string& path, Diagnostics& d) : path_(path), d_(d) {}

  void error(const std::string& key, const std::string& message) {
    d_.items.push_back({Severity::Error, path_, 0, 0, "'" + key + "': " + message});
  }

  std::string resolve(const std::string& p) const {
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (fs::path(path_).parent_path() / p).lexically_normal().string();
  }

  void number(const Json& obj, const char* key, const std::string& where, float& out, float lo, float hi) {
    if (!obj.contains(key)) return;
    const Json& v = obj[key];
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo || v.get<double>() > hi) {
      error(where + "." + key, "expected a number in [" + trim(lo) + ", " + trim(hi) + "]");
      return;
    }
    out = v.get<float>();
  }

  void vec3(const Json& obj, const char* key, const std::string& where, glm::vec3& out) {
    if (!obj.contains(key)) return;
    const Json& v = obj[key];
    bool ok = v.is_array() && v.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) ok = v[i].is_number() && std::isfinite(v[i].get<double>());
    if (!ok) {
      error(where + "." + key, "expected 3 finite numbers");
      return;
    }
    out = {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
  }

  void integer(const Json& obj, const char* key, const std::string& where, int& out, int lo, int hi) {
    if (!obj.contains(key)) return;
    const Json& v = obj[key];
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi) {
      error(where + "." + key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
      return;
    }
    out = static_cast<int>(v.get<long long>());
  }

  bool object(const Json& root, const char* key) {
    if (!root.contains(key)) return false;
    if (!root[key].is_object()) {
      error(key, "expected an object");
      return false;
    }
    return true;
  }

  std::string string(const Json& obj, const char* key, const std::string& where, bool required) {
    if (!obj.contains(key)) {
      if (required) error(where.empty() ? key : where + "." + key, "missing");
      return {};
    }
    if (!obj[key].is_string() || obj[key].get<std::string>().empty()) {
      error(where.empty() ? key : where + "." + key, "expected a non-empty string");
      return {};
    }
    return obj[key].get<std::string>();
  }

  void unknownKeys(const Json& obj, const std::string& where, std::initializer_list<const char*> known) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool found = false;
      for (const char* k : known) found = found || it.key() == k;
      if (!found)
        d_.items.push_back({Severity::Warning, path_, 0, 0,
                            "'" + (where.empty() ? it.key() : where + "." + it.key()) + "': unknown key, ignored"});
    }
  }

 private:
  static std::string trim(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  const std::string& path_;
  Diagnostics& d_;
};

}  // namespace

const char* prtModeName(PrtMode mode) noexcept {
  switch (mode) {
    case PrtMode::Shadowed: return "shadowed";
    case PrtMode::Unshadowed: return "unshadowed";
    case PrtMode::Off: break;
  }
  return "off";
}

bool parsePrtMode(const std::string& name, PrtMode& out) noexcept {
  for (PrtMode m : {PrtMode::Shadowed, PrtMode::Unshadowed, PrtMode::Off})
    if (name == prtModeName(m)) {
      out = m;
      return true;
    }
  return false;
}

Diagnostics readArScene(const std::string& path, ArScene& out) {
  Diagnostics d;
  out.path = path;
  std::string text;
  if (!readTextFile(path, text, d, "cannot read the AR scene file")) return d;
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {  // nlohmann would stop there
    const auto [line, column] = lineColumnAt(text, static_cast<std::ptrdiff_t>(nul));
    d.items.push_back({Severity::Error, path, line, column, "a NUL byte: not a JSON text file"});
    return d;
  }
  Json root = Json::parse(text, nullptr, false);
  if (root.is_discarded() || !root.is_object()) {
    d.items.push_back({Severity::Error, path, 0, 0, "not a JSON object (syntax error)"});
    return d;
  }
  Reader r(path, d);
  r.unknownKeys(root, "", {"comment", "scene", "camera", "background", "environment", "render", "authoring"});
  out.scene = r.resolve(r.string(root, "scene", "", true));

  if (r.object(root, "camera")) {
    const Json& c = root["camera"];
    r.unknownKeys(c, "camera", {"position", "target", "up", "fovY", "near", "far", "tracker", "poses", "camera",
                                "holdSeconds", "hideWhenLost"});
    r.vec3(c, "position", "camera", out.camera.position);
    r.vec3(c, "target", "camera", out.camera.target);
    r.vec3(c, "up", "camera", out.camera.up);
    r.number(c, "fovY", "camera", out.camera.fovYDegrees, 1.0f, 170.0f);
    r.number(c, "near", "camera", out.camera.nearPlane, 1e-4f, 1e3f);
    r.number(c, "far", "camera", out.camera.farPlane, 1e-3f, 1e7f);
    // The pose itself (look direction, up) is checked by StaticCameraPose (frame_inputs.cpp).
    if (!(out.camera.farPlane > out.camera.nearPlane)) r.error("camera.far", "must be greater than camera.near");
    if (c.contains("tracker")) {
      if (!c["tracker"].is_object()) {
        r.error("camera.tracker", "expected an object");
      } else {
        const Json& t = c["tracker"];
        ArTracker& tr = out.camera.tracker;
        r.unknownKeys(t, "camera.tracker", {"kind", "camera", "target", "width", "map", "tagSize", "holdSeconds",
                                            "hideWhenLost"});
        const std::string kind = r.string(t, "kind", "camera.tracker", true);
        if (kind == "markerless") tr.kind = ArTracker::Kind::Markerless;
        else if (kind == "apriltag") tr.kind = ArTracker::Kind::AprilTag;
        else if (!kind.empty()) r.error("camera.tracker.kind", "'" + kind + "' is neither markerless nor apriltag");
        tr.camera = r.resolve(r.string(t, "camera", "camera.tracker", true));
        float width = 0, tagSize = 0, hold = static_cast<float>(tr.holdSeconds);
        if (tr.kind == ArTracker::Kind::Markerless) {
          if (t.contains("map")) tr.map = r.resolve(r.string(t, "map", "camera.tracker", true));
          else {
            tr.target = r.resolve(r.string(t, "target", "camera.tracker", true));
            if (!t.contains("width")) r.error("camera.tracker.width", "missing: the target's width in metres");
          }
          r.number(t, "width", "camera.tracker", width, 1e-4f, 1e4f);
        } else if (tr.kind == ArTracker::Kind::AprilTag) {
          if (!t.contains("tagSize")) r.error("camera.tracker.tagSize", "missing: the tag's side in metres");
          r.number(t, "tagSize", "camera.tracker", tagSize, 1e-4f, 1e3f);
        }
        r.number(t, "holdSeconds", "camera.tracker", hold, 0.0f, 3600.0f);
        tr.width = width;
        tr.tagSize = tagSize;
        tr.holdSeconds = hold;
        if (t.contains("hideWhenLost")) {
          if (!t["hideWhenLost"].is_boolean()) r.error("camera.tracker.hideWhenLost", "expected true or false");
          else tr.hideWhenLost = t["hideWhenLost"].get<bool>();
        }
      }
    }
    ArPoseReplay& replay = out.camera.replay;
    if (c.contains("poses")) {
      replay.poses = r.resolve(r.string(c, "poses", "camera", true));
      replay.camera = r.resolve(r.string(c, "camera", "camera", true));
      if (c.contains("tracker")) r.error("camera.poses", "a camera either tracks or replays poses, not both");
    } else {
      for (const char* key : {"camera", "holdSeconds", "hideWhenLost"})
        if (c.contains(key)) r.error(std::string("camera.") + key, "only with \"poses\" (a replayed trajectory)");
    }
    float hold = static_cast<float>(replay.holdSeconds);
    r.number(c, "holdSeconds", "camera", hold, 0.0f, 3600.0f);
    replay.holdSeconds = hold;
    if (c.contains("hideWhenLost")) {
      if (!c["hideWhenLost"].is_boolean()) r.error("camera.hideWhenLost", "expected true or false");
      else replay.hideWhenLost = c["hideWhenLost"].get<bool>();
    }
  }
  if (r.object(root, "background")) {
    const Json& b = root["background"];
    r.unknownKeys(b, "background", {"kind", "file", "fps", "color", "device", "width", "height", "timeoutSeconds"});
    const std::string kind = r.string(b, "kind", "background", true);
    using K = ArBackground::Kind;
    if (kind == "environment") out.background.kind = K::Environment;
    else if (kind == "image") out.background.kind = K::Image;
    else if (kind == "sequence") out.background.kind = K::Sequence;
    else if (kind == "video") out.background.kind = K::Video;
    else if (kind == "color") out.background.kind = K::Color;
    else if (kind == "camera") out.background.kind = K::Camera;
    else if (!kind.empty())
      r.error("background.kind", "'" + kind + "' is none of environment, image, sequence, video, color, camera");
    const bool needsFile = out.background.kind == K::Image || out.background.kind == K::Sequence ||
                           out.background.kind == K::Video;
    out.background.file = r.resolve(r.string(b, "file", "background", needsFile));
    float fps = static_cast<float>(out.background.fps);
    r.number(b, "fps", "background", fps, 0.1f, 1000.0f);
    out.background.fps = fps;
    r.vec3(b, "color", "background", out.background.color);
    if (out.background.kind == K::Camera) {
      ArBackground& bg = out.background;
      if (!b.contains("device")) {
        r.error("background.device", "missing: a V4L2 index (0), a device (\"/dev/video0\") or a stream URL");
      } else if (b["device"].is_number_integer()) {
        r.integer(b, "device", "background", bg.deviceIndex, 0, 255);
      } else if (b["device"].is_string()) {
        bg.device = b["device"].get<std::string>();
        if (bg.device.rfind("/dev/", 0) != 0 && bg.device.find("://") == std::string::npos)
          r.error("background.device", "'" + bg.device + "' is neither a /dev/ path nor a stream URL (scheme://...)");
      } else {
        r.error("background.device", "expected an index, a /dev/ path or a stream URL");
      }
      r.integer(b, "width", "background", bg.captureWidth, 16, 8192);
      r.integer(b, "height", "background", bg.captureHeight, 16, 8192);
      if ((bg.captureWidth > 0) != (bg.captureHeight > 0))
        r.error("background.width", "give both width and height, or neither");
      float timeout = static_cast<float>(bg.timeoutSeconds);
      r.number(b, "timeoutSeconds", "background", timeout, 0.01f, 3600.0f);
      bg.timeoutSeconds = timeout;
    } else {
      for (const char* key : {"device", "width", "height", "timeoutSeconds"})
        if (b.contains(key)) r.error(std::string("background.") + key, "only for a \"camera\" background");
    }
  }
  if (r.object(root, "environment")) {
    const Json& e = root["environment"];
    r.unknownKeys(e, "environment", {"file", "rotation", "exposure", "probe", "prt", "estimate"});
    const std::string estimate = r.string(e, "estimate", "environment", false);
    if (estimate == "camera") out.environment.estimateFromCamera = true;
    else if (!estimate.empty() && estimate != "none")
      r.error("environment.estimate", "'" + estimate + "' is neither camera nor none");
    // A map, or the light estimated from the camera (or both: the map's shape, the camera's level).
    out.environment.file = r.resolve(r.string(e, "file", "environment", !out.environment.estimateFromCamera));
    r.number(e, "rotation", "environment", out.environment.rotationDegrees, -3600.0f, 3600.0f);
    r.number(e, "exposure", "environment", out.environment.exposure, 0.0f, 1e6f);
    const std::string probe = r.string(e, "probe", "environment", false);
    if (probe == "auto") out.environment.probe = prt::LightProbeKind::Auto;
    else if (probe == "latlong") out.environment.probe = prt::LightProbeKind::LatLong;
    else if (probe == "mirror-ball") out.environment.probe = prt::LightProbeKind::MirrorBall;
    else if (!probe.empty()) r.error("environment.probe", "'" + probe + "' is none of auto, latlong, mirror-ball");
    if (e.contains("prt")) {
      if (!e["prt"].is_object()) {
        r.error("environment.prt", "expected an object");
      } else {
        const Json& p = e["prt"];
        ArPrt& prtOut = out.environment.prt;
        r.unknownKeys(p, "environment.prt", {"mode", "bands", "rays", "cache", "pose"});
        const std::string mode = r.string(p, "mode", "environment.prt", false);
        if (!mode.empty() && !parsePrtMode(mode, prtOut.mode))
          r.error("environment.prt.mode", "'" + mode + "' is none of shadowed, unshadowed, off");
        r.integer(p, "bands", "environment.prt", prtOut.bands, 2, 8);
        r.integer(p, "rays", "environment.prt", prtOut.rays, 1, 65536);
        if (p.contains("cache")) prtOut.cache = r.resolve(r.string(p, "cache", "environment.prt", false));
        if (p.contains("pose")) {
          if (!p["pose"].is_object()) {
            r.error("environment.prt.pose", "expected an object");
          } else {
            const Json& pose = p["pose"];
            r.unknownKeys(pose, "environment.prt.pose", {"clip", "time"});
            prtOut.poseClip = r.string(pose, "clip", "environment.prt.pose", true);
            r.number(pose, "time", "environment.prt.pose", prtOut.poseTime, 0.0f, 1e6f);
          }
        }
      }
    }
  }
  if (out.background.kind == ArBackground::Kind::Environment && out.environment.file.empty() &&
      root.contains("background"))
    r.error("background.kind", "'environment' needs an \"environment\" map");
  if (out.environment.estimateFromCamera && (out.background.kind == ArBackground::Kind::Environment ||
                                             out.background.kind == ArBackground::Kind::Color))
    r.error("environment.estimate", "'camera' needs camera frames: an \"image\", \"sequence\", \"video\" or \"camera\" background");
  if (out.camera.tracker.kind != ArTracker::Kind::None && out.background.kind != ArBackground::Kind::Sequence &&
      out.background.kind != ArBackground::Kind::Video && out.background.kind != ArBackground::Kind::Camera)
    r.error("camera.tracker", "a tracker needs camera frames: a \"sequence\", \"video\" or \"camera\" background");
  if (!out.camera.replay.poses.empty() && out.background.kind == ArBackground::Kind::Camera)
    r.error("camera.poses", "replays a recording: a live \"camera\" background has no time axis to follow");
  if (r.object(root, "authoring")) {
    const Json& a = root["authoring"];
    r.unknownKeys(a, "authoring", {"bml"});
    if (a.contains("bml")) {
      const Json& list = a["bml"];
      if (!list.is_array()) r.error("authoring.bml", "expected an array of BML files");
      for (std::size_t i = 0; list.is_array() && i < list.size(); ++i) {
        if (!list[i].is_string() || list[i].get<std::string>().empty()) {
          r.error("authoring.bml[" + std::to_string(i) + "]", "expected a file name");
          continue;
        }
        out.authoringBml.push_back(r.resolve(list[i].get<std::string>()));
      }
    }
  }
  bool contactShadowsSet = false;
  if (r.object(root, "render")) {
    const Json& rd = root["render"];
    r.unknownKeys(rd, "render", {"width", "height", "fps", "contactShadows", "occlusion"});
    float w = static_cast<float>(out.width), h = static_cast<float>(out.height), fps = static_cast<float>(out.fps);
    r.number(rd, "width", "render", w, 16.0f, 8192.0f);
    r.number(rd, "height", "render", h, 16.0f, 8192.0f);
    r.number(rd, "fps", "render", fps, 1.0f, 1000.0f);
    out.width = static_cast<int>(w);
    out.height = static_cast<int>(h);
    out.fps = fps;
    if (rd.contains("contactShadows")) {
      const Json& cs = rd["contactShadows"];
      ContactShadowSettings& shadows = out.contactShadows;
      if (cs.is_boolean()) {
        shadows.enabled = cs.get<bool>();
      } else if (cs.is_object()) {
        r.unknownKeys(cs, "render.contactShadows", {"enabled", "strength", "softness"});
        shadows.enabled = true;
        if (cs.contains("enabled")) {
          if (!cs["enabled"].is_boolean()) r.error("render.contactShadows.enabled", "expected true or false");
          else shadows.enabled = cs["enabled"].get<bool>();
        }
        r.number(cs, "strength", "render.contactShadows", shadows.strength, 0.0f, 1.0f);
        r.number(cs, "softness", "render.contactShadows", shadows.softnessDegrees, 0.0f, 45.0f);
      } else {
        r.error("render.contactShadows", "expected true, false or an object {\"strength\", \"softness\"}");
      }
      contactShadowsSet = true;
    }
    if (rd.contains("occlusion")) {
      const Json& oc = rd["occlusion"];
      ArOcclusion& occlusion = out.occlusion;
      occlusion.asked = true;
      if (oc.is_boolean()) {
        occlusion.enabled = oc.get<bool>();
      } else if (oc.is_object()) {
        r.unknownKeys(oc, "render.occlusion", {"enabled", "height", "masks"});
        occlusion.enabled = true;
        if (oc.contains("enabled")) {
          if (!oc["enabled"].is_boolean()) r.error("render.occlusion.enabled", "expected true or false");
          else occlusion.enabled = oc["enabled"].get<bool>();
        }
        if (oc.contains("height")) r.number(oc, "height", "render.occlusion", occlusion.heightLimit, 0.001f, 100.0f);
        if (oc.contains("masks")) {
          if (!oc["masks"].is_string()) r.error("render.occlusion.masks", "expected a folder of mask images");
          else occlusion.masks = r.resolve(oc["masks"].get<std::string>());
        }
      } else {
        r.error("render.occlusion", "expected true, false or an object {\"height\", \"masks\"}");
      }
    }
  }
  // On by default where the floor is real: a tracked or replayed camera.
  if (!contactShadowsSet)
    out.contactShadows.enabled = out.camera.tracker.kind != ArTracker::Kind::None || !out.camera.replay.poses.empty();
  // On by default where a mask exists: the markerless tracker's (AprilTag has no image of its target).
  if (!out.occlusion.asked) out.occlusion.enabled = out.camera.tracker.kind == ArTracker::Kind::Markerless;
  return d;
}

}  // namespace marionette::ar
