#include <array>
#include "example_synthesizer.hpp"
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "commands.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/scene_file/scene_file.hpp"
#ifdef MARIONETTE_CLI_HAS_BML
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marionette/bml/realizer.hpp"
#include "marionette/bml/timed_files.hpp"
#endif

namespace marionette::cli {

namespace {
// Counts warnings the runtime reports while running, and says when speech starts.
struct WarningCounter : SceneListener {
  int warnings = 0;
  void onSpeech(const Character& c, std::string_view id, const speech::Utterance& u, std::string_view audioFile,
                double start) override {
    std::printf("speech: %s '%.*s' at %.3f s for %.3f s%s%.*s\n", c.name().c_str(), static_cast<int>(id.size()),
                id.data(), start, u.duration, audioFile.empty() ? "" : ", audio ", static_cast<int>(audioFile.size()),
                audioFile.data());
  }
  void onLog(LogLevel level, std::string_view message) override {
    if (level == LogLevel::Info) return;
    ++warnings;
    std::fprintf(stderr, "marionette: %s: %.*s\n", level == LogLevel::Error ? "error" : "warning",
                 static_cast<int>(message.size()), message.data());
  }
};

// frame,time,character,morph,weight for every morph target of every character that has some.
void writeMorphRows(std::FILE* out, long frame, double time, const Character& c) {
  const std::span<const float> w = c.transformBuffer().morphWeights();
  const auto& names = c.rig().morphTargets();
  for (std::size_t m = 0; m < w.size() && m < names.size(); ++m)
    std::fprintf(out, "%ld,%.6f,%s,%s,%.5f\n", frame, time, c.name().c_str(), names[m].c_str(), static_cast<double>(w[m]));
}

void writeTraceRows(std::FILE* out, long frame, double time, const Character& c) {
  const TransformBuffer& b = c.transformBuffer();
  const glm::mat4& world = b.worldMatrix();
  const Skeleton& s = c.skeleton();
  for (std::size_t j = 0; j < b.jointCount(); ++j) {
    const Transform t = decompose(world * b.modelMatrices()[j]);
    std::fprintf(out, "%ld,%.6f,%s,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", frame, time, c.name().c_str(),
                 s.names[j].c_str(), t.translation.x, t.translation.y, t.translation.z, t.rotation.x, t.rotation.y,
                 t.rotation.z, t.rotation.w);
  }
}
}  // namespace

int runCommand(const RunOptions& r) {
  Scene scene;
  examples::useExampleSynthesizer(scene.speech());
  WarningCounter counter;
  scene.addListener(&counter);
  const auto loadStart = std::chrono::steady_clock::now();
  SceneLoadResult loaded = loadSceneFile(r.scene, scene, {.isolateThirdPartyParsers = true});  // a tool: isolated
  const double loadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loadStart).count();
  std::fputs(loaded.diagnostics.format().c_str(), stderr);
  if (!loaded.ok()) return 2;

