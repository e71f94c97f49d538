// What the renderer reads besides the middleware scene: the environment's
// lighting (9 SH irradiance coefficients, and its radiance in the PRT's bands) and texture, the camera pose, and the
// background frames. None of it needs OpenGL, so it loads before the window.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ar_scene_file.hpp"
#include "occlusion_source.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette_ar/render/image.hpp"
#include "marionette_ar/tracking_state.hpp"

namespace marionette::ar {

struct TrackingStateReport {
  TrackingState state = TrackingState::Lost;
  bool changed = false;        // with the last frame
  long frames = 0, posed = 0;  // frames fed, frames with a pose
  bool replayed = false;       // a recorded trajectory (no badge), not a live tracker
};

struct CameraView {
  bool posed = false;  // the view comes from a pose of this frame (else `view` is the identity)
  glm::mat4 view{1.0f}, projection{1.0f};
  glm::dmat4 viewInDouble{1.0};  // `view` before its rounding to float: measurements use it
};

class FrameInputs {
 public:
  FrameInputs();
  ~FrameInputs();
  // Loads the environment map and opens the background. Errors and warnings go to `diagnostics`,
  // naming the file (and the scene key); false on an error. `offline` (headless): a live camera
  // background waits for a new frame at each rendered frame.
  bool load(const ArScene& scene, Diagnostics& diagnostics, bool offline = false);

  [[nodiscard]] const std::array<glm::vec3, 9>& irradianceSH() const noexcept { return irradiance_; }
  // The environment's radiance in the world frame ("rotation" applied), in
  // max(3, prt.bands) bands; zero bands without an environment.
  [[nodiscard]] const prt::ShCoefficients& radianceSH() const noexcept { return radiance_; }
  [[nodiscard]] bool hasEnvironment() const noexcept { return !environment_.empty(); }
  [[nodiscard]] int environmentWidth() const noexcept { return envWidth_; }
  [[nodiscard]] int environmentHeight() const noexcept { return envHeight_; }
  [[nodiscard]] const float* environmentPixels() const noexcept { return environment_.data(); }

  // "environment": {"estimate": "camera"}: feeds the frame's camera image (once per new frame)
  // with the view's pose to the light estimate (marionette_ar/camera_light_estimate.hpp), then
  // sets irradianceSH() and radianceSH() from it: the estimate alone, or with a map the map's
  // shape at the estimate's level and colour. Call after camera(). No allocation.
  void estimateLight(const CameraView& view, double time, int width, int height);
  // True once the estimate lights the scene (a posed camera frame was fed): its radiance is the
  // camera's linear value, so the characters take the camera's curve (sRGB, clipped), not the
  // renderer's tone map.
  [[nodiscard]] bool lightFromCamera() const noexcept { return lightFromCamera_; }
  // Mean time per fed frame (ms), the share of the sphere seen so far, frames fed.
  [[nodiscard]] double lightEstimateMs() const noexcept;
  [[nodiscard]] double lightSeenFraction() const noexcept;

  // Wall time of loading and projecting the environment (ms).
  [[nodiscard]] double lightingMilliseconds() const noexcept { return lightingMs_; }

  [[nodiscard]] ArBackground::Kind backgroundKind() const noexcept { return kind_; }
  // The camera frame for a scene time; the same pointer while the frame does not
  // change; nullptr without a camera background. A frame that cannot be decoded is an error in
  // `diagnostics` naming the file, and the previous frame stays (BackgroundSource::frameAt).
  [[nodiscard]] const Image8* backgroundFrame(double time, Diagnostics& diagnostics);
  // The camera for a viewport of width x height pixels: the scene file's static pose, the
  // tracker's (fed by backgroundFrame(), so call that first in a frame), or the replayed
  // trajectory's (by the background frame shown, or by `time` without camera frames).
  [[nodiscard]] CameraView camera(double time, int width, int height);
  // Where the viewer stands before the first frame: the static camera's eye at `time`; for a
  // tracked or replayed camera (known only from its frames), 1.5 m up and 2 m in front of the
  // origin until then. The scene's "camera" object (a BML target) starts here.
  [[nodiscard]] glm::vec3 viewerBeforeFirstFrame(double time) const;
  // False while a tracked camera has no pose to draw the characters with (LOST past
  // "holdSeconds", unless "hideWhenLost" is false).
  [[nodiscard]] bool charactersVisible(double time) const noexcept;
  // How opaque to draw them: 1 without tracking; with it, by the pose's state and confidence,
  // eased, fading out after a loss (marionette_ar/pose_hold.hpp).
  [[nodiscard]] float characterOpacity(double time) const noexcept;
  // The tracker's (or replayed trajectory's) state, and whether it changed with the last
  // frame; false with neither.
  [[nodiscard]] bool trackingState(TrackingStateReport& out) const noexcept;
  // Occlusion over the target: the mask of the frame shown (occlusion_source.hpp); false when
  // there is none (occlusion off, no pose, no file for the frame). Call after backgroundFrame().
  [[nodiscard]] bool occlusionMask(OcclusionFrame& out, Diagnostics& diagnostics);
  [[nodiscard]] bool occlusionOn() const noexcept;
  [[nodiscard]] double occlusionMs() const noexcept;
  // The tracker's median time per frame so far, ms (0 without one).
  [[nodiscard]] double trackingMedianMs() const;

 private:
  struct Sources;
  std::unique_ptr<Sources> sources_;
  std::array<glm::vec3, 9> irradiance_{};
  prt::ShCoefficients radiance_{.bands = 0, .c = {}};
  std::vector<float> environment_;
  int envWidth_ = 0, envHeight_ = 0;
  ArBackground::Kind kind_ = ArBackground::Kind::Color;
  float nearPlane_ = 0.05f, farPlane_ = 100.0f;
  double lightingMs_ = 0.0;
  bool lightFromCamera_ = false;
};

}  // namespace marionette::ar
