// marionette-ar: the reference AR renderer. Embeds the middleware as an engine
// would (scene, BML realizer, the bridge's palettes) and draws its characters,
// skinned and lit by the environment, over a camera background.
//
//   marionette-ar SCENE.json [--headless] [--frames N] [--out DIR] [--screenshot FILE]
//                 [--exposure E] [--width W] [--height H] [--hide-characters] [--audio-dir DIR]
//                 [--prt shadowed|unshadowed|off] [--prt-bands N] [--prt-rays R] [--prt-cache DIR]
//                 [--restore AUGMENTATION.json [--truth CSV]] [--json]
//   marionette-ar calibrate ... | track ...   (camera tracking: tracking_commands.hpp)
//   marionette-ar author SCENE.json --actions ACTIONS.json -o AUGMENTATION.json  (author_command.hpp)
//   marionette-ar [COMMAND] --help | --version   (ar_cli.hpp)
//
// Headless renders offscreen into DIR/frame_0000.png ... (still needs an X
// display: run it under xvfb-run; docs/ar-renderer.md).
#include <epoxy/gl.h>
#include "example_synthesizer.hpp"
#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "ar_cli.hpp"
#include "ar_scene_file.hpp"
#include "augmentation_restore.hpp"
#include "augmentation_scene.hpp"
#include "authoring_window.hpp"
#include "frame_inputs.hpp"
#include "prt_lighting.hpp"
#if MARIONETTE_AR_HAS_TRACKING
#include "author_command.hpp"
#include "tracking_commands.hpp"
#endif
#include "marionette/bml/realizer.hpp"
#include "marionette/bml/timed_files.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/render/background_renderer.hpp"
#include "marionette_ar/render/character_renderer.hpp"
#include "marionette_ar/render/gl_context.hpp"
#include "marionette_ar/render/render_target.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

struct Args {
  std::string scene, outDir, screenshot, audioDir, restore, truth, author, inputScript;
  bool headless = false, hideCharacters = false, json = false, help = false, version = false;
  long frames = -1;  // headless default: 5 s of scene time
  float exposure = -1.0f;
  int width = 0, height = 0;
  std::string prtMode, prtCache;  // empty: as the scene file says
  int prtBands = 0, prtRays = 0;  // 0: as the scene file says
};

