// marionette-ar rendering a scene, as named steps. Set up once: the AR scene file, its
// environment and background, the GL context, the middleware scene and BML realizer, a GPU
// model per asset, PRT, the shaders and the authoring window. Then per frame: read the
// inputs (BML that is due, the background frame), update the scene, track (the camera's
// view and how far it can be trusted), render, write (a PNG headless, the window else).
#pragma once
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "augmentation_restore.hpp"
#include "authoring_window.hpp"
#include "frame_inputs.hpp"
#include "prt_lighting.hpp"
#include "render_args.hpp"

#include "marionette/bml/realizer.hpp"
#include "marionette/bml/timed_files.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/render/background_renderer.hpp"
#include "marionette_ar/render/character_renderer.hpp"
#include "marionette_ar/contact_shadow.hpp"
#include "marionette_ar/render/contact_shadow_renderer.hpp"
#include "marionette_ar/render/gl_context.hpp"
#include "marionette_ar/render/occlusion_mask_texture.hpp"
#include "marionette_ar/render/render_target.hpp"

namespace marionette::ar {

class ArApp {
 public:
  // What frame() returns besides an exit code (> 0, its error printed).
  static constexpr int kNextFrame = 0;
  static constexpr int kQuit = -1;  // the authoring window asked to quit: finish() as usual

  explicit ArApp(RenderArgs args);
  ~ArApp();
  ArApp(const ArApp&) = delete;
  ArApp& operator=(const ArApp&) = delete;

  // 0, or the exit code to stop with (the error printed).
  [[nodiscard]] int setUp();
  // Frames left to draw (headless: --frames or 5 s; a window: until it closes).
  [[nodiscard]] bool wantsFrame() const;
  // One frame: read inputs, update the scene, track, render, write.
  [[nodiscard]] int frame();
  // The last screenshot, the summary lines (and --json's report); the exit status.
  [[nodiscard]] int finish();

 private:
  struct LogListener : SceneListener {  // the runtime's warnings, to stderr
    void onLog(LogLevel level, std::string_view message) override;
  };

  [[nodiscard]] int readArSceneFile();
  [[nodiscard]] int loadScene();
  void uploadModels();
  [[nodiscard]] int setUpPrt();
  [[nodiscard]] int setUpDrawing();

  [[nodiscard]] double frameStep();
  void sendDueBml(double step);
  void updateScene(double step);
  [[nodiscard]] int readBackground();
  void track();
  void render();
  // Where each character stands this frame (its anchor and transform buffer), its palette uploaded.
  void placeCharacters();
  // Contact shadows: each placed character's caster and shadow map (before the frame's target is
  // bound), then its catcher over the background.
  void renderShadowMaps(float opacity);
  void drawContactShadows();
  void drawCharacters(float opacity);
  // This frame's occlusion mask uploaded; null when nothing hides the target.
  [[nodiscard]] const OcclusionDraw* updateOcclusion();
  void drawTrackingBadge();
  [[nodiscard]] int write();
  [[nodiscard]] int writeImageOrFail(const std::string& path);

  RenderArgs args_;
  std::FILE* info_ = stdout;  // with --json, stdout holds the report alone
  ArScene ar_;
  AugmentationRestore restore_;
  FrameInputs inputs_;
  std::unique_ptr<GlContext> gl_;
  Scene scene_;
  LogListener log_;
  SceneLoadResult loaded_;
  std::unique_ptr<bml::Realizer> realizer_;
  std::unique_ptr<bml::TimedFiles> bmlFiles_;
  int bmlErrors_ = 0;

  // GPU models, one per asset; a pose (palette texture) per character.
  std::map<const Asset*, std::unique_ptr<CharacterModel>> models_;
  std::vector<std::unique_ptr<CharacterPose>> poses_;
  std::vector<const CharacterModel*> drawn_;
  std::vector<glm::mat4> worlds_;  // this frame's world matrix of each character (placeCharacters())
  std::vector<char> placed_;       // drawn this frame
  // PRT: the transfer of each distinct asset, per character its CPU light and GPU buffers,
  // all sized in setUp(): the frame loop allocates nothing.
  bool usePrt_ = false;
  std::map<const Asset*, std::unique_ptr<PrtAsset>> prtAssets_;
  std::vector<std::unique_ptr<PrtCharacterLight>> prtLights_;
  std::vector<std::unique_ptr<PrtIrradiance>> prtBuffers_;
  std::unique_ptr<prt::ShRotation> shRotation_;
  double prtRelightMs_ = 0.0, prtUploadMs_ = 0.0;
  long prtUpdates_ = 0;

  ShaderProgram characterProgram_;
  BackgroundRenderer background_;
  RenderTarget target_;
  std::unique_ptr<AuthoringWindow> authoring_;
  Lighting lighting_;
  Image8 frameImage_;
  // Contact shadows (ar_.contactShadows): the light's fit, each character's joints in the world
  // (sized in setUp() to the largest skeleton).
  std::unique_ptr<ContactShadowRenderer> contactShadows_;
  ShadowLight shadowLight_;
  std::vector<glm::vec3> jointWorld_;
  std::vector<ShadowCaster> casters_;       // per character, this frame
  std::vector<ContactShadowDraw> shadows_;  // per character, this frame (its contacts point into casters_)
  double shadowMs_ = 0.0;
  long shadowDraws_ = 0;
  // Occlusion over the target (ar_.occlusion): the mask of the frame, frames it hid something in.
  std::unique_ptr<OcclusionMaskTexture> occlusionTexture_;
  OcclusionDraw occlusionDraw_;
  long occludedFrames_ = 0, occlusionFrames_ = 0;
  // Headless, the frame's GL work timed by GL_TIMESTAMP queries (read after the frame's read-back,
  // which waits for it anyway): the whole frame, and the contact shadows' passes within it.
  enum Stamp { kFrameStart, kMapsEnd, kCatchersStart, kCatchersEnd, kFrameEnd, kStamps };
  unsigned stamps_[kStamps] = {};
  bool stamped_ = false;
  double gpuFrameMs_ = 0.0, gpuShadowMs_ = 0.0;
  long gpuFrames_ = 0;
  void stamp(Stamp which);
  void readStamps();

  double dt_ = 1.0 / 30.0;
  long frames_ = -1;
  long frame_ = 0;
  double cpuMs_ = 0.0;
  std::chrono::steady_clock::time_point last_;
  // This frame's camera and tracking state (track()).
  CameraView view_;
  TrackingStateReport tracking_;
  bool tracked_ = false;
};

}  // namespace marionette::ar
