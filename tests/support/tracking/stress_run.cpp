#include "tracking/stress_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <ctime>
#include <limits>
#include <stdexcept>

#include "tracking/scenario_run.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace marionette::ar::synthetic {

namespace {

bool drawn(const TrackedPose& p) { return p.state == TrackingState::Tracking || p.state == TrackingState::Limited; }

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

StressClassReport& classReport(StressReport& report, StressClass kind) {
  for (StressClassReport& c : report.classes)
    if (c.kind == kind) return c;
  StressClassReport c;
  c.kind = kind;
  // Kept in kStressClasses order.
  const auto rank = [](StressClass k) { return std::find(kStressClasses.begin(), kStressClasses.end(), k) - kStressClasses.begin(); };
  const auto at = std::find_if(report.classes.begin(), report.classes.end(),
                               [&](const StressClassReport& other) { return rank(other.kind) > rank(kind); });
  return *report.classes.insert(at, c);
}

// Whether `value` replaces the worst held so far: the first (frame, then class) of the worst
// error keeps it; a NaN pose is the worst of all.
bool worseThanHeld(const StressWorst& held, double value) noexcept {
  return held.frame < 0 || (std::isnan(value) && !std::isnan(held.value)) || value > held.value;
}

}  // namespace

// MN_STRESS_CACHE=DIR keeps each sequence's frames there (raw RGB8, one file a sequence) and
// reads them back the next time: for calibrating the tracker, where rendering is 3/4 of a run.
// The frames are a function of the class, seed, frame count and sub-frame options alone
// (stress_scenarios.hpp): options other than the defaults are part of the file's name.
RenderedScenario cachedRender(const SequenceRenderer& renderer, const StressSequence& sequence,
                              const StressOptions& stress, int threads, std::vector<double>& renderMs) {
  const char* dir = std::getenv("MN_STRESS_CACHE");
  if (!dir || !*dir) return renderStress(renderer, sequence, threads, &renderMs);
  const CameraModel& camera = renderer.camera();
  std::string name = sequence.scenario.name;
  std::replace(name.begin(), name.end(), '/', '_');
  const StressOptions defaults;
  char variant[96] = "";
  if (stress.pxPerSubFrame != defaults.pxPerSubFrame || stress.minSubFrames != defaults.minSubFrames ||
      stress.maxSubFrames != defaults.maxSubFrames)
    std::snprintf(variant, sizeof variant, "_sub%g-%d-%d", stress.pxPerSubFrame, stress.minSubFrames, stress.maxSubFrames);
  const std::string path = std::string(dir) + "/" + name + "_" + std::to_string(sequence.frames.size()) + "_" +
                           std::to_string(camera.width) + "x" + std::to_string(camera.height) + variant + ".rgb";
  const std::size_t bytes = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height) * 3;
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    RenderedScenario r;
    r.scenario = sequence.scenario;
    bool ok = true;
    for (std::size_t i = 0; i < sequence.frames.size() && ok; ++i) {
      cv::Mat m(camera.height, camera.width, CV_8UC3);
      ok = std::fread(m.data, 1, bytes, f) == bytes;
      r.frames.push_back(m);
    }
    std::fclose(f);
    if (ok) return r;
  }
  RenderedScenario r = renderStress(renderer, sequence, threads, &renderMs);
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    for (const cv::Mat& m : r.frames) {
      const cv::Mat c = m.isContinuous() ? m : m.clone();
      std::fwrite(c.data, 1, bytes, f);
    }
    std::fclose(f);
  }
  return r;
}

std::vector<StressCase> stressCases(int seeds, bool splitOverClasses, int frames, int firstSeed) {
  std::vector<StressCase> cases;
  const int last = firstSeed + seeds - 1;
  if (splitOverClasses) {
    for (int s = firstSeed; s <= last; ++s)
      cases.push_back({kStressClasses[static_cast<std::size_t>(s - 1) % kStressClasses.size()], static_cast<std::uint64_t>(s), frames});
  } else {
    for (StressClass k : kStressClasses)
      for (int s = firstSeed; s <= last; ++s) cases.push_back({k, static_cast<std::uint64_t>(s), frames});
  }
  return cases;
}

void addStressRun(StressReport& report, StressClass kind, std::uint64_t seed, const Scenario& truth,
                  const std::vector<TrackedPose>& poses, const std::vector<double>& ms) {
  if (poses.size() != truth.cameraToWorld.size() || truth.visibleFraction.size() != poses.size())
    throw std::invalid_argument("addStressRun: the poses and the truth differ in length");
  StressClassReport& c = classReport(report, kind);
  ++c.sequences;
  c.frames += static_cast<int>(poses.size());
  c.ms.insert(c.ms.end(), ms.begin(), ms.end());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const bool visible = truth.visibleFraction[i] > 0;
    const double hidden = i < truth.hiddenFraction.size() ? truth.hiddenFraction[i] : 0.0;
    const bool halfShown = truth.visibleFraction[i] - hidden >= 0.5;
    c.visibleFrames += visible;
    c.halfShownFrames += halfShown;
    if (!drawn(poses[i])) continue;
    ++c.drawnFrames;
    const double position = glm::length(poses[i].position() - glm::dvec3(truth.cameraToWorld[i][3]));
    const double rotation = rotationErrorDeg(poses[i].cameraToWorld, truth.cameraToWorld[i]);
    if (visible && position <= 0.02) ++c.within2cm;
    if (halfShown && position <= 0.02) ++c.halfShownWithin2cm;
    if (position >= kStressFalsePositionM || rotation >= kStressFalseRotationDeg) ++c.falsePoses;
    if (poses[i].state == TrackingState::Tracking) {
      ++c.trackingFrames;
      c.sumSqTracking += position * position;
    }
    auto keep = [&](StressWorst& w, double value) {
      if (worseThanHeld(w, value)) w = {value, seed, static_cast<int>(i)};
    };
    keep(c.worstPosition, position);
    keep(c.worstRotation, rotation);
  }
}