// To stdout for --help (exit 0), to stderr after a bad command line (exit 2).
int usage(std::FILE* to = stderr) {
  std::fprintf(to,
               "usage: marionette-ar SCENE.json [--headless] [--frames N] [--out DIR] [--screenshot FILE]\n"
               "                     [--exposure E] [--width W] [--height H] [--hide-characters] [--audio-dir DIR]\n"
               "                     [--prt shadowed|unshadowed|off] [--prt-bands N] [--prt-rays R] [--prt-cache DIR]\n"
               "                     [--restore AUGMENTATION.json [--truth CSV]] [--json]\n"
               "                     [--author OUT.json [--input-script EVENTS.json]]\n"
#if MARIONETTE_AR_HAS_TRACKING
               "       marionette-ar calibrate [--board COLSxROWS] [--square M] IMAGES... -o CAMERA.yml [--json]\n"
               "       marionette-ar track --camera CAMERA.yml --images PATTERN|FOLDER|IMAGE|VIDEO ...\n"
               "       marionette-ar author SCENE.json --actions ACTIONS.json -o AUGMENTATION.json [--json]\n"
               "       marionette-ar COMMAND --help   a command's options\n"
#endif
               "       marionette-ar --help | --version\n"
               "  The renderer draws SCENE.json's characters over its camera background (docs/ar-renderer.md).\n"
               "  --headless       render offscreen into --out DIR (frame_0000.png ...; still needs an X display)\n"
               "  --frames N       frames to run (default: 5 s of scene time headless, until closed in a window)\n"
               "  --out DIR        where --headless writes the frames\n"
               "  --screenshot F   the last frame (with --author: the window, with its panel) as an image\n"
               "  --exposure E     the environment's exposure (default: the scene's)\n"
               "  --width W, --height H  the frame size (default: the scene's)\n"
               "  --hide-characters  the background alone\n"
               "  --audio-dir DIR  each spoken line as a WAV, named by its scene start time\n"
               "  --restore FILE   put an authored augmentation back (docs/authoring.md): its map, tracker,\n"
               "                   exposure, environment, characters' placements and BML\n"
               "  --author OUT     the authoring window (docs/authoring.md): place, move, turn, size the scene's\n"
               "                   characters on the tracked floor; Save writes OUT and OUT's .actions.json\n"
               "  --input-script F synthetic mouse and key events for the authoring window (tests)\n"
               "  --truth CSV      exact camera poses of the frames, to measure the restored placement's error\n"
               "                   (default: truth.csv in a sequence folder, when it is there)\n"
               "  --json           print a JSON report (with --restore: first_registered_frame,\n"
               "                   launch_to_registered_seconds, placement_error_m, placement_error_deg)\n"
               "  --prt MODE       PRT lighting of the characters (default: the scene's environment.prt.mode,\n"
               "                   shadowed); off: the environment's SH9 irradiance per fragment\n"
               "  --prt-bands N    SH bands of the transfer, 2..8 (default 4)\n"
               "  --prt-rays R     visibility rays per vertex when shadowed, 1..65536 (default 1024)\n"
               "  --prt-cache DIR  where transfers are cached (default $MARIONETTE_PRT_CACHE,\n"
               "                   else ~/.cache/marionette/prt)\n"
               "  --help, -h       this help; --version: the version\n"
               "  PRT needs an \"environment\" in the scene; without one the light is a neutral grey sky.\n"
               "  Exit status: 0 success, 1 errors in the scene's BML or the restore, 2 bad input, 3 no OpenGL.\n");
  return usageExitCode(to);
}

bool parseArgs(int argc, char** argv, Args& a) {
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* what) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "marionette-ar: %s needs a value\n", what);
        return nullptr;
      }
      return argv[++i];
    };
    auto number = [&](const char* what, double lo, double hi, double& out) {
      const char* v = value(what);
      if (!v) return false;
      char* end = nullptr;
      out = std::strtod(v, &end);
      if (end == v || *end || !(out >= lo && out <= hi)) {
        std::fprintf(stderr, "marionette-ar: %s '%s' is not a number in [%g, %g]\n", what, v, lo, hi);
        return false;
      }
      return true;
    };
    double n = 0;
    if (isHelpFlag(s) || s == "--version") {  // the rest is not read
      (s == "--version" ? a.version : a.help) = true;
      return true;
    }
    if (s == "--headless") a.headless = true;
    else if (s == "--json") a.json = true;
    else if (s == "--restore" || s == "--truth" || s == "--author" || s == "--input-script") {
      const char* v = value(s.c_str());
      if (!v) return false;
      (s == "--restore" ? a.restore : s == "--truth" ? a.truth : s == "--author" ? a.author : a.inputScript) = v;
    }
    else if (s == "--hide-characters") a.hideCharacters = true;
    else if (s == "--frames") {
      if (!number("--frames", 1, 1e6, n)) return false;
      a.frames = static_cast<long>(n);
    } else if (s == "--out") {
      const char* v = value("--out");
      if (!v) return false;
      a.outDir = v;
    } else if (s == "--screenshot") {
      const char* v = value("--screenshot");
      if (!v) return false;
      a.screenshot = v;
    } else if (s == "--audio-dir") {
      const char* v = value("--audio-dir");
      if (!v) return false;
      a.audioDir = v;
    } else if (s == "--prt") {
      const char* v = value("--prt");
      if (!v) return false;
      PrtMode mode{};
      if (!parsePrtMode(v, mode)) {
        std::fprintf(stderr, "marionette-ar: --prt '%s' is none of shadowed, unshadowed, off\n", v);
        return false;
      }
      a.prtMode = v;
    } else if (s == "--prt-bands") {
      if (!number("--prt-bands", 2, 8, n)) return false;
      if (n != std::floor(n)) {
        std::fprintf(stderr, "marionette-ar: --prt-bands needs a whole number\n");
        return false;
      }
      a.prtBands = static_cast<int>(n);
    } else if (s == "--prt-rays") {
      if (!number("--prt-rays", 1, 65536, n)) return false;
      if (n != std::floor(n)) {
        std::fprintf(stderr, "marionette-ar: --prt-rays needs a whole number\n");
        return false;
      }
      a.prtRays = static_cast<int>(n);
    } else if (s == "--prt-cache") {
      const char* v = value("--prt-cache");
      if (!v) return false;
      a.prtCache = v;
    } else if (s == "--exposure") {
      if (!number("--exposure", 0, 1e6, n)) return false;
      a.exposure = static_cast<float>(n);
    } else if (s == "--width") {
      if (!number("--width", 16, 8192, n)) return false;
      a.width = static_cast<int>(n);
    } else if (s == "--height") {
      if (!number("--height", 16, 8192, n)) return false;
      a.height = static_cast<int>(n);
    } else if (!s.empty() && s[0] == '-') {
      std::fprintf(stderr, "marionette-ar: unknown option '%s'\n", s.c_str());
      return false;
    } else if (a.scene.empty()) a.scene = s;
    else {
      std::fprintf(stderr, "marionette-ar: more than one scene file ('%s')\n", s.c_str());
      return false;
    }
  }
  if (a.scene.empty()) return false;
  if (!a.author.empty() && (a.headless || !a.restore.empty())) {
    std::fprintf(stderr, "marionette-ar: --author opens the authoring window: not with --headless or --restore\n");
    return false;
  }
  if (!a.inputScript.empty() && a.author.empty()) {
    std::fprintf(stderr, "marionette-ar: --input-script drives the --author window\n");
    return false;
  }
  if (!a.truth.empty() && a.restore.empty()) {
    std::fprintf(stderr, "marionette-ar: --truth measures a --restore\n");
    return false;
  }
  if (a.headless && a.outDir.empty()) {
    std::fprintf(stderr, "marionette-ar: --headless needs --out DIR\n");
    return false;
  }
  return true;
}

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

