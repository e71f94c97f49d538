#include <cstdio>
#include "example_synthesizer.hpp"
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "marionette/bml/realizer.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/core/text_file.hpp"
#include "marionette/bml/timed_files.hpp"
#include "marionette/io/import.hpp"
#include "marionette/scene_file/scene_file.hpp"

namespace marionette::cli {

namespace {
const char* status(const bml::Schedule& s) {
  if (s.failed) return "failed";
  return s.warnings.empty() ? "ok" : "warnings";
}

std::string warningLine(const std::string& file, const bml::Warning& w) {
  std::string where;
  if (!w.behaviorId.empty()) where = "behavior '" + w.behaviorId + "': ";
  Diagnostic d{w.fatal ? Severity::Error : Severity::Warning, file, w.line, w.column,
               std::string(bml::toString(w.type)) + ": " + where + w.message};
  return d.format();
}

// What the characters say while the blocks are realized (a voice they fell back from, a face
// they cannot move): warnings, printed after the file's.
struct SceneWarnings : SceneListener {
  std::vector<std::string> lines;
  void onLog(LogLevel level, std::string_view message) override {
    if (level == LogLevel::Warning || level == LogLevel::Error) lines.emplace_back(message);
  }
};

// The default character: one that has every controller and the built-in
// default durations (docs/bml-compliance.md), so a check is about the BML
// itself. Its rig is a single joint; nothing is rendered.
std::shared_ptr<const Rig> defaultCharacterRig() {
  auto asset = std::make_shared<Asset>();
  asset->skeleton.addJoint("root", -1, Transform{});
  return std::make_shared<Rig>(*asset);
}
}  // namespace

int bmlCheckCommand(const BmlCheckOptions& o) {
  const bool json = o.json;
  const std::vector<std::string>& files = o.files;
  const std::string& characterFile = o.character;
  const bool inScene = !o.scene.empty();
  // Against a real character: its clips give default durations, and behaviors
  // it cannot realize are CANNOT_CREATE_BEHAVIOR warnings.
  std::shared_ptr<const Rig> rig;
  std::string name = characterFile.empty() ? "default" : std::filesystem::path(characterFile).stem().string();
  if (inScene) {
    // The scene is loaded once here to check it and the name; each file gets a fresh copy below.
    Scene probe;
    const SceneLoadResult loaded = loadSceneFile(o.scene, probe, {.isolateThirdPartyParsers = true});
    std::fputs(loaded.diagnostics.format().c_str(), stderr);
    if (!loaded.ok()) return 2;
    if (probe.characters().empty()) {
      std::fprintf(stderr, "%s: error: the scene has no character to check the blocks against\n", o.scene.c_str());
      return 2;
    }
    if (!o.characterName.empty() && !probe.findCharacter(o.characterName)) {
      std::string names;
      for (const auto& c : probe.characters()) names += (names.empty() ? "'" : ", '") + c->name() + "'";
      std::fprintf(stderr, "%s: error: --character-name '%s': the scene has no such character (it has %s)\n",
                   o.scene.c_str(), o.characterName.c_str(), names.c_str());
      return 2;
    }
    name = o.characterName;  // empty: the block's characterId, else the first (Realizer::perform)
  } else if (characterFile.empty()) {
    rig = defaultCharacterRig();
  } else {
    ImportResult loaded = importAsset(characterFile, {.isolateThirdPartyParsers = true});  // a tool: isolated
    std::fputs(loaded.diagnostics.format().c_str(), stderr);
    if (!loaded.ok()) return 2;
    rig = std::make_shared<Rig>(*loaded.asset);
  }
  const bml::Dialect dialect = bml::dialectFromName(o.dialect).value_or(bml::Dialect::Auto);  // checked by the option
  // Without a character the check is about the BML alone: say so once, so that "ok" is not
  // read as "a character can do this".
  const std::string realizability =
      inScene                ? "checked in the scene " + o.scene
      : characterFile.empty() ? "not checked (no --character: durations are the built-in defaults)"
                              : "checked against " + characterFile;
  if (characterFile.empty() && !inScene && !json)
    std::fprintf(stderr, "note: no --character: what a character can realize is not checked; "
                         "durations are the built-in defaults\n");
  int worst = 0;
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const std::string& file : files) {
    std::string content;
    if (Diagnostics unread; !readTextFile(file, content, unread, "cannot read the file")) {
      std::fputs(unread.format().c_str(), stderr);
      worst = 2;
      continue;
    }
    // Each file is one block sent at time 0 to a fresh scene, so files do not
    // interact (many corpus files share the id "bml1").
    Scene scene;
    examples::useExampleSynthesizer(scene.speech());
    SceneLoadResult loaded;
    if (inScene) {
      loaded = loadSceneFile(o.scene, scene, {.isolateThirdPartyParsers = true});  // checked above
      if (!loaded.ok()) return 2;
    } else {
      scene.addCharacter(name, rig);
    }
    SceneWarnings said;
    scene.addListener(&said);
    bml::Realizer realizer(scene);
    realizer.setDialect(dialect);
    if (inScene) bml::useSceneDialects(realizer, loaded);
    realizer.setForwardWarningsToScene(false);
    realizer.setReportUnrealized(inScene || !characterFile.empty());
    realizer.setSpeechSynthesis(bml::Realizer::SpeechSynthesis::Inline);  // the schedule is the answer
    bml::SchedulerOptions options;  // <bmlt:audiofile fileName> is beside the file
    options.fileDirectory = std::filesystem::path(file).parent_path().generic_string();
    const bml::Schedule s = realizer.perform(content, name, options);
    scene.removeListener(&said);
    worst = std::max(worst, s.failed ? 2 : (s.warnings.empty() && said.lines.empty() ? 0 : 1));
    if (json) {
      nlohmann::ordered_json block;
      block["id"] = s.blockId;
      block["status"] = status(s);
      block["dialect"] = bml::toString(s.dialect);
      block["realizability"] = realizability;
      auto& behaviors = block["behaviors"] = nlohmann::ordered_json::array();
      for (const auto& b : s.behaviors) {
        nlohmann::ordered_json syncs = nlohmann::ordered_json::object();
        for (const auto& sync : b.syncs) syncs[sync.name] = sync.time;
        behaviors.push_back({{"id", b.id}, {"type", b.type}, {"syncPoints", syncs}});
      }
      auto& warnings = block["warnings"] = nlohmann::ordered_json::array();
      for (const auto& w : s.warnings)
        warnings.push_back({{"type", bml::toString(w.type)}, {"behavior", w.behaviorId}, {"line", w.line},
                            {"column", w.column}, {"message", w.message}});
      auto& characters = block["characterWarnings"] = nlohmann::ordered_json::array();
      for (const std::string& line : said.lines) characters.push_back(line);
      out.push_back({{"file", file}, {"blocks", nlohmann::json::array({block})}});
      continue;
    }
    std::printf("%s: block '%s': %s%s\n", file.c_str(), s.blockId.c_str(), status(s),
                s.dialect == bml::Dialect::SmartBody ? " (read as SmartBody)" : "");
    for (const auto& b : s.behaviors) {
      std::printf("  %-14s %-12s", b.id.c_str(), b.type.c_str());
      for (const auto& sync : b.syncs) std::printf(" %s=%.3f", sync.name.c_str(), sync.time);
      std::printf("\n");
    }
    for (const auto& w : s.warnings) std::fprintf(stderr, "%s\n", warningLine(file, w).c_str());
    for (const std::string& line : said.lines) std::fprintf(stderr, "%s: warning: %s\n", file.c_str(), line.c_str());
  }
  if (json) std::cout << out.dump(2) << '\n';
  return worst;
}

}  // namespace marionette::cli
