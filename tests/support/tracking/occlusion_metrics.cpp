#include "tracking/occlusion_metrics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "tracking/scenario_run.hpp"
#include "tracking/stress_run.hpp"

namespace marionette::ar::synthetic {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

MaskTruth maskTruth(const cv::Mat& onTarget, const cv::Mat& hidden, int scale) {
  const int mw = (onTarget.cols + scale - 1) / scale, mh = (onTarget.rows + scale - 1) / scale;
  MaskTruth t;
  t.onTarget = cv::Mat::zeros(mh, mw, CV_32FC1);
  t.hidden = cv::Mat::zeros(mh, mw, CV_32FC1);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      double on = 0, hid = 0;
      int n = 0;
      for (int fy = y * scale; fy < std::min(onTarget.rows, y * scale + scale); ++fy)
        for (int fx = x * scale; fx < std::min(onTarget.cols, x * scale + scale); ++fx, ++n) {
          on += onTarget.at<float>(fy, fx);
          hid += hidden.at<float>(fy, fx);
        }
      t.onTarget.at<float>(y, x) = static_cast<float>(on / n);
      t.hidden.at<float>(y, x) = static_cast<float>(hid / n);
    }
  return t;
}

MaskScore scoreMask(const OcclusionMask& mask, const MaskTruth& truth) {
  MaskScore s;
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x) {
      const float on = truth.onTarget.at<float>(y, x), hid = truth.hidden.at<float>(y, x);
      const bool isHidden = hid >= 0.5f, isVisible = on - hid >= 0.5f;
      const bool said = mask.at(x, y) >= 128;
      s.truthHidden += isHidden;
      s.truthVisible += isVisible;
      s.predictedHidden += said;
      s.hiddenFound += isHidden && said;
      s.visibleSaidHidden += isVisible && said;
      s.unionPixels += isHidden || said;
    }
  s.clipped = mask.clippedShare > 0.25;
  s.iou = s.unionPixels > 0 ? static_cast<double>(s.hiddenFound) / s.unionPixels : kNaN;
  s.falseHidden = s.truthVisible > 0 ? static_cast<double>(s.visibleSaidHidden) / s.truthVisible : kNaN;
  s.missedHidden = s.truthHidden > 0 ? 1.0 - static_cast<double>(s.hiddenFound) / s.truthHidden : kNaN;
  return s;
}

void addFrame(MaskSummary& m, const MaskScore& s, int frame) {
  ++m.frames;
  m.clippedFrames += s.clipped;
  m.found += s.hiddenFound, m.truthHidden += s.truthHidden, m.unionPixels += s.unionPixels;
  m.visibleSaidHidden += s.visibleSaidHidden, m.truthVisible += s.truthVisible;
  if (s.truthHidden >= kMinHiddenPixels) {
    ++m.hiddenFrames;
    m.iouMean += s.iou, m.missedHiddenMean += s.missedHidden;
    if (s.iou < m.iouWorst) m.iouWorst = s.iou, m.worstIouFrame = frame;
    if (s.missedHidden > m.missedHiddenWorst || m.worstMissedFrame < 0)
      m.missedHiddenWorst = std::max(m.missedHiddenWorst, s.missedHidden), m.worstMissedFrame = frame;
  }
  if (s.truthVisible >= kMinVisiblePixels) {
    ++m.visibleFrames;
    m.falseHiddenMean += s.falseHidden;
    if (s.falseHidden > m.falseHiddenWorst || m.worstFalseFrame < 0)
      m.falseHiddenWorst = std::max(m.falseHiddenWorst, s.falseHidden), m.worstFalseFrame = frame;
  }
}

void finishSummary(MaskSummary& m) {
  if (m.hiddenFrames > 0) {
    m.iouMean /= m.hiddenFrames, m.missedHiddenMean /= m.hiddenFrames;
  } else {
    m.iouMean = m.iouWorst = m.missedHiddenMean = m.missedHiddenWorst = kNaN;
  }
  if (m.visibleFrames > 0) m.falseHiddenMean /= m.visibleFrames;
  else m.falseHiddenMean = m.falseHiddenWorst = kNaN;
  m.pooledIou = m.unionPixels > 0 ? static_cast<double>(m.found) / static_cast<double>(m.unionPixels) : kNaN;
  m.pooledFalseHidden = m.truthVisible > 0 ? static_cast<double>(m.visibleSaidHidden) / static_cast<double>(m.truthVisible) : kNaN;
  m.pooledMissedHidden = m.truthHidden > 0 ? 1.0 - static_cast<double>(m.found) / static_cast<double>(m.truthHidden) : kNaN;
}

