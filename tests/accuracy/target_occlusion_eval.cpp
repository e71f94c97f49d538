// marionette_occlusion_eval: the occlusion mask over the target (target_occlusion.hpp) against
// the synthetic sequences' truth (SequenceRenderer::targetCoverage), as docs/tracking.md
// ("Occlusion over the target") reports it: at the exact poses, at the markerless tracker's (its
// occlusionMask(), the pose before smoothing) and at the pose it returned (smoothed), one thread.
//
//   marionette_occlusion_eval [--frames N] [--seeds N] [--first-seed S] [--set NAME]...
//                             [--scale S] [--window W] [--ncc HIDDEN VISIBLE] [--fine W]
//                             [--exact-only] [--verbose] [--dump DIR]
//
// Sets: the standard scenarios `occluder` (a flat rectangle sweeping over 20..60 % of the
// target) and, with nothing over the target, `orbit`, `blur`, `gain`, `noise_jpeg`, `grazing`
// (--frames each, default 150); the stress classes `hands` (seeds S..S+N-1, default 1..10: one
// or two textured hands reaching over the target) and `photometric` (the same seeds; exposure
// and white-balance steps, defocus). MN_STRESS_CACHE=DIR keeps the stress frames between runs.
// A row per set and pose source: the frames scored, those where the truth hides at least 20 mask
// pixels, IoU of the hidden pixels (mean over those frames, and the worst), the share of the
// visible target said hidden (mean and worst over the frames), the share of the hidden target
// missed, the pooled rates, the frames where more than a quarter of the target was clipped
// (nothing said hidden), the mask's cost per frame. --scale, --window, --ncc and --fine set the
// OcclusionSettings fields of those names (--ncc: hiddenNcc and visibleNcc; --fine: fineWeight);
// --exact-only skips the tracker; --verbose prints a line per frame; --dump writes the frame, the
// mask and the truth of every frame at the exact poses as PNGs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/occlusion_metrics.hpp"
#include "tracking/scenario_run.hpp"

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

