#include "render_args.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "ar_cli.hpp"
#include "ar_scene_file.hpp"

namespace marionette::ar {

int renderUsage(std::FILE* to) {
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

bool parseRenderArgs(int argc, char** argv, RenderArgs& a) {
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

}  // namespace marionette::ar
