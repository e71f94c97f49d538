// The `marionette` command line: every command's arguments, declared once with
// CLI11, so that parsing and `--help` come from the same lines. The commands
// themselves (one file each) receive typed options (commands.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "marionette/version.h"
#ifdef MARIONETTE_CLI_HAS_PRT
#include "marionette/prt/sh_lighting.hpp"
#endif

namespace marionette::cli {
namespace {

// An output file: its folder is made and the file checked writable while the
// arguments are read, so a bad path fails before seconds of loading.
const CLI::Validator kOutputFile([](std::string& path) { return prepareOutputFile(path); }, "", "output file");
const CLI::Validator kOutputFolder([](std::string& path) { return prepareOutputFolder(path); }, "", "output folder");

// A number (a whole one when `whole`), finite, in [lo, hi].
CLI::Validator number(double lo, double hi, bool whole, const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi || (whole && v != std::floor(v)))
          return "'" + text + "': expected " + expected;
        return {};
      },
      "", "number");
}

// One of a few words.
CLI::Validator oneOf(const std::vector<std::string>& words, const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        for (const std::string& w : words)
          if (text == w) return {};
        return "'" + text + "': expected " + expected;
      },
      "", "word");
}

// A file name with one of these extensions.
CLI::Validator extension(const std::vector<std::string>& extensions, const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        for (const std::string& e : extensions)
          if (text.size() > e.size() && text.compare(text.size() - e.size(), e.size(), e) == 0) return {};
        return "'" + text + "': expected " + expected;
      },
      "", "extension");
}

// The innermost command the arguments reached ("marionette prt precompute").
std::string commandPath(const CLI::App& app) {
  std::string path = app.get_name();
  const CLI::App* at = &app;
  for (;;) {
    const auto subs = at->get_subcommands();
    if (subs.empty()) return path;
    at = subs.back();
    path += " " + at->get_name();
  }
}

}  // namespace

