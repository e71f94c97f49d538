#include "author_command.hpp"
#include "example_synthesizer.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ar_cli.hpp"
#include "ar_scene_file.hpp"
#include "augmentation_scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/authoring/authoring_session.hpp"
#include "marionette_ar/background_source.hpp"
#include "tracked_camera.hpp"

namespace marionette::ar {

namespace {

int usage(std::FILE* to = stderr) {
  std::fprintf(to,
               "usage: marionette-ar author SCENE.json --actions ACTIONS.json -o AUGMENTATION.json [--json]\n"
               "  Replays an authoring session's actions (docs/authoring.md) over the scene's recorded camera\n"
               "  sequence, tracked with the scene's tracker and saved map, and writes the augmentation.\n"
               "  --actions     the session's actions (an authoring window's OUT.actions.json)\n"
               "  -o            the augmentation to write\n"
               "  --json        prints the actions' count, the modelled authoring time and the placements\n"
               "  --help, -h    this help; --version: the version\n");
  return usageExitCode(to);
}

// The recorded sequence played forwards then backwards, as a user sweeping a phone to and fro:
// the source frame shown at replay frame n.
std::int64_t pingPong(std::int64_t n, std::int64_t frames) {
  if (frames <= 1) return 0;
  const std::int64_t period = 2 * (frames - 1), m = n % period;
  return m < frames ? m : period - m;
}

}  // namespace

int runAuthorCommand(int argc, char** argv) {
  std::string scenePath, actionsPath, outPath;
  bool json = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json = true;
    else if ((a == "--actions" || a == "-o") && i + 1 < argc) (a == "-o" ? outPath : actionsPath) = argv[++i];
    else if (isHelpFlag(a)) return usage(stdout);
    else if (a == "--version") return printVersion();
    else if (!a.empty() && a[0] != '-' && scenePath.empty()) scenePath = a;
    else {
      std::fprintf(stderr, "marionette-ar author: unexpected argument '%s'\n", a.c_str());
      return usage();
    }
  }
  if (scenePath.empty() || actionsPath.empty() || outPath.empty()) return usage();
  auto fail = [](const std::string& message) {
    std::fprintf(stderr, "marionette-ar author: %s\n", message.c_str());
    return 2;
  };

  Diagnostics d;
  const std::optional<std::vector<Action>> actions = readActions(actionsPath, d);
  std::fputs(d.format().c_str(), stderr);
  ArScene ar;
  const Diagnostics sceneDiagnostics = readArScene(scenePath, ar);
  std::fputs(sceneDiagnostics.format().c_str(), stderr);
  if (!actions || !sceneDiagnostics.ok()) return 2;
  Scene scene;
  examples::useExampleSynthesizer(scene.speech());
  SceneLoadResult loaded = loadSceneFile(ar.scene, scene, {.loadMeshes = true, .isolateThirdPartyParsers = true});
  std::fputs(loaded.diagnostics.format().c_str(), stderr);
  if (!loaded.ok()) return 2;
  Diagnostics problems;
  std::optional<AuthoringSession> started = startAuthoring(ar, scene, loaded, problems);
  std::fputs(problems.format().c_str(), stderr);
  if (!started) return 2;
  AuthoringSession& session = *started;

  std::optional<BackgroundKind> kind;
  if (ar.background.kind == ArBackground::Kind::Sequence) kind = BackgroundKind::Sequence;
  else if (ar.background.kind == ArBackground::Kind::Video) kind = BackgroundKind::Video;
  else return fail(scenePath + ": 'background' must be a recorded \"sequence\" or \"video\" to author over");

  Diagnostics open;
  auto source = openBackground(*kind, ar.background.file, ar.background.fps, open, Playback::Hold);
  if (!source) {
    std::fputs(open.format().c_str(), stderr);
    return 2;
  }
  Diagnostics tracking;
  auto camera = TrackedCamera::create(ar.camera.tracker, source->width(), source->height(), tracking);
  std::fputs(tracking.format().c_str(), stderr);
  if (!camera) return 2;