void finishStressReport(StressReport& report) {
  auto finish = [](StressClassReport& c) {
    c.trackingRmsM = c.trackingFrames > 0 ? std::sqrt(c.sumSqTracking / c.trackingFrames)
                                          : std::numeric_limits<double>::quiet_NaN();
    c.msMedian = percentile(c.ms, 0.5);
    c.msP95 = percentile(c.ms, 0.95);
  };
  StressClassReport& all = report.all;
  all = StressClassReport{};
  report.allWorstPositionClass.clear();
  report.allWorstRotationClass.clear();
  // The worst of the classes (the earlier class keeps a tie, as the earlier frame does).
  auto worse = [](StressWorst& w, std::string& name, const StressWorst& v, StressClass kind) {
    if (v.frame >= 0 && worseThanHeld(w, v.value)) {
      w = v;
      name = std::string(stressClassName(kind));
    }
  };
  for (StressClassReport& c : report.classes) {
    finish(c);
    all.sequences += c.sequences, all.frames += c.frames, all.visibleFrames += c.visibleFrames;
    all.drawnFrames += c.drawnFrames, all.trackingFrames += c.trackingFrames, all.within2cm += c.within2cm;
    all.halfShownFrames += c.halfShownFrames, all.halfShownWithin2cm += c.halfShownWithin2cm;
    all.falsePoses += c.falsePoses;
    all.sumSqTracking += c.sumSqTracking;
    all.ms.insert(all.ms.end(), c.ms.begin(), c.ms.end());
    worse(all.worstPosition, report.allWorstPositionClass, c.worstPosition, c.kind);
    worse(all.worstRotation, report.allWorstRotationClass, c.worstRotation, c.kind);
  }
  finish(all);
  report.renderedFrames = static_cast<int>(report.renderMs.size());
  double sum = 0;
  for (double v : report.renderMs) sum += v;
  report.renderMsMean = report.renderMs.empty() ? 0.0 : sum / static_cast<double>(report.renderMs.size());
  report.renderMsMedian = percentile(report.renderMs, 0.5);
}

StressReport runStressSeeds(const SequenceRenderer& renderer, const std::vector<StressCase>& cases,
                            const MarkerlessSettings& settings, const StressRunOptions& options) {
  StressReport report;
  for (const StressCase& k : cases) {
    const auto begin = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    const StressSequence sequence = stressSequence(renderer, k.kind, k.seed, k.frames > 0 ? k.frames : defaultStressFrames(k.kind),
                                                   options.stress);
    std::vector<double> renderMs;
    const RenderedScenario rendered = cachedRender(renderer, sequence, options.stress, options.renderThreads, renderMs);
    report.renderSeconds += seconds(begin);
    report.renderCpuSeconds += static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
    report.renderMs.insert(report.renderMs.end(), renderMs.begin(), renderMs.end());
    const auto tracking = std::chrono::steady_clock::now();
    const ScenarioRun run = runMarkerless(rendered, renderer.camera(), settings);
    report.trackSeconds += seconds(tracking);
    addStressRun(report, k.kind, k.seed, sequence.scenario, run.poses, run.ms);
    if (options.log) {
      std::fprintf(options.log, "%-16s %s\n", sequence.scenario.name.c_str(), formatReport(run.report).c_str());
      std::fflush(options.log);
    }
  }
  finishStressReport(report);
  return report;
}

std::string stressTable(const StressReport& report) {
  auto worst = [](const StressWorst& w, double scale) {
    if (w.frame < 0) return std::string("-");
    char b[64];
    std::snprintf(b, sizeof b, "%.2f (seed %llu, frame %d)", w.value * scale, static_cast<unsigned long long>(w.seed), w.frame);
    return std::string(b);
  };
  std::string out =
      "| class | sequences | frames | visible | drawn | visible within 2 cm | half shown: within 2 cm | "
      "worst drawn position cm | worst drawn rotation deg | false poses | TRACKING rms cm | ms median | ms p95 |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::pair<std::string, const StressClassReport*>> rows;
  for (const StressClassReport& c : report.classes) rows.emplace_back(std::string(stressClassName(c.kind)), &c);
  // The worst cells name their seed; the pooled row names the class too.
  if (report.classes.size() > 1) rows.emplace_back("**all**", &report.all);
  for (const auto& [name, row] : rows) {
    const StressClassReport& c = *row;
    std::string worstPosition = worst(c.worstPosition, 100), worstRotation = worst(c.worstRotation, 1);
    if (row == &report.all) {
      if (!report.allWorstPositionClass.empty()) worstPosition = report.allWorstPositionClass + " " + worstPosition;
      if (!report.allWorstRotationClass.empty()) worstRotation = report.allWorstRotationClass + " " + worstRotation;
    }
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %d | %d | %d | %d | %.1f %% | %.1f %% of %d | %s | %s | %d | %.2f | %.2f | %.2f |\n",
                  name.c_str(), c.sequences, c.frames, c.visibleFrames, c.drawnFrames,
                  c.visibleFrames > 0 ? 100.0 * c.within2cm / c.visibleFrames : 0.0,
                  c.halfShownFrames > 0 ? 100.0 * c.halfShownWithin2cm / c.halfShownFrames : 0.0, c.halfShownFrames,
                  worstPosition.c_str(), worstRotation.c_str(), c.falsePoses, c.trackingRmsM * 100, c.msMedian, c.msP95);
    out += line;
  }
  return out;
}

}  // namespace marionette::ar::synthetic
