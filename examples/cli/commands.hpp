// Subcommands of the `marionette` tool. main.cpp reads the arguments
// (CLI11: one grammar gives both the parsing and every --help, so they cannot
// drift) into these options; each command returns the process exit code:
// 0 success, 1 warnings, 2 errors (errors on stderr as file:line:col: error: ...).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace marionette::cli {

struct InspectOptions {
  std::string file;
  bool json = false;
};
int inspectCommand(const InspectOptions& o);

struct RunOptions {
  std::string scene, trace, feedback, morphs, audioDir;
  std::vector<std::string> bml;
  std::string dialect;  // "" = the scene file's (else auto); else auto, bml, smartbody
  std::optional<long> frames;  // none: at least kDefaultSeconds, on to the end of the BML blocks
  double fps = 60.0;
  bool stats = false;
  static constexpr double kDefaultSeconds = 2.0;
  static constexpr double kMaxDefaultSeconds = 120.0;  // without --frames, a block that never ends stops here
};
int runCommand(const RunOptions& o);

struct SpeakOptions {
  std::string text, voice, output, visemes, phonemes;
  std::optional<int> wordsPerMinute;
};
int speakCommand(const SpeakOptions& o);

struct LipSyncOptions {
  std::string audio, phones, visemes;
};
int lipsyncCommand(const LipSyncOptions& o);

struct RetargetCommandOptions {
  std::string source, target, sourceMap, targetMap, clip, output;
  float fps = 0.0f;
  bool feet = false, hands = false, report = false, json = false;
  bool allowPartial = false;  // retarget onto (or from) a character that is not a full humanoid
  std::vector<std::string> jointMapFolders;  // where the shipped maps are looked up: jointMapFolders()
};
// $MARIONETTE_JOINTMAPS, the installed share/marionette/jointmaps beside this executable's
// bin/, and the source tree's assets/jointmaps (joint_map_folders.cpp).
[[nodiscard]] std::vector<std::string> jointMapFolders();
int retargetCommand(const RetargetCommandOptions& o);

#ifdef MARIONETTE_CLI_HAS_PRT
struct PrtLightingErrorOptions {
  std::string env, window = "none", probe = "auto";
  int bands = -1;  // -1: the default for lighting
  bool json = false;
};
int prtLightingErrorCommand(const PrtLightingErrorOptions& o);

struct PrtPrecomputeOptions {
  std::string mesh, output;
  int bands = -1, rays = 1024, threads = 0;  // bands -1: the default for transfer; threads 0: every core
  bool shadowed = false, json = false;
};
int prtPrecomputeCommand(const PrtPrecomputeOptions& o);

struct PrtReportOptions {
  std::string docs = "docs", assets = "../shared/assets",
              studiolights = "/usr/share/blender/datafiles/studiolights/world", scripts = "scripts";
  bool quick = false;
  unsigned threads = 2;
};
int prtReportCommand(const PrtReportOptions& o);  // prt_report.cpp
#endif

#ifdef MARIONETTE_CLI_HAS_BML
struct BmlCheckOptions {
  std::vector<std::string> files;
  std::string character;
  std::string scene;          // a scene file: its characters, objects, voices and dialects
  std::string characterName;  // which of its characters (default: the block's characterId, else the first)
  std::string dialect = "auto";  // auto, bml, smartbody (bml::dialectFromName)
  bool json = false;
};
int bmlCheckCommand(const BmlCheckOptions& o);
#endif

// Makes an output file's folder (like mkdir -p) and checks that the file can be
// written, before any work: "" when it can, else why not (output_files.cpp).
[[nodiscard]] std::string prepareOutputFile(const std::string& path);
// The same for an output folder: made, and a file written into it and removed.
[[nodiscard]] std::string prepareOutputFolder(const std::string& path);

}  // namespace marionette::cli