  // Frames are fed to the tracker in the order a user would see them, at the sequence's rate, up
  // to the frame each action happens at; a video plays once and holds its last frame.
  const double fps = source->fps() > 0 ? source->fps() : 30.0;
  const std::int64_t sourceFrames = source->frameCount();
  std::int64_t fed = -1;
  double clock = 0.0;
  nlohmann::json steps = nlohmann::json::array();
  const Action* previous = nullptr;
  int saves = 0;
  for (std::size_t k = 0; k < actions->size(); ++k) {
    const Action& a = (*actions)[k];
    const double seconds = modelledSeconds(a, previous);
    clock += seconds;
    previous = &a;
    const std::int64_t frame = a.frame >= 0 ? a.frame : static_cast<std::int64_t>(std::floor(clock * fps));
    const std::string where = actionsPath + ": actions[" + std::to_string(k) + "] (" + actionName(a.kind) + ")";
    if (frame < fed) return fail(where + ": frame " + std::to_string(frame) + " is before frame " + std::to_string(fed) +
                                 ", which the session has reached");
    for (; fed < frame; ) {
      ++fed;
      const std::int64_t src = *kind == BackgroundKind::Sequence ? pingPong(fed, sourceFrames)
                                                                 : std::min(fed, sourceFrames - 1);
      Diagnostics frameDiagnostics;
      const BackgroundFrame& f = source->frameAt((static_cast<double>(src) + 0.5) / fps, frameDiagnostics);
      if (!frameDiagnostics.ok()) {
        std::fputs(frameDiagnostics.format().c_str(), stderr);
        return 2;
      }
      camera->update({f.rgb.data(), f.width, f.height, 3, 0}, static_cast<double>(fed) / fps);
    }
    AuthoringView view;
    view.width = source->width();
    view.height = source->height();
    view.tracked = camera->state() != TrackingState::Lost;
    view.view = camera->view();
    view.projection = camera->projection(view.width, view.height, ar.camera.nearPlane, ar.camera.farPlane);
    if (Diagnostics refused; !session.apply(a, view, refused)) {  // the session's reason, after the file and action
      std::string why;
      for (const Diagnostic& item : refused.items) why += (why.empty() ? "" : "; ") + item.message;
      return fail(where + " at frame " + std::to_string(frame) + " (" + std::string(trackingStateName(camera->state())) +
                  "): " + why);
    }
    if (a.kind == ActionKind::Save) {
      Diagnostics w;
      if (!writeAugmentation(outPath, relativeTo(session.augmentation(), outPath), w)) {
        std::fputs(w.format().c_str(), stderr);
        return 2;
      }
      ++saves;
    }
    steps.push_back({{"do", actionName(a.kind)}, {"frame", frame}, {"seconds", seconds},
                     {"state", std::string(trackingStateName(camera->state()))}});
  }
  if (actions->empty() || actions->back().kind != ActionKind::Save) {
    std::fprintf(stderr, "marionette-ar author: warning: %s: the actions do not end with a save; the final state is "
                 "written to %s\n", actionsPath.c_str(), outPath.c_str());
    Diagnostics w;
    if (!writeAugmentation(outPath, relativeTo(session.augmentation(), outPath), w)) {
      std::fputs(w.format().c_str(), stderr);
      return 2;
    }
  }

  const Augmentation& aug = session.augmentation();
  if (json) {
    nlohmann::json characters = nlohmann::json::array();
    for (const PlacedCharacter& c : aug.characters) {
      float height = 0, lifeHeight = 0;
      for (const CatalogueEntry& e : session.catalogue())
        if (e.name == c.name) height = e.heightMetres * c.placement.scale, lifeHeight = e.lifeSize().metres;
      const Placement& p = c.placement;
      characters.push_back({{"name", c.name},
                            {"position", {p.position.x, p.position.y, p.position.z}},
                            {"rotor", {p.rotation.s, p.rotation.b23, p.rotation.b31, p.rotation.b12}},
                            {"scale", p.scale},
                            {"height_m", height},
                            {"life_height_m", lifeHeight},
                            {"bml", c.bml}});
    }
    // The scene's characters that life size places at the default height, and why.
    nlohmann::json notes = nlohmann::json::array();
    for (const CatalogueEntry& e : session.catalogue())
      if (const LifeSize life = e.lifeSize(); !life.note.empty()) notes.push_back(life.note);
    nlohmann::json out = {{"actions", actions->size()},  {"authoring_seconds", clock},
                          {"frames", fed + 1},           {"saves", saves},
                          {"augmentation", outPath},     {"exposure_ev", aug.exposureEv},
                          {"characters", characters},    {"notes", notes},
                          {"steps", steps}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("marionette-ar author: %zu actions, %.1f s modelled, %lld frames tracked; %zu characters placed; "
                "wrote %s\n", actions->size(), clock, static_cast<long long>(fed + 1), aug.characters.size(),
                outPath.c_str());
  }
  return 0;
}

}  // namespace marionette::ar
