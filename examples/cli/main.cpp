#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"

namespace {
void usage() {
  std::fputs(
      "usage: marionette <command> [arguments]\n"
      "  inspect FILE [--json]    skeleton, clips, morph targets and meshes of a character or motion file\n"
      "  run SCENE.json [--frames N] [--fps F] [--trace OUT.csv] [--stats] [--morphs OUT.csv] [--audio-dir DIR]\n"
      "                           step a scene headless; --trace writes\n"
      "                           frame,time,character,joint,px,py,pz,qx,qy,qz,qw (world space, metres)\n"
      "  speak \"TEXT\" [--voice en-us] [--rate WPM] -o OUT.wav --visemes V.csv [--phonemes P.csv]\n"
      "                           synthesize with espeak-ng: audio, lip-sync channels per 1/100 s, phonemes\n"
      "  lipsync [--audio A.wav] --phones P.txt --visemes V.csv\n"
      "                           lip-sync channels of a recorded line from its phoneme alignment\n"
      "                           (.phones.txt, HTS .lab, Rhubarb .tsv)\n"
      "  retarget SRC_MOTION --to TARGET_CHARACTER [--src-map M.json] [--dst-map M.json] [--clip NAME]\n"
      "           [--fps F] [--ik feet,hands|none] -o OUT.glb|OUT.gltf|OUT.bvh [--report] [--json]\n"
      "                           a motion played by another skeleton, written as glTF (the character\n"
      "                           with the animation) or BVH; --report: end-effector error, foot skating\n"
#ifdef MARIONETTE_CLI_HAS_PRT
      "  prt lighting-error --env MAP [--bands N] [--window none|hann|lanczos|sinc4] [--json]\n"
      "                           n-band SH irradiance of a light probe against brute force\n"
      "  prt precompute MESH [--bands N] [--rays R] [--shadowed] -o CACHE [--json]\n"
      "                           per-vertex radiance transfer (shadowed: Embree rays), into a file\n"
      "  prt report [--docs DIR] [--quick]\n"
      "                           the PRT accuracy report: DIR/prt-report.md, CSVs and plots (gnuplot)\n"
#endif
#ifdef MARIONETTE_CLI_HAS_BML
      "  bml-check FILE.xml... [--json] [--character ASSET]\n"
      "                           parse and schedule BML blocks: predicted sync-point times and\n"
      "                           warnings as file:line:col: warning: TYPE: message\n"
#endif
      "exit status: 0 success, 1 warnings, 2 errors\n",
      stderr);
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    usage();
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (command == "inspect") return marionette::cli::inspectCommand(args);
  if (command == "run") return marionette::cli::runCommand(args);
  if (command == "speak") return marionette::cli::speakCommand(args);
  if (command == "lipsync") return marionette::cli::lipsyncCommand(args);
  if (command == "retarget") return marionette::cli::retargetCommand(args);
#ifdef MARIONETTE_CLI_HAS_PRT
  if (command == "prt") return marionette::cli::prtCommand(args);
#endif
#ifdef MARIONETTE_CLI_HAS_BML
  if (command == "bml-check") return marionette::cli::bmlCheckCommand(args);
#endif
  std::fprintf(stderr, "marionette: error: unknown command '%s'\n", command.c_str());
  usage();
  return 2;
}
