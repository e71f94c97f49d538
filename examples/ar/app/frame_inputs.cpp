#include "frame_inputs.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iterator>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette_ar/background_source.hpp"
#include "marionette_ar/camera_light_estimate.hpp"
#include "marionette_ar/render/background_renderer.hpp"
#include "marionette_ar/camera_pose.hpp"
#include "marionette_ar/live_camera.hpp"
#if MARIONETTE_AR_HAS_TRACKING
#include "replayed_camera.hpp"
#include "tracked_camera.hpp"
#endif
#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/mirror_ball.hpp"
#include "marionette/prt/sh_lighting.hpp"

namespace marionette::ar {

struct FrameInputs::Sources {
  std::unique_ptr<BackgroundSource> background;
#if MARIONETTE_AR_HAS_TRACKING
  std::unique_ptr<TrackedCamera> tracked;
  TrackingState previousState = TrackingState::Lost;
  std::unique_ptr<ReplayedCamera> replayed;
  bool replayByFrame = false;  // a sequence or video: the row of the frame shown
  TrackingState previousRecorded = TrackingState::Lost;
  bool stateChanged = false;
#endif
  std::optional<StaticCameraPose> camera;
  Image8 frame;
  std::int64_t frameIndex = -1;
  // The light estimated from the camera: the frames fed, the map's own light (its shape).
  std::unique_ptr<CameraLightEstimator> light;
  std::int64_t lightFrameIndex = -1;
  prt::ShCoefficients mapRadiance{.bands = 0, .c = {}};
  double lightMs = 0.0;
  long lightFrames = 0;
  std::unique_ptr<OcclusionSource> occlusion;
};

FrameInputs::FrameInputs() : sources_(std::make_unique<Sources>()) {}
FrameInputs::~FrameInputs() = default;

namespace {

// A neutral grey sky (constant radiance) when the scene has no environment map:
// E(n) = pi * L everywhere, i.e. the DC irradiance coefficient pi * L / Y00.
constexpr float kNeutralRadiance = 0.8f;

// The SH9 per-fragment light: the irradiance of the radiance's first 3 bands.
std::array<glm::vec3, 9> irradianceNine(const prt::ShCoefficients& radiance) {
  prt::ShCoefficients nine = radiance;
  nine.bands = 3;
  for (std::size_t i = 9; i < nine.c.size(); ++i) nine.c[i] = glm::dvec3(0.0);
  const prt::ShCoefficients irradiance = prt::irradianceCoefficients(nine);
  std::array<glm::vec3, 9> out{};
  for (std::size_t i = 0; i < 9; ++i) out[i] = glm::vec3(irradiance.c[i]);
  return out;
}

// Moves `from`'s items to the end of `to`; false if one is an error.
bool report(Diagnostics& from, Diagnostics& to) {
  const bool ok = from.ok();
  to.items.insert(to.items.end(), std::make_move_iterator(from.items.begin()),
                  std::make_move_iterator(from.items.end()));
  from.items.clear();
  return ok;
}

}  // namespace

bool FrameInputs::load(const ArScene& scene, Diagnostics& diagnostics, bool offline) {
  kind_ = scene.background.kind;
  Diagnostics camera;
  sources_->camera = StaticCameraPose::create(scene.camera.position, scene.camera.target, scene.camera.up,
                                              scene.camera.fovYDegrees, camera, scene.path);
  nearPlane_ = scene.camera.nearPlane;
  farPlane_ = scene.camera.farPlane;
  if (!report(camera, diagnostics)) return false;

  irradiance_.fill(glm::vec3(0.0f));
  irradiance_[0] = glm::vec3(3.14159265f * kNeutralRadiance / 0.282095f);
  if (!scene.environment.file.empty()) {
    const auto start = std::chrono::steady_clock::now();
    prt::EnvironmentMapLoad loaded = prt::loadLightProbe(scene.environment.file, scene.environment.probe);
    const bool ok = report(loaded.diagnostics, diagnostics);
    if (!ok || !loaded.map) {
      if (ok) diagnostics.error(scene.environment.file, "cannot load the environment map");
      return false;
    }
    // Rotating the environment rotates its SH coefficients; the map is projected once,
    // in as many bands as the PRT uses (the first 3 are the SH9 per-fragment light's).
    const int bands = std::max(3, scene.environment.prt.mode == PrtMode::Off ? 3 : scene.environment.prt.bands);
    radiance_ = prt::rotateAboutY(prt::projectRadiance(*loaded.map, bands),
                                  glm::radians(static_cast<double>(scene.environment.rotationDegrees)));
    irradiance_ = irradianceNine(radiance_);
    envWidth_ = loaded.map->width();
    envHeight_ = loaded.map->height();
    environment_ = std::move(loaded.map->pixels());
    lightingMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  if (kind_ == ArBackground::Kind::Environment && environment_.empty()) kind_ = ArBackground::Kind::Color;
  if (scene.environment.estimateFromCamera) {
    sources_->light = std::make_unique<CameraLightEstimator>();
    sources_->mapRadiance = radiance_;
    if (radiance_.bands == 0) radiance_.bands = 3;  // the estimate's 3 bands, zero until a frame is fed
  }

  if (kind_ == ArBackground::Kind::Image || kind_ == ArBackground::Kind::Sequence ||
      kind_ == ArBackground::Kind::Video) {
    const BackgroundKind kind = kind_ == ArBackground::Kind::Image      ? BackgroundKind::Still
                                : kind_ == ArBackground::Kind::Sequence ? BackgroundKind::Sequence
                                                                        : BackgroundKind::Video;
    Diagnostics opened;
    sources_->background = openBackground(kind, scene.background.file, scene.background.fps, opened);
    if (!report(opened, diagnostics)) return false;
    if (!sources_->background) {
      diagnostics.error(scene.background.file, "cannot open the background");
      return false;
    }
  } else if (kind_ == ArBackground::Kind::Camera) {
    LiveCameraSettings live;
    live.index = scene.background.deviceIndex;
    live.device = scene.background.device;
    live.width = scene.background.captureWidth;
    live.height = scene.background.captureHeight;
    live.timeoutSeconds = scene.background.timeoutSeconds;
    live.waitForNewFrame = offline;
    Diagnostics opened;
    sources_->background = openLiveCamera(live, opened);
    if (!report(opened, diagnostics)) return false;
    if (!sources_->background) {
      diagnostics.error(liveCameraName(live), "cannot open the camera");
      return false;
    }
  }
  if (scene.camera.tracker.kind != ArTracker::Kind::None) {
#if MARIONETTE_AR_HAS_TRACKING
    if (!sources_->background) {
      diagnostics.error(scene.path, "'camera.tracker' needs a sequence or video background");
      return false;
    }
    sources_->tracked = TrackedCamera::create(scene.camera.tracker, sources_->background->width(),
                                              sources_->background->height(), diagnostics);
    if (!sources_->tracked) return false;
#else
    diagnostics.error(scene.path, "'camera.tracker' needs a build with MARIONETTE_WITH_TRACKING");
    return false;
#endif
  }
  if (!scene.camera.replay.poses.empty()) {
#if MARIONETTE_AR_HAS_TRACKING
    const bool frames = kind_ == ArBackground::Kind::Sequence || kind_ == ArBackground::Kind::Video;
    const bool sized = frames || kind_ == ArBackground::Kind::Image;
    sources_->replayed = ReplayedCamera::create(scene.camera.replay, sized ? sources_->background->width() : 0,
                                                sized ? sources_->background->height() : 0, diagnostics);
    if (!sources_->replayed) return false;
    sources_->replayByFrame = frames;
#else
    diagnostics.error(scene.path,
                      "'camera.poses' needs a build with MARIONETTE_WITH_TRACKING (the calibration reader)");
    return false;
#endif
  }
  Diagnostics occlusion;
  sources_->occlusion = OcclusionSource::create(scene, occlusion);
  if (!report(occlusion, diagnostics)) return false;
  return true;
}

const Image8* FrameInputs::backgroundFrame(double time, Diagnostics& diagnostics) {
  if (!sources_->background) return nullptr;
  Sources& s = *sources_;
  const BackgroundFrame& f = s.background->frameAt(time, diagnostics);
  if (f.index != s.frameIndex) {  // a new frame: convert once
    s.frameIndex = f.index;
    s.frame.width = f.width;
    s.frame.height = f.height;
    s.frame.channels = 3;
    s.frame.pixels.assign(f.rgb.begin(), f.rgb.end());
#if MARIONETTE_AR_HAS_TRACKING
    if (s.tracked) {
      s.tracked->update({f.rgb.data(), f.width, f.height, 3, 0}, time);
      s.stateChanged = s.tracked->state() != s.previousState;
      s.previousState = s.tracked->state();
    }
    if (s.replayed && s.replayByFrame) {
      s.replayed->update(f.index, time);
      s.stateChanged = s.replayed->state() != s.previousRecorded;
      s.previousRecorded = s.replayed->state();
    }
#endif
  }
  return &s.frame;
}

namespace {

// Pinhole intrinsics of the camera image as the viewport shows it: the GL projection's focal
// lengths and centre carried through the cover crop (coverRect) into the image's pixels.
PinholeIntrinsics imageIntrinsics(const glm::mat4& projection, int imageWidth, int imageHeight, int width, int height) {
  const glm::vec4 rect = coverRect(static_cast<float>(imageWidth) / static_cast<float>(imageHeight),
                                   static_cast<float>(width) / static_cast<float>(height));
  PinholeIntrinsics k;
  k.fx = 0.5 * projection[0][0] * rect.x * imageWidth;
  k.cx = (0.5 * (1.0 - projection[2][0]) * rect.x + rect.z) * imageWidth - 0.5;
  k.fy = 0.5 * projection[1][1] * rect.y * imageHeight;
  k.cy = (1.0 - rect.w - 0.5 * (1.0 - projection[2][1]) * rect.y) * imageHeight - 0.5;
  return k;
}

}  // namespace

void FrameInputs::estimateLight(const CameraView& view, double time, int width, int height) {
  Sources& s = *sources_;
  if (!s.light || !view.posed || s.frame.empty() || s.frame.channels != 3 || s.frameIndex == s.lightFrameIndex) return;
  s.lightFrameIndex = s.frameIndex;
  const auto start = std::chrono::steady_clock::now();
  CameraLightFrame frame;
  frame.image = {s.frame.pixels.data(), s.frame.width, s.frame.height, static_cast<std::size_t>(s.frame.width) * 3};
  frame.cameraToWorld = glm::inverse(view.viewInDouble);
  frame.intrinsics = imageIntrinsics(view.projection, s.frame.width, s.frame.height, width, height);
  frame.timeSeconds = time;
  if (s.light->addFrame(frame) != LightFrameResult::Accepted || !s.light->estimate().valid) return;
  // The camera's linear values, white balance as the camera set it (exposure unknown: 1).
  const prt::ShCoefficients camera = cameraMatchedRadiance(s.light->estimate().radiance, 1.0);
  const int bands = radiance_.bands;
  if (s.mapRadiance.bands > 0) {  // the map's shape at the camera's level and colour, channel by channel
    for (int c = 0; c < 3; ++c) {
      const double gain = s.mapRadiance.c[0][c] > 0.0 ? camera.c[0][c] / s.mapRadiance.c[0][c] : 0.0;
      for (int i = 0; i < s.mapRadiance.count(); ++i)
        radiance_.c[static_cast<std::size_t>(i)][c] = s.mapRadiance.c[static_cast<std::size_t>(i)][c] * gain;
    }
  } else {
    radiance_.c.fill(glm::dvec3(0.0));
    for (std::size_t i = 0; i < 9; ++i) radiance_.c[i] = camera.c[i];
  }
  radiance_.bands = bands;
  irradiance_ = irradianceNine(radiance_);
  lightFromCamera_ = true;
  s.lightMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++s.lightFrames;
}

double FrameInputs::lightEstimateMs() const noexcept {
  return sources_->lightFrames > 0 ? sources_->lightMs / static_cast<double>(sources_->lightFrames) : 0.0;
}

double FrameInputs::lightSeenFraction() const noexcept {
  return sources_->light ? sources_->light->estimate().seenFraction : 0.0;
}

glm::vec3 FrameInputs::viewerBeforeFirstFrame(double time) const {
#if MARIONETTE_AR_HAS_TRACKING
  if (sources_->tracked || sources_->replayed) return {0.0f, 1.5f, 2.0f};
#endif
  return glm::vec3(glm::inverse(sources_->camera->poseAt(time).view)[3]);
}

CameraView FrameInputs::camera(double time, int width, int height) {
  CameraView v;
#if MARIONETTE_AR_HAS_TRACKING
  if (const TrackedCamera* t = sources_->tracked.get()) {
    if (t->hasPose(time)) {
      v.posed = true;
      v.viewInDouble = t->viewInDouble();
      v.view = glm::mat4(v.viewInDouble);
    }
    v.projection = t->projection(width, height, nearPlane_, farPlane_);
    return v;
  }
  if (ReplayedCamera* r = sources_->replayed.get()) {
    if (!sources_->replayByFrame) {  // no camera frames: the row of the scene time
      r->update(-1, time);
      sources_->stateChanged = r->state() != sources_->previousRecorded;
      sources_->previousRecorded = r->state();
    }
    if (r->hasPose(time)) {
      v.posed = true;
      v.viewInDouble = r->viewInDouble();
      v.view = glm::mat4(v.viewInDouble);
    }
    v.projection = r->projection(width, height, nearPlane_, farPlane_);
    return v;
  }
#endif
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const CameraPose pose = sources_->camera->poseAt(time);
  v.posed = true;
  v.view = pose.view;
  v.viewInDouble = glm::dmat4(pose.view);
  v.projection = glm::perspective(glm::radians(pose.fovYDegrees), aspect, nearPlane_, farPlane_);
  return v;
}

bool FrameInputs::charactersVisible(double time) const noexcept {
#if MARIONETTE_AR_HAS_TRACKING
  if (const TrackedCamera* t = sources_->tracked.get()) return t->charactersVisible(time);
  if (const ReplayedCamera* r = sources_->replayed.get()) return r->charactersVisible(time);
#endif
  (void)time;
  return true;
}

float FrameInputs::characterOpacity(double time) const noexcept {
#if MARIONETTE_AR_HAS_TRACKING
  if (const TrackedCamera* t = sources_->tracked.get()) return t->opacity(time);
  if (const ReplayedCamera* r = sources_->replayed.get()) return r->opacity(time);
#endif
  (void)time;
  return 1.0f;
}

bool FrameInputs::trackingState(TrackingStateReport& out) const noexcept {
#if MARIONETTE_AR_HAS_TRACKING
  if (const TrackedCamera* t = sources_->tracked.get()) {
    out.state = t->state();
    out.changed = sources_->stateChanged;
    out.frames = t->framesSeen();
    out.posed = t->framesTracked();
    return true;
  }
  if (const ReplayedCamera* r = sources_->replayed.get()) {
    out.state = r->state();
    out.changed = sources_->stateChanged;
    out.frames = r->framesSeen();
    out.posed = r->framesPosed();
    out.replayed = true;
    return true;
  }
#endif
  (void)out;
  return false;
}

bool FrameInputs::occlusionMask(OcclusionFrame& out, Diagnostics& diagnostics) {
  Sources& s = *sources_;
  if (!s.occlusion) return false;
  TrackedCamera* tracked = nullptr;
#if MARIONETTE_AR_HAS_TRACKING
  tracked = s.tracked.get();
#endif
  out.frameWidth = s.frame.width;
  out.frameHeight = s.frame.height;
  return s.frame.width > 0 && s.occlusion->frame(s.frameIndex, tracked, out, diagnostics);
}

bool FrameInputs::occlusionOn() const noexcept { return sources_->occlusion != nullptr; }
double FrameInputs::occlusionMs() const noexcept {
  return sources_->occlusion ? sources_->occlusion->meanMilliseconds() : 0.0;
}

double FrameInputs::trackingMedianMs() const {
#if MARIONETTE_AR_HAS_TRACKING
  if (const TrackedCamera* t = sources_->tracked.get()) return t->medianMilliseconds();
#endif
  return 0;
}

}  // namespace marionette::ar