namespace {

double percentileOf(std::vector<double> v, double p) { return v.empty() ? std::nan("") : percentile(std::move(v), p); }

void row(const std::string& set, const char* poses, int frames, const MaskSummary& m) {
  std::printf("| %s | %s | %d | %d | %.3f | %.3f | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %.3f / %.2f %% / %.2f %% | %d | %.2f | %.2f |\n",
              set.c_str(), poses, frames, m.hiddenFrames, m.iouMean, m.iouWorst, 100 * m.falseHiddenMean,
              100 * m.falseHiddenWorst, 100 * m.missedHiddenMean, 100 * m.missedHiddenWorst, m.pooledIou,
              100 * m.pooledFalseHidden, 100 * m.pooledMissedHidden, m.clippedFrames, percentileOf(m.ms, 0.5),
              percentileOf(m.ms, 0.95));
  std::fflush(stdout);
}

void add(MaskSummary& all, const MaskSummary& one) {
  // Pooled sums and per-frame means re-weighted by their frames.
  all.iouMean += std::isnan(one.iouMean) ? 0 : one.iouMean * one.hiddenFrames;
  all.missedHiddenMean += std::isnan(one.missedHiddenMean) ? 0 : one.missedHiddenMean * one.hiddenFrames;
  all.falseHiddenMean += std::isnan(one.falseHiddenMean) ? 0 : one.falseHiddenMean * one.visibleFrames;
  if (one.hiddenFrames > 0) {
    all.iouWorst = std::min(all.iouWorst, one.iouWorst);
    all.missedHiddenWorst = std::max(all.missedHiddenWorst, one.missedHiddenWorst);
  }
  if (one.visibleFrames > 0) all.falseHiddenWorst = std::max(all.falseHiddenWorst, one.falseHiddenWorst);
  all.frames += one.frames, all.hiddenFrames += one.hiddenFrames, all.visibleFrames += one.visibleFrames;
  all.found += one.found, all.truthHidden += one.truthHidden, all.unionPixels += one.unionPixels;
  all.visibleSaidHidden += one.visibleSaidHidden, all.truthVisible += one.truthVisible;
  all.ms.insert(all.ms.end(), one.ms.begin(), one.ms.end());
  all.clippedFrames += one.clippedFrames;
}

void finishPooled(MaskSummary& m) {
  const double nan = std::nan("");
  m.iouMean = m.hiddenFrames > 0 ? m.iouMean / m.hiddenFrames : nan;
  m.missedHiddenMean = m.hiddenFrames > 0 ? m.missedHiddenMean / m.hiddenFrames : nan;
  if (m.hiddenFrames == 0) m.iouWorst = m.missedHiddenWorst = nan;
  m.falseHiddenMean = m.visibleFrames > 0 ? m.falseHiddenMean / m.visibleFrames : nan;
  if (m.visibleFrames == 0) m.falseHiddenWorst = nan;
  m.pooledIou = m.unionPixels > 0 ? static_cast<double>(m.found) / static_cast<double>(m.unionPixels) : nan;
  m.pooledFalseHidden = m.truthVisible > 0 ? static_cast<double>(m.visibleSaidHidden) / static_cast<double>(m.truthVisible) : nan;
  m.pooledMissedHidden = m.truthHidden > 0 ? 1.0 - static_cast<double>(m.found) / static_cast<double>(m.truthHidden) : nan;
}

void dump(const std::string& dir, const OcclusionSequence& s, const CameraModel& camera, const OcclusionSettings& settings) {
  auto occlusion = standardTargetOcclusion(camera, settings);
  std::string name = s.name;
  std::replace(name.begin(), name.end(), '/', '_');
  for (std::size_t i = 0; i < s.frames.size(); ++i) {
    const cv::Mat& f = s.frames[i];
    occlusion->update(ImageView{f.data, f.cols, f.rows, 3, static_cast<std::ptrdiff_t>(f.step)}, s.poses[i]);
    const OcclusionMask& m = occlusion->mask();
    cv::Mat mask(m.height, m.width, CV_8UC1, const_cast<std::uint8_t*>(m.pixels)), big, truth, truthBig, out, bgr;
    cv::resize(mask, big, f.size(), 0, 0, cv::INTER_NEAREST);
    s.truth[i].hidden.convertTo(truth, CV_8U, 255.0);
    cv::resize(truth, truthBig, f.size(), 0, 0, cv::INTER_NEAREST);
    cv::cvtColor(f, bgr, cv::COLOR_RGB2BGR);
    std::vector<cv::Mat> ch{truthBig, big, cv::Mat::zeros(f.size(), CV_8U)};
    cv::Mat overlay;
    cv::merge(ch, overlay);  // blue: truth, green: mask
    cv::hconcat(bgr, overlay, out);
    char file[512];
    std::snprintf(file, sizeof file, "%s/%s_%03zu.png", dir.c_str(), name.c_str(), i);
    cv::imwrite(file, out);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 150, seeds = 10, firstSeed = 1, scale = 4, window = 5;
  bool verbose = false, exactOnly = false;
  double hiddenNcc = OcclusionSettings{}.hiddenNcc, visibleNcc = OcclusionSettings{}.visibleNcc;
  double fineWeight = OcclusionSettings{}.fineWeight;
  std::string dumpDir;
  std::vector<std::string> sets;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) seeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--first-seed") && i + 1 < argc) firstSeed = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--set") && i + 1 < argc) sets.emplace_back(argv[++i]);
    else if (!std::strcmp(argv[i], "--scale") && i + 1 < argc) scale = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--window") && i + 1 < argc) window = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--ncc") && i + 2 < argc) hiddenNcc = std::atof(argv[++i]), visibleNcc = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--fine") && i + 1 < argc) fineWeight = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else if (!std::strcmp(argv[i], "--exact-only")) exactOnly = true;
    else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc) dumpDir = argv[++i];
    else {
      std::fprintf(stderr, "usage: marionette_occlusion_eval [--frames N] [--seeds N] [--first-seed S] [--set NAME]... "
                           "[--scale S] [--window W] [--ncc HIDDEN VISIBLE] [--fine W] [--exact-only] [--verbose] [--dump DIR]\n");
      return 2;
    }
  }
  if (sets.empty()) sets = {"occluder", "hands", "orbit", "blur", "gain", "noise_jpeg", "grazing", "photometric"};
  cv::setNumThreads(1);
  const SequenceRenderer renderer = standardRenderer();
  const CameraModel& camera = renderer.camera();
  OcclusionSettings settings;
  settings.scale = scale;
  settings.window = window;
  settings.hiddenNcc = hiddenNcc, settings.visibleNcc = visibleNcc;
  settings.fineWeight = fineWeight;
  MarkerlessSettings trackerSettings;
  trackerSettings.occlusion = settings;
  std::printf("| set | poses | frames | with hidden | IoU mean | IoU worst | false hidden mean | worst | missed mean | worst | "
              "pooled IoU / false / missed | clipped | ms median | ms p95 |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& set : sets) {
    std::vector<OcclusionSequence> sequences;
    if (set == "hands" || set == "photometric") {
      const StressClass kind = set == "hands" ? StressClass::Hands : StressClass::Photometric;
      cv::setNumThreads(2);  // the renderer's own threads
      for (int s = firstSeed; s < firstSeed + seeds; ++s)
        sequences.push_back(stressOcclusionSequence(renderer, kind, static_cast<std::uint64_t>(s), 0, scale));
      cv::setNumThreads(1);
    } else {
      cv::setNumThreads(2);
      sequences.push_back(standardOcclusionSequence(renderer, set, frames, scale));
      cv::setNumThreads(1);
    }
    MaskSummary exact, tracked, smoothed;
    int allFrames = 0, drawn = 0;
    for (const OcclusionSequence& s : sequences) {
      std::vector<MaskScore> e, t;
      add(exact, maskAtExactPoses(s, camera, settings, &e));
      int d = 0;
      MaskSummary drawnPose;
      if (!exactOnly) {
        add(tracked, maskAtTrackerPoses(s, camera, trackerSettings, d, &t, &drawnPose));
        add(smoothed, drawnPose);
      }
      t.resize(e.size());
      drawn += d;
      allFrames += static_cast<int>(s.frames.size());
      if (verbose)
        for (std::size_t i = 0; i < e.size(); ++i)
          std::fprintf(stderr, "%s %zu: truth hidden %d visible %d | exact iou %.3f false %.3f missed %.3f | tracker iou %.3f false %.3f missed %.3f\n",
                       s.name.c_str(), i, e[i].truthHidden, e[i].truthVisible, e[i].iou, e[i].falseHidden, e[i].missedHidden,
                       t[i].iou, t[i].falseHidden, t[i].missedHidden);
      if (!dumpDir.empty()) dump(dumpDir, s, camera, settings);
    }
    finishPooled(exact);
    finishPooled(tracked);
    finishPooled(smoothed);
    const std::string name = sequences.size() > 1 ? set + " (" + std::to_string(sequences.size()) + " seeds)" : set;
    row(name, "exact", allFrames, exact);
    if (!exactOnly) row(name, "tracker", drawn, tracked);
    if (!exactOnly) row(name, "tracker, smoothed", drawn, smoothed);
  }
  return 0;
}