int parseAndRun(int argc, char** argv) {
  CLI::App app{"Marionette " MARIONETTE_VERSION_STRING
               ": inspect characters, run scenes headless, check BML, speak and lip-sync, retarget motions",
               "marionette"};
  app.set_version_flag("--version", "marionette " MARIONETTE_VERSION_STRING);
  app.set_help_all_flag("--help-all", "Print every command's options and exit");
  app.require_subcommand(1, 1);
  app.footer("Exit status: 0 success, 1 warnings, 2 errors.\n'marionette COMMAND --help': a command's options.");

  InspectOptions inspect;
  CLI::App* inspectCmd =
      app.add_subcommand("inspect", "Skeleton, clips, morph targets and meshes of a character or motion file");
  inspectCmd->add_option("FILE", inspect.file, "A character or motion file (glTF, VRM, FBX, BVH, COLLADA, X, ...)")->type_name("")
      ->required();
  inspectCmd->add_flag("--json", inspect.json, "Print JSON instead of text");

  RunOptions run;
  CLI::App* runCmd = app.add_subcommand("run", "Step a scene headless");
  runCmd->add_option("SCENE", run.scene, "The scene file (.json: characters, clips, BML, speech lines)")->type_name("")->required();
  runCmd
      ->add_option("--frames", run.frames,
                   "Frames to run (default: 2 s of frames, and on until the scene's and --bml's blocks have "
                   "ended, speech included; at most 120 s)")->type_name("N")
      ->check(number(1, 1e7, true, "a whole number from 1 to 10000000"));
  runCmd->add_option("--fps", run.fps, "Frames per second (default 60)")->type_name("F")
      ->check(number(1e-3, 1e4, false, "a number in [0.001, 10000]"));
  runCmd
      ->add_option("--trace", run.trace,
                   "Write frame,time,character,joint,px,py,pz,qx,qy,qz,qw for every frame (world space, metres)")->type_name("OUT.csv")
      ->check(kOutputFile);
  runCmd->add_option("--morphs", run.morphs, "Write frame,time,character,morph,weight for every frame")->type_name("OUT.csv")
      ->check(kOutputFile);
  runCmd->add_option("--audio-dir", run.audioDir, "Write each line said as a WAV file into this folder")
      ->check(kOutputFolder)->type_name("DIR");
  runCmd->add_flag("--stats", run.stats, "Print each character's update time and its controllers");
#ifdef MARIONETTE_CLI_HAS_BML
  runCmd->add_option("--bml", run.bml, "A BML file to perform at time 0 (repeatable)")->type_name("FILE.xml")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->expected(1)
      ->allow_extra_args(false);
  runCmd->add_option("--feedback", run.feedback, "Write the BML feedback as JSON lines")->type_name("OUT.jsonl")->check(kOutputFile);
  runCmd->add_option("--dialect", run.dialect,
                     "How BML is read: auto (SmartBody's forms when a block uses them), bml, smartbody "
                     "(default: the scene file's bmlDialect, else auto); a character's own bmlDialect comes first")
      ->type_name("D")->check(oneOf({"auto", "bml", "smartbody"}, "auto, bml or smartbody"));
#endif

  SpeakOptions speak;
  CLI::App* speakCmd = app.add_subcommand(
      "speak", "Synthesize a line (espeak-ng): audio, lip-sync channels per 1/100 s, phonemes");
  speakCmd->add_option("TEXT", speak.text, "What to say")->type_name("")->required();
  speakCmd->add_option("--voice", speak.voice, "An espeak-ng voice (default en-us)")->type_name("VOICE");
  speakCmd->add_option("--rate", speak.wordsPerMinute, "Words per minute")->type_name("WPM")
      ->check(number(1, 10000, true, "words per minute, a whole number in [1, 10000]"));
  speakCmd->add_option("-o,--output", speak.output, "The WAV file to write")->type_name("OUT.wav")->required()->check(kOutputFile);
  speakCmd->add_option("--visemes", speak.visemes, "The lip-sync channels to write (CSV)")->type_name("V.csv")
      ->required()
      ->check(kOutputFile);
  speakCmd->add_option("--phonemes", speak.phonemes, "The phonemes to write (CSV: start,end,phoneme)")->type_name("P.csv")
      ->check(kOutputFile);

  LipSyncOptions lipsync;
  CLI::App* lipsyncCmd =
      app.add_subcommand("lipsync", "Lip-sync channels of a recorded line from its phoneme alignment");
  lipsyncCmd->add_option("--audio", lipsync.audio, "The line's WAV file")->type_name("A.wav");
  lipsyncCmd->add_option("--phones", lipsync.phones, "The alignment: .phones.txt, HTS .lab or Rhubarb .tsv")->type_name("FILE")
      ->required();
  lipsyncCmd->add_option("--visemes", lipsync.visemes, "The lip-sync channels to write (CSV)")->type_name("V.csv")
      ->required()
      ->check(kOutputFile);

  RetargetCommandOptions retarget;
  retarget.jointMapFolders = jointMapFolders();
  std::string ik = "none";
  CLI::App* retargetCmd = app.add_subcommand(
      "retarget", "Play a motion on another skeleton; write glTF (the character with the animation) or BVH");
  retargetCmd->add_option("SRC_MOTION", retarget.source, "The motion (BVH, glTF, VRMA, FBX, ...)")->type_name("")->required();
  retargetCmd->add_option("--to", retarget.target, "The character that plays it")->type_name("FILE")->required();
  retargetCmd->add_option("--src-map", retarget.sourceMap,
                          "The source's joint map (default: the shipped map that fits it, else a guess)")->type_name("M.json");
  retargetCmd->add_option("--dst-map", retarget.targetMap,
                          "The target's joint map (default: the shipped map that fits it, else a guess)")->type_name("M.json");
  retargetCmd->add_option("--clip", retarget.clip, "The clip to retarget (default: the first)")->type_name("NAME");
  retargetCmd->add_option("--fps", retarget.fps, "Output frames per second (default: the source's)")->type_name("F")
      ->check(number(1e-3, 1000, false, "frames per second in [0.001, 1000]"));
  retargetCmd->add_option("--ik", ik, "Foot and hand IK: feet, hands, feet,hands or none (default)")->type_name("LIST")
      ->check(oneOf({"none", "feet", "hands", "feet,hands", "hands,feet"}, "feet, hands, feet,hands or none"));
  retargetCmd->add_option("-o,--output", retarget.output, "The file to write: OUT.glb, OUT.gltf or OUT.bvh")->type_name("OUT")
      ->required()
      ->check(extension({".glb", ".gltf", ".bvh"}, "a .glb, .gltf or .bvh file name") & kOutputFile);
  retargetCmd->add_flag("--report", retarget.report,
                        "Print the error (end-effector, limb directions, foot skating) as a Markdown table");
  retargetCmd->add_flag("--json", retarget.json, "Print the result and its error as JSON");
  retargetCmd->add_flag("--allow-partial", retarget.allowPartial,
                        "Retarget onto (or from) a character that is not a full humanoid (a quadruped, missing "
                        "bones): what maps is retargeted, the report says what it covers, the exit status is 1");

#ifdef MARIONETTE_CLI_HAS_PRT
  CLI::App* prtCmd = app.add_subcommand("prt", "Precomputed radiance transfer: lighting error, precompute, report");
  prtCmd->require_subcommand(1, 1);
  const std::string bandsExpected = "an integer in 2.." + std::to_string(prt::kMaxShBands);

  PrtLightingErrorOptions lighting;
  CLI::App* lightingCmd =
      prtCmd->add_subcommand("lighting-error", "The n-band SH irradiance of a light probe against brute force");
  lightingCmd->add_option("--env", lighting.env, "The light probe (HDR, EXR)")->type_name("MAP")->required();
  lightingCmd->add_option("--bands", lighting.bands, "SH bands (default 3)")->type_name("N")
      ->check(number(2, prt::kMaxShBands, true, bandsExpected));
  lightingCmd->add_option("--window", lighting.window, "Ringing window: none (default), hann, lanczos or sinc4")->type_name("NAME")
      ->check(oneOf({"none", "hann", "lanczos", "sinc4"}, "none, hann, lanczos or sinc4"));
  lightingCmd->add_option("--probe", lighting.probe, "The map's layout: latlong, mirror-ball or auto (default)")->type_name("KIND")
      ->check(oneOf({"latlong", "mirror-ball", "auto"}, "latlong, mirror-ball or auto"));
  lightingCmd->add_flag("--json", lighting.json, "Print JSON");

  PrtPrecomputeOptions precompute;
  CLI::App* precomputeCmd = prtCmd->add_subcommand(
      "precompute", "Per-vertex radiance transfer of a character's mesh (shadowed: Embree rays), into a cache file");
  precomputeCmd->add_option("MESH", precompute.mesh, "The character file")->type_name("")->required();
  precomputeCmd->add_option("-o,--output", precompute.output, "The transfer cache to write")->type_name("CACHE")
      ->required()
      ->check(kOutputFile);
  precomputeCmd->add_option("--bands", precompute.bands, "SH bands (default 3)")->type_name("N")
      ->check(number(2, prt::kMaxShBands, true, bandsExpected));
  precomputeCmd->add_option("--rays", precompute.rays, "Rays per vertex (default 1024)")->type_name("R")
      ->check(number(1, 1 << 20, true, "an integer in 1..1048576"));
  precomputeCmd->add_flag("--shadowed", precompute.shadowed, "Shadowed transfer (visibility rays)");
  precomputeCmd->add_option("--threads", precompute.threads, "Threads (default 0: every core)")->type_name("T")
      ->check(number(0, 256, true, "an integer in 0..256 (0: every core)"));
  precomputeCmd->add_flag("--json", precompute.json, "Print JSON");

  PrtReportOptions report;
  CLI::App* reportCmd = prtCmd->add_subcommand(
      "report", "The PRT accuracy report: DOCS/prt-report.md, DOCS/data/prt/*.csv, DOCS/img/prt_*.png (gnuplot)");
  reportCmd->add_option("--docs", report.docs, "The output folder (default docs)")
      ->check(kOutputFolder)->type_name("DIR");
  reportCmd->add_flag("--quick", report.quick, "A smoke run in well under 30 s (fewer maps, normals, rays, vertices)");
  reportCmd->add_option("--assets", report.assets, "The shared assets: envmaps/, characters/ (default ../shared/assets)")->type_name("DIR");
  reportCmd->add_option("--studiolights", report.studiolights,
                        "Blender's studio lights (default /usr/share/blender/datafiles/studiolights/world)")->type_name("DIR");
  reportCmd->add_option("--scripts", report.scripts, "Where plot_prt_*.gp are (default scripts)")->type_name("DIR");
  reportCmd->add_option("--threads", report.threads, "Threads for the brute force, references and precompute (default 2)")->type_name("T")
      ->check(number(1, 256, true, "an integer in 1..256"));
#endif

#ifdef MARIONETTE_CLI_HAS_BML
  BmlCheckOptions bmlCheck;
  CLI::App* bmlCheckCmd = app.add_subcommand(
      "bml-check", "Parse and schedule BML blocks: sync-point times, warnings as file:line:col: warning: TYPE: message");
  bmlCheckCmd->add_option("FILE", bmlCheck.files, "BML files, one block each")->type_name("")->required();
  bmlCheckCmd->add_option("--character", bmlCheck.character,
                          "Check against this character: durations from its clips, what it cannot realize")->type_name("FILE");
  bmlCheckCmd->add_option("--dialect", bmlCheck.dialect,
                          "How the blocks are read: auto (default: SmartBody's forms when a block uses them), bml, smartbody")
      ->type_name("D")->check(oneOf({"auto", "bml", "smartbody"}, "auto, bml or smartbody"));
  auto* sceneOption = bmlCheckCmd->add_option("--scene", bmlCheck.scene,
                          "Check in this scene file: its characters (profiles, clips), objects (gaze and point targets), voices")
      ->type_name("FILE");
  bmlCheckCmd->add_option("--character-name", bmlCheck.characterName,
                          "With --scene: the character the blocks are for (default: the block's characterId, else the first)")
      ->type_name("NAME")->needs(sceneOption);
  sceneOption->excludes(bmlCheckCmd->get_option("--character"));
  bmlCheckCmd->add_flag("--json", bmlCheck.json, "Print JSON");
#endif

  if (argc < 2) {  // no command: the overview, as an error
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  // A word where a command is expected that names none: CLI11 would say only that a
  // command is required.
  const CLI::App* at = &app;
  std::string path = "marionette";
  for (int k = 1; k < argc && argv[k][0] != '-' && at->get_require_subcommand_min() > 0; ++k) {
    const auto subs = at->get_subcommands([&](const CLI::App* s) { return s->get_name() == argv[k]; });
    if (subs.empty()) {
      std::fprintf(stderr, "%s: error: unknown command '%s'\nRun '%s --help' for the commands.\n", path.c_str(), argv[k],
                   path.c_str());
      return 2;
    }
    at = subs.front();
    path += " " + at->get_name();
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --help-all, --version
    const std::string where = commandPath(app);
    std::fprintf(stderr, "%s: error: %s\nRun '%s --help' for the options.\n", where.c_str(), e.what(), where.c_str());
    return 2;
  }

  if (*inspectCmd) return inspectCommand(inspect);
  if (*runCmd) return runCommand(run);
  if (*speakCmd) return speakCommand(speak);
  if (*lipsyncCmd) return lipsyncCommand(lipsync);
  if (*retargetCmd) {
    retarget.feet = ik.find("feet") != std::string::npos;
    retarget.hands = ik.find("hands") != std::string::npos;
    return retargetCommand(retarget);
  }
#ifdef MARIONETTE_CLI_HAS_PRT
  if (*lightingCmd) return prtLightingErrorCommand(lighting);
  if (*precomputeCmd) return prtPrecomputeCommand(precompute);
  if (*reportCmd) return prtReportCommand(report);
#endif
#ifdef MARIONETTE_CLI_HAS_BML
  if (*bmlCheckCmd) return bmlCheckCommand(bmlCheck);
#endif
  return 2;  // unreachable: require_subcommand
}

}  // namespace marionette::cli

int main(int argc, char** argv) { return marionette::cli::parseAndRun(argc, argv); }