  std::FILE* trace = nullptr;
  if (!r.trace.empty()) {
    trace = std::fopen(r.trace.c_str(), "w");
    if (!trace) {
      std::fprintf(stderr, "%s: error: cannot open the trace file for writing\n", r.trace.c_str());
      return 2;
    }
    std::fputs("frame,time,character,joint,px,py,pz,qx,qy,qz,qw\n", trace);
  }
  std::FILE* morphs = nullptr;
  if (!r.morphs.empty()) {
    if (!(morphs = std::fopen(r.morphs.c_str(), "w"))) {
      std::fprintf(stderr, "%s: error: cannot open the morph file for writing\n", r.morphs.c_str());
      return 2;
    }
    std::fputs("frame,time,character,morph,weight\n", morphs);
  }
  if (!r.audioDir.empty()) scene.speech().setAudioDirectory(r.audioDir);
  scene.setStatsEnabled(r.stats);
#ifdef MARIONETTE_CLI_HAS_BML
  // BML: files from the scene (at their times) and from --bml (at 0), sent as the clock reaches them.
  bml::Realizer realizer(scene);
  realizer.setForwardWarningsToScene(false);  // the run loop prints them with their file:line:col
  realizer.setSpeechSynthesis(bml::Realizer::SpeechSynthesis::Inline);  // a fixed clock: the same output every run
  std::vector<TimedFile> sends = loaded.bml;
  for (const std::string& f : r.bml) sends.push_back({f, 0.0, {}});
  const std::size_t bmlFileCount = sends.size();
  if (!r.dialect.empty()) realizer.setDialect(*bml::dialectFromName(r.dialect));  // checked by the option
  bml::useSceneDialects(realizer, loaded);
  bml::TimedFiles bmlFiles(realizer, std::move(sends));
  int bmlProblems = 0, bmlErrors = 0;
  std::FILE* feedback = nullptr;
  if (!r.feedback.empty() && !(feedback = std::fopen(r.feedback.c_str(), "w"))) {
    std::fprintf(stderr, "%s: error: cannot open the feedback file for writing\n", r.feedback.c_str());
    return 2;
  }
  realizer.addFeedbackListener([&](const bml::Feedback& f) {
    if (!feedback) return;
    static const char* kinds[] = {"prediction", "blockProgress", "syncPointProgress", "warning"};
    nlohmann::ordered_json j{{"kind", kinds[static_cast<int>(f.kind)]}, {"character", f.character}, {"block", f.blockId},
                             {"behavior", f.behaviorId}, {"sync", f.syncPoint}, {"blockTime", f.blockTime},
                             {"sceneTime", f.sceneTime}, {"xml", f.xml()}};
    std::fprintf(feedback, "%s\n", j.dump().c_str());
  });
  auto sendDue = [&](double now) {
    bmlFiles.sendDue(now, [&](const Diagnostic& d) {
      std::fprintf(stderr, "%s\n", d.format().c_str());
      ++bmlProblems;
      bmlErrors += d.severity == Severity::Error ? 1 : 0;
    });
  };
#endif
  std::vector<double> totalMicros(scene.characters().size(), 0.0);
  std::vector<std::array<double, kControllerCount>> controllerMicros(scene.characters().size());
  const double dt = 1.0 / r.fps;
  // Without --frames: 2 s, and on while a block is still to be sent, held for its speech
  // or running, so that a scene that speaks runs to the end of its line.
  // Frame 0 is t = 0, so N seconds take N * fps + 1 frames.
  const long minFrames = r.frames.value_or(static_cast<long>(std::ceil(RunOptions::kDefaultSeconds * r.fps)) + 1);
  const long maxFrames = r.frames.value_or(static_cast<long>(std::ceil(RunOptions::kMaxDefaultSeconds * r.fps)) + 1);
  auto blocksRunning = [&] {
#ifdef MARIONETTE_CLI_HAS_BML
    return !bmlFiles.done() || realizer.heldBlocks() > 0 || realizer.activeBlocks() > 0;
#else
    return false;
#endif
  };
  const auto runStart = std::chrono::steady_clock::now();
  long frames = 0;
  for (long f = 0; f < maxFrames && (f < minFrames || blocksRunning()); ++f, ++frames) {
#ifdef MARIONETTE_CLI_HAS_BML
    sendDue(scene.time() + (f == 0 ? 0.0 : dt));
#endif
    scene.update(f == 0 ? 0.0 : dt);  // frame 0 is the pose at t = 0
#ifdef MARIONETTE_CLI_HAS_BML
    realizer.update();
#endif
    for (std::size_t i = 0; i < scene.characters().size(); ++i) {
      totalMicros[i] += scene.characters()[i]->stats().lastUpdateMicros;
      for (std::size_t k = 0; k < kControllerCount; ++k)
        controllerMicros[i][k] += scene.characters()[i]->stats().controllerMicros[k];
      if (trace) writeTraceRows(trace, f, scene.time(), *scene.characters()[i]);
      if (morphs) writeMorphRows(morphs, f, scene.time(), *scene.characters()[i]);
    }
  }
  const double runMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - runStart).count();
  if (trace && std::fclose(trace) != 0) {
    std::fprintf(stderr, "%s: error: writing the trace failed\n", r.trace.c_str());
    return 2;
  }

  std::printf("scene %s: %d characters from %d files loaded in %.1f ms\n", r.scene.c_str(), loaded.charactersAdded,
              loaded.assetsLoaded, loadMs);
  std::printf("ran %ld frames at %g fps (%.3f s of scene time) in %.1f ms%s\n", frames, r.fps, scene.time(), runMs,
              r.frames ? "" : (frames > minFrames ? " (to the end of the BML blocks)" : ""));
  if (!r.frames && frames == maxFrames && blocksRunning()) {
    std::fprintf(stderr, "marionette run: warning: BML blocks still running after %.0f s; stopped (--frames N runs longer)\n",
                 RunOptions::kMaxDefaultSeconds);
    ++counter.warnings;
  }
  for (const auto& c : scene.characters()) {
    glm::vec3 p = c->position();
    std::printf("  %-16s %3zu joints  layers %d  at (%.3f, %.3f, %.3f) heading %.1f deg\n", c->name().c_str(),
                c->skeleton().jointCount(), c->layerCount(), p.x, p.y, p.z, glm::degrees(c->heading()));
  }
  if (r.stats) {
    for (const std::string& note : loaded.notes) std::printf("scene clip %s\n", note.c_str());
    std::printf("stats (mean wall time per update, per character):\n");
    for (std::size_t i = 0; i < scene.characters().size(); ++i) {
      const Character& c = *scene.characters()[i];
      const CharacterStats& st = c.stats();
      std::string controllers;
      for (std::size_t k = 0; k < kControllerCount; ++k)
        if (st.controllerUsed[k]) {
          char buf[64];
          std::snprintf(buf, sizeof buf, ", %s %.2f us", controllerName(static_cast<Controller>(k)).data(),
                        controllerMicros[i][k] / static_cast<double>(frames));
          controllers += buf;
        }
      std::printf("  %-16s %8.2f us   controllers: clip layers x%d%s%s\n", c.name().c_str(),
                  totalMicros[i] / static_cast<double>(frames), c.layerCount(),
                  c.layerCount() == 0 ? " (rest pose only)" : (st.sampledDirect ? " (one-clip fast path)" : " (blend)"),
                  controllers.c_str());
    }
  }
  if (morphs && std::fclose(morphs) != 0) {
    std::fprintf(stderr, "%s: error: writing the morph weights failed\n", r.morphs.c_str());
    return 2;
  }
  if (trace) std::printf("trace: %s\n", r.trace.c_str());
  if (morphs) std::printf("morphs: %s\n", r.morphs.c_str());
#ifdef MARIONETTE_CLI_HAS_BML
  if (feedback && std::fclose(feedback) != 0) {
    std::fprintf(stderr, "%s: error: writing the feedback failed\n", r.feedback.c_str());
    return 2;
  }
  if (feedback) std::printf("feedback: %s\n", r.feedback.c_str());
  if (bmlFileCount > 0) std::printf("bml: %zu blocks sent, %d warnings or errors\n", bmlFileCount, bmlProblems);
  if (bmlErrors > 0) return 2;
  if (bmlProblems > 0) counter.warnings += bmlProblems;
#endif
  if (!loaded.diagnostics.items.empty() || counter.warnings > 0) return loaded.diagnostics.hasWarnings() || counter.warnings ? 1 : 0;
  return 0;
}

}  // namespace marionette::cli