OcclusionSequence standardOcclusionSequence(const SequenceRenderer& renderer, const std::string& scenario, int frames,
                                            int scale) {
  std::vector<RenderedScenario> rendered = renderScenarios(renderer, frames, {scenario});
  if (rendered.empty()) throw std::invalid_argument("no standard scenario " + scenario);
  OcclusionSequence s;
  s.name = scenario;
  s.fps = rendered[0].scenario.fps;
  s.frames = std::move(rendered[0].frames);
  s.poses = rendered[0].scenario.cameraToWorld;
  for (std::size_t i = 0; i < s.poses.size(); ++i) {
    cv::Mat on, hid;
    renderer.targetCoverage({SubFrame{s.poses[i], {}}}, rendered[0].scenario.effects[i], on, hid);
    s.truth.push_back(maskTruth(on, hid, scale));
  }
  return s;
}

OcclusionSequence stressOcclusionSequence(const SequenceRenderer& renderer, StressClass kind, std::uint64_t seed,
                                          int frames, int scale, int threads) {
  const StressSequence sequence =
      stressSequence(renderer, kind, seed, frames > 0 ? frames : defaultStressFrames(kind));
  std::vector<double> ms;
  RenderedScenario rendered = cachedRender(renderer, sequence, StressOptions{}, threads, ms);
  OcclusionSequence s;
  s.name = sequence.scenario.name;
  s.fps = sequence.scenario.fps;
  s.frames = std::move(rendered.frames);
  s.poses = sequence.scenario.cameraToWorld;
  for (std::size_t i = 0; i < s.poses.size(); ++i) {
    cv::Mat on, hid;
    renderer.targetCoverage(sequence.frames[i].subFrames, sequence.scenario.effects[i], on, hid);
    s.truth.push_back(maskTruth(on, hid, scale));
  }
  return s;
}

std::unique_ptr<TargetOcclusion> standardTargetOcclusion(const CameraModel& camera, const OcclusionSettings& settings) {
  const TargetPyramid p = standardTargetPyramid();
  const cv::Mat& g = p.levels[0];
  std::array<double, 9> planeToImage{};
  for (int k = 0; k < 9; ++k) planeToImage[static_cast<std::size_t>(k)] = p.planeToImage.val[k];
  Diagnostics d;
  auto o = TargetOcclusion::create(camera, ImageView{g.data, g.cols, g.rows, 1, static_cast<std::ptrdiff_t>(g.step)},
                                   planeToImage, settings, d);
  if (!o) throw std::runtime_error(d.format());
  return o;
}

namespace {
ImageView viewOf(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)};
}
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

MaskSummary maskAtExactPoses(const OcclusionSequence& sequence, const CameraModel& camera,
                             const OcclusionSettings& settings, std::vector<MaskScore>* perFrame) {
  auto occlusion = standardTargetOcclusion(camera, settings);
  MaskSummary summary;
  for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    occlusion->update(viewOf(sequence.frames[i]), sequence.poses[i]);
    summary.ms.push_back(msSince(t0));
    const MaskScore score = scoreMask(occlusion->mask(), sequence.truth[i]);
    addFrame(summary, score, static_cast<int>(i));
    if (perFrame) perFrame->push_back(score);
  }
  finishSummary(summary);
  return summary;
}

MaskSummary maskAtTrackerPoses(const OcclusionSequence& sequence, const CameraModel& camera,
                               const MarkerlessSettings& settings, int& drawnFrames, std::vector<MaskScore>* perFrame,
                               MaskSummary* drawnPose) {
  std::unique_ptr<TargetOcclusion> standalone = drawnPose ? standardTargetOcclusion(camera, settings.occlusion) : nullptr;
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(camera, standardTargetImage(), kStandardTargetWidth, settings, d);
  if (!tracker) throw std::runtime_error(d.format());
  MaskSummary summary;
  drawnFrames = 0;
  for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
    const TrackedPose p = tracker->update(viewOf(sequence.frames[i]), static_cast<double>(i) / sequence.fps);
    const bool drawn = p.state != TrackingState::Lost;
    const auto t0 = std::chrono::steady_clock::now();
    const OcclusionMask* mask = tracker->occlusionMask();
    const double ms = msSince(t0);
    if (!drawn || !mask) {
      if (perFrame) perFrame->push_back(MaskScore{.iou = std::nan(""), .falseHidden = std::nan(""), .missedHidden = std::nan("")});
      continue;
    }
    ++drawnFrames;
    summary.ms.push_back(ms);
    if (standalone) {
      standalone->update(viewOf(sequence.frames[i]), p.cameraToWorld);
      addFrame(*drawnPose, scoreMask(standalone->mask(), sequence.truth[i]), static_cast<int>(i));
    }
    const MaskScore score = scoreMask(*mask, sequence.truth[i]);
    addFrame(summary, score, static_cast<int>(i));
    if (perFrame) perFrame->push_back(score);
  }
  finishSummary(summary);
  if (drawnPose) finishSummary(*drawnPose);
  return summary;
}

}  // namespace marionette::ar::synthetic
