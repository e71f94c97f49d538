// marionette_tracking_eval: the markerless tracker over the standard scenarios (exact ground
// truth; tests/support/tracking), one thread, as docs/tracking.md reports it.
//
//   marionette_tracking_eval [--frames N] [--scenario NAME]... [--sweep] [--no-smoothing]
//   marionette_tracking_eval --stress SEEDS [--first-seed S] [--split] [--class CLASS] [--frames N] [--no-smoothing] [--verbose]
//   marionette_tracking_eval --case CLASS/SEED [--frames N]     (one stress sequence: a worst case again;
//                                                                MN_FRAMES=1 prints its frames' gates)
//
// Without --sweep: one row per scenario with the default settings. With --sweep: the
// work-precision grid (corners x pyramid levels x refinements) over orbit, occluder and partial,
// ATE against ms per frame. With --stress: seeds 1..SEEDS of every stress class
// (stress_scenarios.hpp; with --split, seed s of class (s - 1) % 4 only, the accuracy test's
// plan), a row per class of its worst cases (stress_run.hpp), and the time spent rendering;
// --frames sets every sequence's length (default: the class's), --verbose a line per sequence.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>

#include "tracking/scenario_run.hpp"
#include "tracking/stress_run.hpp"

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

namespace {

void row(const std::string& name, const ScenarioRun& r) {
  const TrajectoryReport& t = r.report;
  const double share = t.visibleFrames > 0 ? 100.0 * t.within2cm / t.visibleFrames : std::nan("");
  std::printf("| %s | %d | %d | %d | %.0f %% | %.2f | %.2f | %.2f | %d | %.3f | %s | %.2f | %.2f | %d |\n", name.c_str(),
              t.frames, t.visibleFrames, t.verifiedFrames, share, t.ateRmsM * 100, t.ateMaxM * 100, t.rotationMeanDeg,
              t.falsePoses, t.jitterMm, t.framesToRelocalize < 0 ? "-" : std::to_string(t.framesToRelocalize).c_str(),
              r.medianMs, r.p95Ms, r.keyframes);
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 0, stressSeeds = 0, firstSeed = 1;
  bool sweep = false, smoothing = true, split = false, verbose = false;
  std::string oneCase;  // --case CLASS/SEED
  std::string onlyClass;  // --class CLASS: the seeds of one class (calibrating on it)
  std::vector<std::string> names;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--scenario") && i + 1 < argc) names.emplace_back(argv[++i]);
    else if (!std::strcmp(argv[i], "--sweep")) sweep = true;
    else if (!std::strcmp(argv[i], "--no-smoothing")) smoothing = false;
    else if (!std::strcmp(argv[i], "--stress") && i + 1 < argc) stressSeeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--split")) split = true;
    else if (!std::strcmp(argv[i], "--first-seed") && i + 1 < argc) firstSeed = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) oneCase = argv[++i];
    else if (!std::strcmp(argv[i], "--class") && i + 1 < argc) onlyClass = argv[++i];
    else {
      std::fprintf(stderr, "usage: marionette_tracking_eval [--frames N] [--scenario NAME]... [--sweep] [--no-smoothing]\n"
                           "       marionette_tracking_eval --stress SEEDS [--first-seed S] [--split] [--class CLASS] [--frames N] [--no-smoothing] [--verbose]\n"
                           "       marionette_tracking_eval --case CLASS/SEED [--frames N]\n");
      return 2;
    }
  }
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  std::vector<StressCase> cases;
  if (!oneCase.empty()) {  // CLASS/SEED
    const std::size_t slash = oneCase.find('/');
    const auto kind = stressClassNamed(oneCase.substr(0, slash));
    if (slash == std::string::npos || !kind || std::atoll(oneCase.c_str() + slash + 1) <= 0) {
      std::fprintf(stderr, "marionette_tracking_eval: --case needs CLASS/SEED, e.g. pan/14\n");
      return 2;
    }
    cases.push_back({*kind, static_cast<std::uint64_t>(std::atoll(oneCase.c_str() + slash + 1)), frames});
    stressSeeds = 1;
  }
  if (stressSeeds > 0) {
    if (frames > 0 && frames < 30) {
      std::fprintf(stderr, "marionette_tracking_eval: a stress sequence needs --frames 30 or more\n");
      return 2;
    }
    MarkerlessSettings settings;
    settings.smoothing = smoothing;
    if (std::getenv("MN_NO_DENSE")) settings.denseAlignment = false;  // KLT on corners alone
    if (std::getenv("MN_NO_REENTRY")) settings.reentrySearch = false;  // no search from the way out
    StressRunOptions options;
    options.log = verbose ? stderr : nullptr;
    const auto start = std::chrono::steady_clock::now();
    if (cases.empty()) cases = stressCases(stressSeeds, split, frames, firstSeed);
    if (!onlyClass.empty()) {
      const auto kind = stressClassNamed(onlyClass);
      if (!kind) {
        std::fprintf(stderr, "marionette_tracking_eval: --class '%s' is not a stress class (pan, reentry, hands, photometric)\n",
                     onlyClass.c_str());
        return 2;
      }
      std::erase_if(cases, [&](const StressCase& c) { return c.kind != *kind; });
    }
    const StressReport report = runStressSeeds(renderer, cases, settings, options);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s\n", stressTable(report).c_str());
    std::printf("%d frames: rendering %.1f ms a frame (mean on its thread; median %.1f; %.1f ms of CPU), %.1f s on %d "
                "threads; tracking %.1f s; %.1f s in all\n",
                report.renderedFrames, report.renderMsMean, report.renderMsMedian,
                1000 * report.renderCpuSeconds / std::max(1, report.renderedFrames), report.renderSeconds,
                options.renderThreads, report.trackSeconds, total);
    return 0;
  }
  if (frames <= 0) frames = 150;
  if (sweep && names.empty()) names = {"orbit", "occluder", "partial"};
  const auto scenarios = renderScenarios(renderer, frames, names);
  if (!sweep) {
    MarkerlessSettings settings;
    settings.smoothing = smoothing;
    if (const char* v = std::getenv("MN_RELOC")) settings.relocalizationFeatures = std::atoi(v);
    if (const char* v = std::getenv("MN_REF")) settings.referenceFeatures = std::atoi(v);
    if (std::getenv("MN_NO_BACKGROUND")) settings.backgroundMotion = false;  // the prediction without the image's motion
    if (std::getenv("MN_NO_DENSE")) settings.denseAlignment = false;  // KLT on corners alone
    if (std::getenv("MN_NO_REENTRY")) settings.reentrySearch = false;  // no search from the way out
    std::printf("| scenario | frames | visible | TRACKING | visible within 2 cm | ATE rms cm | ATE max cm | rot mean deg "
                "| false poses | jitter mm | frames to relocalize | ms median | ms p95 | keyframes |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::vector<double> all;
    for (const RenderedScenario& s : scenarios) {
      const ScenarioRun r = runMarkerless(s, renderer.camera(), settings);
      row(s.scenario.name, r);
      all.insert(all.end(), r.ms.begin(), r.ms.end());
    }
    std::printf("\nall frames: %.2f ms median, %.2f ms p95\n", percentile(all, 0.5), percentile(all, 0.95));
    return 0;
  }
  std::printf("| corners | levels | refinements | ATE rms cm (orbit, occluder, partial) | visible within 2 cm | ms median | ms p95 |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (int corners : {60, 120, 200})
    for (int levels : {2, 3, 4})
      for (int refinements : {0, 1, 2}) {
        MarkerlessSettings s;
        s.trackedCorners = corners;
        s.pyramidLevels = levels;
        s.refinements = refinements;
        s.smoothing = smoothing;
        std::vector<double> ms;
        double sumSq = 0;
        int n = 0, within = 0, visible = 0;
        for (const RenderedScenario& sc : scenarios) {
          const ScenarioRun r = runMarkerless(sc, renderer.camera(), s);
          ms.insert(ms.end(), r.ms.begin(), r.ms.end());
          if (r.report.trackedFrames > 0) {
            sumSq += r.report.ateRmsM * r.report.ateRmsM * r.report.trackedFrames;
            n += r.report.trackedFrames;
          }
          within += r.report.within2cm;
          visible += r.report.visibleFrames;
        }
        std::printf("| %d | %d | %d | %.3f | %.1f %% | %.2f | %.2f |\n", corners, levels, refinements,
                    n ? std::sqrt(sumSq / n) * 100 : std::nan(""), visible ? 100.0 * within / visible : 0.0,
                    percentile(ms, 0.5), percentile(ms, 0.95));
        std::fflush(stdout);
      }
  return 0;
}
