#include "ar_app.hpp"

#include <epoxy/gl.h>
#include "example_synthesizer.hpp"
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "augmentation_scene.hpp"

namespace marionette::ar {

namespace {

// The window's back buffer as an image (rows top to bottom), after the panel is drawn.
void readWindow(int width, int height, Image8& out) {
  out.width = width;
  out.height = height;
  out.channels = 3;
  out.pixels.resize(static_cast<std::size_t>(width) * height * 3);
  std::vector<std::uint8_t> rows(out.pixels.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(rows.data() + static_cast<std::size_t>(height - 1 - y) * row, row, out.pixels.data() + y * row);
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void ArApp::LogListener::onLog(LogLevel level, std::string_view message) {
  if (level == LogLevel::Info) return;
  std::fprintf(stderr, "marionette-ar: %s: %.*s\n", level == LogLevel::Error ? "error" : "warning",
               static_cast<int>(message.size()), message.data());
}

ArApp::ArApp(RenderArgs args) : args_(std::move(args)), info_(args_.json ? stderr : stdout) {}
ArApp::~ArApp() {
  if (stamps_[0] && gl_) glDeleteQueries(kStamps, stamps_);
}

// ---- set-up ---------------------------------------------------------------------------------

int ArApp::setUp() {
  if (const int code = readArSceneFile()) return code;
  // Inputs that need no GL: the environment's lighting, the background source.
  Diagnostics inputs;
  const bool inputsLoaded = inputs_.load(ar_, inputs, args_.headless);
  std::fputs(inputs.format().c_str(), stderr);  // the error, or the warnings
  if (!inputsLoaded) return 2;
  restore_.mark("environment_and_background");

  Diagnostics glProblems;
  gl_ = GlContext::create({ar_.width, ar_.height, !args_.headless, "marionette-ar: " + args_.scene}, glProblems);
  if (!gl_) {
    std::fprintf(stderr, "marionette-ar: %s", glProblems.format().c_str());
    return 3;
  }
  std::fprintf(info_, "marionette-ar: %s\n", gl_->rendererName().c_str());
  restore_.mark("gl_context");
  if (const int code = loadScene()) return code;
  uploadModels();
  if (const int code = setUpPrt()) return code;
  return setUpDrawing();
}

// The AR scene file, an augmentation to restore, and the command line's overrides.
int ArApp::readArSceneFile() {
  const Diagnostics arDiag = readArScene(args_.scene, ar_);
  std::fputs(arDiag.format().c_str(), stderr);
  if (!arDiag.ok()) return 2;
  if (!args_.restore.empty()) {
    std::string truth = args_.truth;
    const std::filesystem::path sequenceTruth = std::filesystem::path(ar_.background.file) / "truth.csv";
    if (truth.empty() && ar_.background.kind == ArBackground::Kind::Sequence &&
        std::filesystem::is_regular_file(sequenceTruth))
      truth = sequenceTruth.string();
    (void)restore_.load(args_.restore, ar_, truth);
  }
  restore_.mark("main_and_augmentation");
  if (args_.width) ar_.width = args_.width;
  if (args_.height) ar_.height = args_.height;
  if (args_.exposure >= 0.0f) ar_.environment.exposure = args_.exposure;
  ArPrt& prt = ar_.environment.prt;
  if (!args_.prtMode.empty()) (void)parsePrtMode(args_.prtMode, prt.mode);
  if (args_.prtBands) prt.bands = args_.prtBands;
  if (args_.prtRays) prt.rays = args_.prtRays;
  if (!args_.prtCache.empty()) prt.cache = args_.prtCache;
  usePrt_ = !ar_.environment.file.empty() && prt.mode != PrtMode::Off;
  return 0;
}

// The middleware: the scene file's characters, the realizer and the timed BML files.
int ArApp::loadScene() {
  examples::useExampleSynthesizer(scene_.speech());
  scene_.addListener(&log_);
  // The renderer plays no sound; --audio-dir writes each spoken line as a WAV, named by
  // the listener's onSpeech with its scene start time, for an engine or editor to play.
  if (!args_.audioDir.empty()) scene_.speech().setAudioDirectory(args_.audioDir);
  loaded_ = loadSceneFile(ar_.scene, scene_, {.loadMeshes = true, .isolateThirdPartyParsers = true});
  std::fputs(loaded_.diagnostics.format().c_str(), stderr);
  if (!loaded_.ok()) return 2;
  restore_.mark("scene_and_characters");
  realizer_ = std::make_unique<bml::Realizer>(scene_);
  realizer_->setForwardWarningsToScene(false);
  // A window keeps its frame rate (speech is said off the frame path); frames
  // written headless step a fixed clock and must come out the same every run.
  if (args_.headless) realizer_->setSpeechSynthesis(bml::Realizer::SpeechSynthesis::Inline);
  restore_.bind(scene_, loaded_.bml);
  bml::useSceneDialects(*realizer_, loaded_);
  bmlFiles_ = std::make_unique<bml::TimedFiles>(*realizer_, loaded_.bml);
  return 0;
}

// A GPU model per distinct asset, a pose (palette texture) per character.
void ArApp::uploadModels() {
  for (const auto& c : scene_.characters()) {
    const Asset* asset = loaded_.assetOf(c->name()).get();
    auto& model = models_[asset];
    if (!asset) {
      std::fprintf(stderr, "marionette-ar: character '%s' is not drawn: it was not loaded from the scene file\n",
                   c->name().c_str());
    } else if (!model) {
      Diagnostics uploaded;
      auto m = std::make_unique<CharacterModel>();
      if (m->upload(*asset, uploaded)) model = std::move(m);
      std::fputs(uploaded.format().c_str(), stderr);  // the textures not used; why nothing is drawn
      if (!model) std::fprintf(stderr, "marionette-ar: character '%s' is not drawn\n", c->name().c_str());
    }
    poses_.push_back(std::make_unique<CharacterPose>(c->skeleton()));
    drawn_.push_back(model.get());
    worlds_.emplace_back(1.0f);
    placed_.push_back(0);
  }
}

// The transfer of each distinct asset (from the cache when it is there), then per character
// the CPU light and its GPU buffers.
int ArApp::setUpPrt() {
  const std::size_t n = scene_.characters().size();
  prtLights_.resize(n);
  prtBuffers_.resize(n);
  const ArPrt& settings = ar_.environment.prt;
  if (!usePrt_) {
    std::fprintf(info_, "marionette-ar: prt off (%s): no precompute, SH9 light per fragment\n",
                 ar_.environment.file.empty() ? "no environment, neutral sky light" : "environment.prt.mode off");
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      if (!drawn_[i]) continue;
      const Character& c = *scene_.characters()[i];
      const Asset& asset = *loaded_.assetOf(c.name());  // drawn: it has one
      auto& prtAsset = prtAssets_[&asset];
      if (!prtAsset) {
        Diagnostics d;
        auto a = std::make_unique<PrtAsset>();
        const bool ok = loadPrtAsset(asset, c.rig(), settings, ar_.path, *a, d);
        std::fputs(d.format().c_str(), stderr);
        if (!ok) return 2;
        const std::string file = std::filesystem::path(asset.sourcePath).filename().string();
        std::fprintf(info_, "marionette-ar: %s\n", a->describe(file).c_str());
        std::fflush(info_);
        prtAsset = std::move(a);
      }
      prtLights_[i] = std::make_unique<PrtCharacterLight>(*prtAsset);
      prtBuffers_[i] = std::make_unique<PrtIrradiance>(*drawn_[i], prtAsset->primitiveVertexOffset, prtAsset->vertexCount);
      if (prtBuffers_[i]->mismatches() > 0)
        std::fprintf(stderr, "marionette-ar: warning: character '%s': %zu primitives do not match the transfer mesh; "
                     "they keep the SH9 light\n", c.name().c_str(), prtBuffers_[i]->mismatches());
    }
  }
  shRotation_ = std::make_unique<prt::ShRotation>(usePrt_ ? settings.bands : 2);
  restore_.mark("gpu_models_and_prt");
  return 0;
}

// Shaders, the offscreen target, the authoring window; the frame clock.
int ArApp::setUpDrawing() {
  if (Diagnostics gpu; !characterProgram_.build("character.vert", "character.frag", gpu) || !background_.create(gpu) ||
                       !target_.create(ar_.width, ar_.height, 4, gpu)) {
    std::fprintf(stderr, "marionette-ar: %s", gpu.format().c_str());
    return 3;
  }
  if (inputs_.hasEnvironment())
    background_.setEnvironment(inputs_.environmentWidth(), inputs_.environmentHeight(), inputs_.environmentPixels());
  restore_.mark("shaders_and_targets");
  // The authoring window: a session on the scene's tracker, its characters measured at rest.
  if (!args_.author.empty()) {
    Diagnostics authoring;
    std::optional<AuthoringSession> started = startAuthoring(ar_, scene_, loaded_, authoring);
    if (!started) {
      std::fputs(authoring.format().c_str(), stderr);
      return 2;
    }
    authoring_ = std::make_unique<AuthoringWindow>(std::move(*started), ar_.authoringBml, args_.author);
    if (!authoring_->init(gl_->window(), authoring) ||
        (!args_.inputScript.empty() && !authoring_->loadInputScript(args_.inputScript, authoring))) {
      std::fputs(authoring.format().c_str(), stderr);
      return 2;
    }
  }
  if (!args_.outDir.empty()) std::filesystem::create_directories(args_.outDir);
  dt_ = 1.0 / ar_.fps;
  frames_ = args_.frames > 0 ? args_.frames : (args_.headless ? static_cast<long>(5.0 * ar_.fps) : -1);
  lighting_.irradianceSH = inputs_.irradianceSH();
  lighting_.exposure = ar_.environment.exposure;
  if (ar_.contactShadows.enabled) {
    Diagnostics gpu;
    contactShadows_ = std::make_unique<ContactShadowRenderer>();
    casters_.resize(scene_.characters().size());
    shadows_.resize(scene_.characters().size());
    if (!contactShadows_->create(scene_.characters().size(), gpu)) {
      std::fprintf(stderr, "marionette-ar: %s", gpu.format().c_str());
      return 3;
    }
    std::size_t joints = 0;
    for (const auto& c : scene_.characters()) joints = std::max(joints, c->transformBuffer().jointCount());
    jointWorld_.resize(joints);
    shadowLight_ = dominantLight(lighting_.irradianceSH);
    std::fprintf(info_, "marionette-ar: contact shadows: light from (%.2f, %.2f, %.2f), %.0f %% of the floor's light direct\n",
                 shadowLight_.towardLight.x, shadowLight_.towardLight.y, shadowLight_.towardLight.z,
                 100.0 * shadowLight_.directFraction);
  }
  if (inputs_.occlusionOn())
    std::fprintf(info_, "marionette-ar: occlusion over the target: on (%s)\n",
                 ar_.occlusion.masks.empty() ? "the tracker's mask" : ar_.occlusion.masks.c_str());
  last_ = std::chrono::steady_clock::now();
  // The viewer is the scene's "camera" object: scripts gaze and point at the user through it.
  scene_.setObject("camera", inputs_.viewerBeforeFirstFrame(0.0));
  return 0;
}

// ---- one frame ------------------------------------------------------------------------------

bool ArApp::wantsFrame() const {
  if (!args_.headless && gl_->shouldClose()) return false;
  return frames_ < 0 || frame_ < frames_;
}

int ArApp::frame() {
  const double step = frameStep();
  const auto cpuStart = std::chrono::steady_clock::now();
  sendDueBml(step);
  updateScene(step);
  cpuMs_ += millisecondsSince(cpuStart);
  if (frame_ == 0) restore_.mark("frame0_bml_and_scene");
  // The background frame first: a tracked camera's pose comes from it.
  if (const int code = readBackground()) return code;
  if (frame_ == 0) restore_.mark("frame0_background_and_tracking");
  track();
  render();
  const int status = write();
  ++frame_;
  return status;
}

// Headless steps at the scene's fps exactly; a window follows the wall clock (at most 0.1 s a
// frame), unless a script drives it: then frame N shows camera frame N, as a replay does.
double ArApp::frameStep() {
  if (args_.headless || !args_.inputScript.empty()) return dt_;
  const auto now = std::chrono::steady_clock::now();
  const double step = std::min(0.1, std::chrono::duration<double>(now - last_).count());
  last_ = now;
  return step;
}

void ArApp::sendDueBml(double step) {
  bmlFiles_->sendDue(scene_.time() + (frame_ == 0 ? 0.0 : step), [&](const Diagnostic& d) {
    std::fprintf(stderr, "%s\n", d.format().c_str());
    bmlErrors_ += d.severity == Severity::Error ? 1 : 0;
  });
}

void ArApp::updateScene(double step) {
  scene_.update(frame_ == 0 ? 0.0 : step);
  realizer_->update();
}

int ArApp::readBackground() {
  const ArBackground::Kind kind = inputs_.backgroundKind();
  if (kind == ArBackground::Kind::Environment || kind == ArBackground::Kind::Color) return 0;
  Diagnostics decoding;  // a frame that cannot be decoded: said, and the previous frame stays
  const Image8* image = inputs_.backgroundFrame(scene_.time(), decoding);
  if (!decoding.items.empty()) std::fputs(decoding.format().c_str(), stderr);
  if (image) background_.setImage(*image);
  return 0;
}

void ArApp::track() {
  view_ = inputs_.camera(scene_.time(), ar_.width, ar_.height);
  inputs_.estimateLight(view_, scene_.time(), ar_.width, ar_.height);
  if (inputs_.lightFromCamera()) {  // this frame's light: the characters, their shadows
    lighting_.irradianceSH = inputs_.irradianceSH();
    lighting_.cameraCurve = true;
    shadowLight_ = dominantLight(lighting_.irradianceSH);
  }
  // Followed from the next frame; a tracked camera without a pose keeps the last.
  if (view_.posed) scene_.setObject("camera", glm::vec3(glm::inverse(view_.view)[3]));
  tracked_ = inputs_.trackingState(tracking_);
  if (tracked_ && (tracking_.changed || frame_ == 0))
    std::fprintf(info_, "marionette-ar: %s %s at %.3f s (frame %ld)\n", tracking_.replayed ? "replayed pose" : "tracking",
                 trackingStateName(tracking_.state).data(), scene_.time(), frame_);
}

void ArApp::stamp(Stamp which) {
  if (!args_.headless) return;
  if (!stamps_[0]) glGenQueries(kStamps, stamps_);
  glQueryCounter(stamps_[which], GL_TIMESTAMP);
  if (which == kCatchersEnd) stamped_ = true;
}

void ArApp::readStamps() {
  if (!args_.headless || !stamps_[0]) return;
  GLuint64 t[kStamps] = {};
  for (int i = 0; i < kStamps; ++i) glGetQueryObjectui64v(stamps_[i], GL_QUERY_RESULT, &t[i]);
  gpuFrameMs_ += static_cast<double>(t[kFrameEnd] - t[kFrameStart]) * 1e-6;
  if (stamped_)
    gpuShadowMs_ += static_cast<double>((t[kMapsEnd] - t[kFrameStart]) + (t[kCatchersEnd] - t[kCatchersStart])) * 1e-6;
  stamped_ = false;
  ++gpuFrames_;
}

void ArApp::render() {
  const bool charactersShown = !args_.hideCharacters && inputs_.charactersVisible(scene_.time());
  const float opacity = inputs_.characterOpacity(scene_.time());
  stamp(kFrameStart);
  if (charactersShown) {
    placeCharacters();
    if (contactShadows_) renderShadowMaps(opacity);
  }
  stamp(kMapsEnd);
  target_.bind();
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  switch (inputs_.backgroundKind()) {
    case ArBackground::Kind::Environment:
      background_.drawEnvironment(glm::inverse(view_.projection * view_.view), lighting_.exposure,
                                  glm::radians(ar_.environment.rotationDegrees));
      break;
    case ArBackground::Kind::Color:
      background_.drawFlat(ar_.background.color);
      break;
    default:
      background_.drawImage(static_cast<float>(ar_.width) / static_cast<float>(ar_.height));
  }
  lighting_.occlusion = charactersShown ? updateOcclusion() : nullptr;
  if (charactersShown) {
    if (contactShadows_) {
      stamp(kCatchersStart);
      drawContactShadows();
      stamp(kCatchersEnd);
    }
    drawCharacters(opacity);
  }
  stamp(kFrameEnd);
  if (tracked_ && !tracking_.replayed) drawTrackingBadge();
  if (restore_.active()) {  // a verified pose, the restored characters drawn with it
    const bool verified = tracked_ && tracking_.state == TrackingState::Tracking && charactersShown;
    if (verified && restore_.firstRegisteredFrame() < 0) glFinish();  // drawn, not only queued
    restore_.frameDrawn(frame_, scene_.time(), verified, view_.viewInDouble);
  }
}

void ArApp::placeCharacters() {
  for (std::size_t i = 0; i < scene_.characters().size(); ++i) {
    placed_[i] = 0;
    if (!drawn_[i] || !restore_.drawn(i)) continue;
    const Character& c = *scene_.characters()[i];
    glm::mat4 anchor = restore_.anchor(i);
    if (authoring_ && !authoring_->placement(c.name(), anchor)) continue;  // not placed yet
    worlds_[i] = anchor * c.transformBuffer().worldMatrix();
    poses_[i]->update(c.transformBuffer());
    placed_[i] = 1;
  }
}

// Before the frame's target: where each character stands, the light's view of it, its map.
void ArApp::renderShadowMaps(float opacity) {
  const auto start = std::chrono::steady_clock::now();
  const ContactShadowSettings& settings = ar_.contactShadows;
  const bool cameraAboveFloor = glm::inverse(view_.view)[3].y > 0.0f;  // below it, the floor shows no shadow
  const float tanSoftness = std::tan(glm::radians(settings.softnessDegrees));
  for (std::size_t i = 0; i < scene_.characters().size(); ++i) {
    shadows_[i].strength = 0.0f;
    if (!placed_[i] || !cameraAboveFloor) continue;
    const glm::mat4& world = worlds_[i];
    const std::span<const glm::mat4> model = scene_.characters()[i]->transformBuffer().modelMatrices();
    const std::size_t n = std::min(model.size(), jointWorld_.size());
    for (std::size_t j = 0; j < n; ++j) jointWorld_[j] = glm::vec3(world * model[j][3]);
    casters_[i] = shadowCaster(std::span<const glm::vec3>(jointWorld_.data(), n), shadowLight_.towardLight);
    const ShadowCaster& caster = casters_[i];
    if (!caster.valid) continue;
    ContactShadowDraw& draw = shadows_[i];
    draw.lightViewProjection = lightViewProjection(caster, shadowLight_.towardLight);
    draw.centre = caster.catcherCentre;
    draw.axis = caster.catcherAxis;
    draw.halfSize = glm::vec2(caster.catcherHalfLength, caster.catcherHalfWidth);
    draw.contacts = std::span<const glm::vec4>(caster.contacts.data(), caster.contactCount);
    draw.hasDirect = shadowLight_.directFraction > 0.0f;
    draw.tanSoftness = tanSoftness;
    draw.directFraction = shadowLight_.directFraction;
    draw.ambientFraction = shadowLight_.ambientFraction;
    draw.strength = settings.strength * std::clamp(opacity, 0.0f, 1.0f);
    if (draw.hasDirect && draw.strength > 0.0f)
      contactShadows_->renderMap(i, *drawn_[i], *poses_[i], world, draw.lightViewProjection);
  }
  shadowMs_ += millisecondsSince(start);
}

// Over the background, before the characters: each one's shadow on the floor (y = 0).
void ArApp::drawContactShadows() {
  const auto start = std::chrono::steady_clock::now();
  const glm::mat4 viewProjection = view_.projection * view_.view;
  for (std::size_t i = 0; i < scene_.characters().size(); ++i)
    if (placed_[i]) {
      shadows_[i].occlusion = lighting_.occlusion;
      contactShadows_->drawCatcher(i, viewProjection, shadows_[i]);
    }
  shadowMs_ += millisecondsSince(start);
  ++shadowDraws_;
}

void ArApp::drawCharacters(float opacity) {
  glEnable(GL_DEPTH_TEST);
  for (std::size_t i = 0; i < scene_.characters().size(); ++i) {
    if (!placed_[i]) continue;
    const glm::mat4& world = worlds_[i];
    if (prtLights_[i]) {
      const auto t0 = std::chrono::steady_clock::now();
      prtLights_[i]->relight(inputs_.radianceSH(), world, *shRotation_);
      const auto t1 = std::chrono::steady_clock::now();
      prtBuffers_[i]->upload(prtLights_[i]->irradiance());
      prtRelightMs_ += std::chrono::duration<double, std::milli>(t1 - t0).count();
      prtUploadMs_ += millisecondsSince(t1);
      ++prtUpdates_;
    }
    drawCharacter(characterProgram_, *drawn_[i], *poses_[i], world, view_.projection * view_.view, lighting_,
                  prtBuffers_[i].get(), opacity);
  }
}

const OcclusionDraw* ArApp::updateOcclusion() {
  if (!inputs_.occlusionOn()) return nullptr;
  OcclusionFrame mask;
  Diagnostics reading;  // a mask file that cannot be read: said, and nothing is hidden this frame
  const bool have = inputs_.occlusionMask(mask, reading);
  if (!reading.items.empty()) std::fputs(reading.format().c_str(), stderr);
  ++occlusionFrames_;
  if (!have || !(mask.hiddenShare > 0.0)) return nullptr;
  if (!occlusionTexture_) occlusionTexture_ = std::make_unique<OcclusionMaskTexture>();
  occlusionTexture_->upload(mask.width, mask.height, mask.pixels, mask.stride);
  GLint viewport[4] = {};
  glGetIntegerv(GL_VIEWPORT, viewport);
  occlusionDraw_.texture = occlusionTexture_->texture();
  occlusionDraw_.screenToImage = coverRect(float(mask.frameWidth) / float(mask.frameHeight),
                                           float(viewport[2]) / float(std::max(1, viewport[3])));
  occlusionDraw_.imageToMask = mask.imageToMask;
  occlusionDraw_.viewport = glm::vec2(float(viewport[2]), float(viewport[3]));
  occlusionDraw_.heightLimit = ar_.occlusion.heightLimit;
  ++occludedFrames_;
  return &occlusionDraw_;
}

// The tracking state in the top-left corner: green, amber, red.
void ArApp::drawTrackingBadge() {
  const glm::vec3 badge = tracking_.state == TrackingState::Tracking  ? glm::vec3(0.1f, 0.8f, 0.2f)
                          : tracking_.state == TrackingState::Limited ? glm::vec3(0.95f, 0.7f, 0.1f)
                                                                      : glm::vec3(0.9f, 0.1f, 0.1f);
  glEnable(GL_SCISSOR_TEST);
  glScissor(8, ar_.height - 24, 16, 16);
  glClearColor(badge.r, badge.g, badge.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
}

int ArApp::writeImageOrFail(const std::string& path) {
  Diagnostics written;
  if (writeImage(path, frameImage_, written)) return 0;
  std::fputs(written.format().c_str(), stderr);
  return 2;
}

// Headless: frame_NNNN.png. A window: shown, with the authoring panel and its screenshot.
int ArApp::write() {
  if (args_.headless) {
    target_.read(frameImage_);
    readStamps();
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04ld.png", frame_);
    return writeImageOrFail((std::filesystem::path(args_.outDir) / name).string());
  }
  int w = 0, h = 0;
  gl_->framebufferSize(w, h);
  target_.present(w, h);
  if (authoring_) {
    lighting_.exposure = std::exp2(authoring_->session().augmentation().exposureEv);
    const AuthoringView av{view_.view, view_.projection, ar_.width, ar_.height,
                           tracked_ && tracking_.state != TrackingState::Lost};
    authoring_->frame(frame_, av, tracked_ ? trackingStateName(tracking_.state).data() : "not tracked", w, h);
    if (!args_.screenshot.empty() && (authoring_->quitRequested() || frame_ + 1 == frames_)) {
      readWindow(w, h, frameImage_);  // the window, with the panel
      if (const int code = writeImageOrFail(args_.screenshot)) return code;
      std::fprintf(info_, "marionette-ar: screenshot %s\n", args_.screenshot.c_str());
    }
  }
  gl_->swapAndPoll();
  return authoring_ && authoring_->quitRequested() ? kQuit : kNextFrame;
}

// ---- the end --------------------------------------------------------------------------------

int ArApp::finish() {
  if (!args_.screenshot.empty() && !authoring_) {
    target_.read(frameImage_);
    if (const int code = writeImageOrFail(args_.screenshot)) return code;
    std::fprintf(info_, "marionette-ar: screenshot %s\n", args_.screenshot.c_str());
  }
  const double msPerFrame = frame_ > 0 ? cpuMs_ / static_cast<double>(frame_) : 0.0;
  std::fprintf(info_, "marionette-ar: %ld frames of %dx%d, %.3f s of scene time, middleware %.3f ms per frame\n",
               frame_, ar_.width, ar_.height, scene_.time(), msPerFrame);
  if (prtUpdates_ > 0)
    std::fprintf(info_, "marionette-ar: prt per character per frame: relight %.3f ms, upload %.3f ms (%ld updates)\n",
                 prtRelightMs_ / static_cast<double>(prtUpdates_), prtUploadMs_ / static_cast<double>(prtUpdates_),
                 prtUpdates_);
  if (inputs_.lightEstimateMs() > 0.0)
    std::fprintf(info_, "marionette-ar: light from the camera: %.3f ms per camera frame, %.0f %% of the sphere seen\n",
                 inputs_.lightEstimateMs(), 100.0 * inputs_.lightSeenFraction());
  if (shadowDraws_ > 0)
    std::fprintf(info_, "marionette-ar: contact shadows: %.3f ms per frame submitting the passes\n",
                 shadowMs_ / static_cast<double>(shadowDraws_));
  if (occlusionFrames_ > 0)
    std::fprintf(info_, "marionette-ar: occlusion over the target: something hid it in %ld of %ld frames; the mask %.3f ms per frame\n",
                 occludedFrames_, occlusionFrames_, inputs_.occlusionMs());
  if (gpuFrames_ > 0) {  // the GL work of a frame (on llvmpipe: the CPU's rasterizer threads)
    const double frameMs = gpuFrameMs_ / static_cast<double>(gpuFrames_);
    const double shadowMs = gpuShadowMs_ / static_cast<double>(gpuFrames_);
    const double estimateMs = inputs_.lightEstimateMs();
    std::fprintf(info_, "marionette-ar: GL work per frame %.3f ms, of it contact shadows %.3f ms; light estimate %.3f ms (CPU); "
                 "shadows and estimate %.1f %% of the frame\n", frameMs, shadowMs, estimateMs,
                 100.0 * (shadowMs + estimateMs) / std::max(frameMs + estimateMs, 1e-9));
  }
  TrackingStateReport tracking;
  if (inputs_.trackingState(tracking) && tracking.replayed)
    std::fprintf(info_, "marionette-ar: replayed poses: %ld of %ld frames with a pose\n", tracking.posed, tracking.frames);
  else if (inputs_.trackingState(tracking))
    std::fprintf(info_, "marionette-ar: tracking: %ld of %ld camera frames with a pose, tracker %.2f ms per frame median\n",
                 tracking.posed, tracking.frames, inputs_.trackingMedianMs());
  if (args_.headless) std::fprintf(info_, "marionette-ar: frames in %s\n", args_.outDir.c_str());
  if (!args_.restore.empty()) {
    if (restore_.active())
      std::fprintf(info_, "marionette-ar: restored %s: first registered frame %ld at %.3f s after launch\n",
                   args_.restore.c_str(), restore_.firstRegisteredFrame(), restore_.firstRegisteredSeconds());
    if (args_.json) std::printf("%s\n", restore_.json(frame_).c_str());
    if (!restore_.diagnostics().ok()) return 1;
  } else if (args_.json) {
    std::printf("{\"frames\": %ld, \"scene_seconds\": %.6f, \"middleware_ms_per_frame\": %.6f}\n", frame_,
                scene_.time(), msPerFrame);
  }
  return bmlErrors_ > 0 ? 1 : 0;
}

}  // namespace marionette::ar