// Logs the runtime's warnings to stderr.
struct LogListener : SceneListener {
  int warnings = 0;
  void onLog(LogLevel level, std::string_view message) override {
    if (level == LogLevel::Info) return;
    ++warnings;
    std::fprintf(stderr, "marionette-ar: %s: %.*s\n", level == LogLevel::Error ? "error" : "warning",
                 static_cast<int>(message.size()), message.data());
  }
};

}  // namespace

int main(int argc, char** argv) {
  (void)secondsSinceProcessStart();  // starts its clock
#if MARIONETTE_AR_HAS_TRACKING
  if (const int code = runTrackingCommand(argc, argv); code >= 0) return code;
  if (argc > 1 && std::strcmp(argv[1], "author") == 0) return runAuthorCommand(argc, argv);
#endif
  Args args;
  if (!parseArgs(argc, argv, args)) return usage();
  if (args.help) return usage(stdout);
  if (args.version) return printVersion();
  std::FILE* info = args.json ? stderr : stdout;  // with --json, stdout holds the report alone
  ArScene ar;
  const Diagnostics arDiag = readArScene(args.scene, ar);
  std::fputs(arDiag.format().c_str(), stderr);
  if (!arDiag.ok()) return 2;
  AugmentationRestore restore;
  if (!args.restore.empty()) {
    std::string truth = args.truth;
    if (truth.empty() && ar.background.kind == ArBackground::Kind::Sequence &&
        std::filesystem::is_regular_file(std::filesystem::path(ar.background.file) / "truth.csv"))
      truth = (std::filesystem::path(ar.background.file) / "truth.csv").string();
    (void)restore.load(args.restore, ar, truth);
  }
  restore.mark("main_and_augmentation");
  if (args.width) ar.width = args.width;
  if (args.height) ar.height = args.height;
  if (args.exposure >= 0.0f) ar.environment.exposure = args.exposure;
  ArPrt& prtSettings = ar.environment.prt;
  if (!args.prtMode.empty()) (void)parsePrtMode(args.prtMode, prtSettings.mode);
  if (args.prtBands) prtSettings.bands = args.prtBands;
  if (args.prtRays) prtSettings.rays = args.prtRays;
  if (!args.prtCache.empty()) prtSettings.cache = args.prtCache;
  const bool usePrt = !ar.environment.file.empty() && prtSettings.mode != PrtMode::Off;

  // Inputs that need no GL: the environment's lighting, the background source.
  FrameInputs inputs;
  std::string error;
  if (!inputs.load(ar, error, args.headless)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  for (const std::string& w : inputs.warnings()) std::fprintf(stderr, "%s\n", w.c_str());
  restore.mark("environment_and_background");

  std::string glError;
  auto gl = GlContext::create({ar.width, ar.height, !args.headless, "marionette-ar: " + args.scene}, glError);
  if (!gl) {
    std::fprintf(stderr, "marionette-ar: %s\n", glError.c_str());
    return 3;
  }
  std::fprintf(info, "marionette-ar: %s\n", gl->rendererName().c_str());
  restore.mark("gl_context");

  Scene scene;
  examples::useExampleSynthesizer(scene.speech());
  LogListener log;
  scene.addListener(&log);
  // The renderer plays no sound; --audio-dir writes each spoken line as a WAV, named by
  // the listener's onSpeech with its scene start time, for an engine or editor to play.
  if (!args.audioDir.empty()) scene.speech().setAudioDirectory(args.audioDir);
  SceneLoadResult loaded = loadSceneFile(ar.scene, scene, {.loadMeshes = true});
  std::fputs(loaded.diagnostics.format().c_str(), stderr);
  if (!loaded.ok()) return 2;
  restore.mark("scene_and_characters");
  bml::Realizer realizer(scene);
  realizer.setForwardWarningsToScene(false);
  // A window keeps its frame rate (speech is said off the frame path); frames
  // written headless step a fixed clock and must come out the same every run.
  if (args.headless) realizer.setSpeechSynthesis(bml::Realizer::SpeechSynthesis::Inline);
  restore.bind(scene, loaded.bml);
  bml::useSceneDialects(realizer, loaded);
  bml::TimedFiles bmlFiles(realizer, loaded.bml);
  int bmlErrors = 0;

  // GPU models, one per asset; a pose (palette texture) per character.
  std::map<const Asset*, std::unique_ptr<CharacterModel>> models;
  std::vector<std::unique_ptr<CharacterPose>> poses;
  std::vector<const CharacterModel*> drawn;
  for (const auto& c : scene.characters()) {
    const Asset* asset = &c->rig().asset();
    auto& model = models[asset];
    if (!model) {
      std::vector<std::string> warnings;
      auto m = std::make_unique<CharacterModel>();
      if (m->upload(*asset, warnings, error)) model = std::move(m);
      else std::fprintf(stderr, "marionette-ar: character '%s' is not drawn: %s\n", c->name().c_str(), error.c_str());
      for (const std::string& w : warnings) std::fprintf(stderr, "marionette-ar: warning: %s\n", w.c_str());
    }
    poses.push_back(std::make_unique<CharacterPose>(c->skeleton()));
    drawn.push_back(model.get());
  }

  // PRT: the transfer of each distinct asset (from the cache when it is there), then per
  // character the CPU light and its GPU buffers, all sized here: the frame loop allocates nothing.
  std::map<const Asset*, std::unique_ptr<PrtAsset>> prtAssets;
  std::vector<std::unique_ptr<PrtCharacterLight>> prtLights(scene.characters().size());
  std::vector<std::unique_ptr<PrtIrradiance>> prtBuffers(scene.characters().size());
  if (!usePrt) {
    std::fprintf(info, "marionette-ar: prt off (%s): no precompute, SH9 light per fragment\n",
                ar.environment.file.empty() ? "no environment, neutral sky light" : "environment.prt.mode off");
  } else {
    for (std::size_t i = 0; i < scene.characters().size(); ++i) {
      if (!drawn[i]) continue;
      const Character& c = *scene.characters()[i];
      auto& prtAsset = prtAssets[&c.rig().asset()];
      if (!prtAsset) {
        Diagnostics d;
        auto a = std::make_unique<PrtAsset>();
        const bool ok = loadPrtAsset(c.rig(), prtSettings, ar.path, *a, d);
        std::fputs(d.format().c_str(), stderr);
        if (!ok) return 2;
        std::fprintf(info, "marionette-ar: %s\n", a->describe(std::filesystem::path(c.rig().asset().sourcePath).filename().string()).c_str());
        std::fflush(info);
        prtAsset = std::move(a);
      }
      prtLights[i] = std::make_unique<PrtCharacterLight>(*prtAsset);
      prtBuffers[i] = std::make_unique<PrtIrradiance>(*drawn[i], prtAsset->primitiveVertexOffset, prtAsset->vertexCount);
      if (prtBuffers[i]->mismatches() > 0)
        std::fprintf(stderr, "marionette-ar: warning: character '%s': %zu primitives do not match the transfer mesh; "
                     "they keep the SH9 light\n", c.name().c_str(), prtBuffers[i]->mismatches());
    }
  }
  const prt::ShRotation shRotation(usePrt ? prtSettings.bands : 2);
  restore.mark("gpu_models_and_prt");
  double prtRelightMs = 0.0, prtUploadMs = 0.0;
  long prtUpdates = 0;

  ShaderProgram characterProgram;
  BackgroundRenderer background;
  RenderTarget target;
  if (!characterProgram.build("character.vert", "character.frag", error) || !background.create(error) ||
      !target.create(ar.width, ar.height, 4, error)) {
    std::fprintf(stderr, "marionette-ar: %s\n", error.c_str());
    return 3;
  }
  if (inputs.hasEnvironment())
    background.setEnvironment(inputs.environmentWidth(), inputs.environmentHeight(), inputs.environmentPixels());
  restore.mark("shaders_and_targets");

  // The authoring window: a session on the scene's tracker, its characters measured at rest.
  std::unique_ptr<AuthoringWindow> authoring;
  if (!args.author.empty()) {
    std::optional<AuthoringSession> started = startAuthoring(ar, scene, error);
    if (!started) {
      std::fprintf(stderr, "marionette-ar: --author: %s\n", error.c_str());
      return 2;
    }
    authoring = std::make_unique<AuthoringWindow>(std::move(*started), ar.authoringBml, args.author);
    if (!authoring->init(gl->window(), error) ||
        (!args.inputScript.empty() && !authoring->loadInputScript(args.inputScript, error))) {
      std::fprintf(stderr, "marionette-ar: %s\n", error.c_str());
      return 2;
    }
  }
  if (!args.outDir.empty()) std::filesystem::create_directories(args.outDir);
  const double dt = 1.0 / ar.fps;
  const long frames = args.frames > 0 ? args.frames : (args.headless ? static_cast<long>(5.0 * ar.fps) : -1);
  const float aspect = static_cast<float>(ar.width) / static_cast<float>(ar.height);
  Image8 frameImage;
  Lighting lighting;
  lighting.irradianceSH = inputs.irradianceSH();
  lighting.exposure = ar.environment.exposure;
  double cpuMs = 0.0;
  auto last = std::chrono::steady_clock::now();
  long frame = 0;
  // The viewer is the scene's "camera" object: scripts gaze and point at the user through it.
  scene.setObject("camera", inputs.viewerBeforeFirstFrame(0.0));
  for (; frames < 0 || frame < frames; ++frame) {
    if (!args.headless && gl->shouldClose()) break;
    // Headless steps at the scene's fps exactly; a window follows the wall clock (at most 0.1 s a
    // frame), unless a script drives it: then frame N shows camera frame N, as a replay does.
    double step = dt;
    if (!args.headless && args.inputScript.empty()) {
      const auto now = std::chrono::steady_clock::now();
      step = std::min(0.1, std::chrono::duration<double>(now - last).count());
      last = now;
    }
    const auto cpuStart = std::chrono::steady_clock::now();
    bmlFiles.sendDue(scene.time() + (frame == 0 ? 0.0 : step), [&](const Diagnostic& d) {
      std::fprintf(stderr, "%s\n", d.format().c_str());
      bmlErrors += d.severity == Severity::Error ? 1 : 0;
    });
    scene.update(frame == 0 ? 0.0 : step);
    realizer.update();
    cpuMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
    if (frame == 0) restore.mark("frame0_bml_and_scene");

    // The background frame first: a tracked camera's pose comes from it.
    const bool imageBackground = inputs.backgroundKind() != ArBackground::Kind::Environment &&
                                 inputs.backgroundKind() != ArBackground::Kind::Color;
    if (imageBackground) {
      if (const Image8* image = inputs.backgroundFrame(scene.time(), error)) background.setImage(*image);
      else if (!error.empty()) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 2;
      }
    }
    if (frame == 0) restore.mark("frame0_background_and_tracking");
    const CameraView view = inputs.camera(scene.time(), ar.width, ar.height);
    // Followed from the next frame; a tracked camera without a pose (identity view) keeps the last.
    if (view.view != glm::mat4(1.0f)) scene.setObject("camera", glm::vec3(glm::inverse(view.view)[3]));
    TrackingStateReport tracking;
    const bool tracked = inputs.trackingState(tracking);
    if (tracked && (tracking.changed || frame == 0))
      std::fprintf(info, "marionette-ar: %s %s at %.3f s (frame %ld)\n", tracking.replayed ? "replayed pose" : "tracking",
                  tracking.state, scene.time(), frame);
    target.bind();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    switch (inputs.backgroundKind()) {
      case ArBackground::Kind::Environment:
        background.drawEnvironment(glm::inverse(view.projection * view.view), lighting.exposure,
                                   glm::radians(ar.environment.rotationDegrees));
        break;
      case ArBackground::Kind::Color:
        background.drawFlat(ar.background.color);
        break;
      default:
        background.drawImage(aspect);
    }
    if (!args.hideCharacters && inputs.charactersVisible(scene.time())) {
      glEnable(GL_DEPTH_TEST);
      for (std::size_t i = 0; i < scene.characters().size(); ++i) {
        if (!drawn[i] || !restore.drawn(i)) continue;
        const Character& c = *scene.characters()[i];
        glm::mat4 anchor = restore.anchor(i);
        if (authoring && !authoring->placement(c.name(), anchor)) continue;  // not placed yet
        poses[i]->update(c.transformBuffer());
        const glm::mat4 world = anchor * c.transformBuffer().worldMatrix();
        if (prtLights[i]) {
          const auto t0 = std::chrono::steady_clock::now();
          prtLights[i]->relight(inputs.radianceSH(), world, shRotation);
          const auto t1 = std::chrono::steady_clock::now();
          prtBuffers[i]->upload(prtLights[i]->irradiance());
          const auto t2 = std::chrono::steady_clock::now();
          prtRelightMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
          prtUploadMs += std::chrono::duration<double, std::milli>(t2 - t1).count();
          ++prtUpdates;
        }
        drawCharacter(characterProgram, *drawn[i], *poses[i], world, view.projection * view.view, lighting,
                      prtBuffers[i].get(), inputs.characterOpacity(scene.time()));
      }
    }
    if (tracked && !tracking.replayed) {  // the tracking state in the top-left corner: green, amber, red
      const glm::vec3 badge = tracking.state[0] == 'T' ? glm::vec3(0.1f, 0.8f, 0.2f)
                              : tracking.state[1] == 'I' ? glm::vec3(0.95f, 0.7f, 0.1f)
                                                         : glm::vec3(0.9f, 0.1f, 0.1f);
      glEnable(GL_SCISSOR_TEST);
      glScissor(8, ar.height - 24, 16, 16);
      glClearColor(badge.r, badge.g, badge.b, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT);
      glDisable(GL_SCISSOR_TEST);
    }
    if (restore.active()) {  // a verified pose, the restored characters drawn with it
      const bool verified = tracked && std::strcmp(tracking.state, "TRACKING") == 0 && !args.hideCharacters &&
                            inputs.charactersVisible(scene.time());
      if (verified && restore.firstRegisteredFrame() < 0) glFinish();  // drawn, not only queued
      restore.frameDrawn(frame, scene.time(), verified, view.viewInDouble);
    }
    if (args.headless) {
      target.read(frameImage);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04ld.png", frame);
      if (!writeImage((std::filesystem::path(args.outDir) / name).string(), frameImage, error)) {
        std::fprintf(stderr, "marionette-ar: %s\n", error.c_str());
        return 2;
      }
    } else {
      int w = 0, h = 0;
      gl->framebufferSize(w, h);
      target.present(w, h);
      if (authoring) {
        lighting.exposure = std::exp2(authoring->session().augmentation().exposureEv);
        const AuthoringView av{view.view, view.projection, ar.width, ar.height,
                               tracked && std::strcmp(tracking.state, "LOST") != 0};
        authoring->frame(frame, av, tracked ? tracking.state : "not tracked", w, h);
        if (!args.screenshot.empty() && (authoring->quitRequested() || frame + 1 == frames)) {
          readWindow(w, h, frameImage);  // the window, with the panel
          if (!writeImage(args.screenshot, frameImage, error)) {
            std::fprintf(stderr, "marionette-ar: %s\n", error.c_str());
            return 2;
          }
          std::fprintf(info, "marionette-ar: screenshot %s\n", args.screenshot.c_str());
        }
      }
      gl->swapAndPoll();
      if (authoring && authoring->quitRequested()) {
        ++frame;
        break;
      }
    }
  }
  if (!args.screenshot.empty() && !authoring) {
    target.read(frameImage);
    if (!writeImage(args.screenshot, frameImage, error)) {
      std::fprintf(stderr, "marionette-ar: %s\n", error.c_str());
      return 2;
    }
    std::fprintf(info, "marionette-ar: screenshot %s\n", args.screenshot.c_str());
  }
  std::fprintf(info, "marionette-ar: %ld frames of %dx%d, %.3f s of scene time, middleware %.3f ms per frame\n", frame,
              ar.width, ar.height, scene.time(), frame > 0 ? cpuMs / static_cast<double>(frame) : 0.0);
  if (prtUpdates > 0)
    std::fprintf(info, "marionette-ar: prt per character per frame: relight %.3f ms, upload %.3f ms (%ld updates)\n",
                prtRelightMs / static_cast<double>(prtUpdates), prtUploadMs / static_cast<double>(prtUpdates), prtUpdates);
  TrackingStateReport tracking;
  if (inputs.trackingState(tracking) && tracking.replayed)
    std::fprintf(info, "marionette-ar: replayed poses: %ld of %ld frames with a pose\n", tracking.posed, tracking.frames);
  else if (inputs.trackingState(tracking))
    std::fprintf(info, "marionette-ar: tracking: %ld of %ld camera frames with a pose, tracker %.2f ms per frame median\n",
                tracking.posed, tracking.frames, inputs.trackingMedianMs());
  if (args.headless) std::fprintf(info, "marionette-ar: frames in %s\n", args.outDir.c_str());
  if (!args.restore.empty()) {
    if (restore.active())
      std::fprintf(info, "marionette-ar: restored %s: first registered frame %ld at %.3f s after launch\n",
                   args.restore.c_str(), restore.firstRegisteredFrame(), restore.firstRegisteredSeconds());
    if (args.json) std::printf("%s\n", restore.json(frame).c_str());
    if (!restore.error().empty()) return 1;
  } else if (args.json) {
    std::printf("{\"frames\": %ld, \"scene_seconds\": %.6f, \"middleware_ms_per_frame\": %.6f}\n", frame, scene.time(),
                frame > 0 ? cpuMs / static_cast<double>(frame) : 0.0);
  }
  return bmlErrors > 0 ? 1 : 0;
}
