// The occlusion mask (target_occlusion.hpp) against the synthetic sequences' truth
// (SequenceRenderer::targetCoverage): which mask pixels truly show the target, which of them
// something hides, and how the mask's verdicts compare, per frame and over a sequence. The
// occlusion test and marionette_occlusion_eval share it, so both measure the same thing.
#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>

#include <glm/mat4x4.hpp>

#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "tracking/stress_scenarios.hpp"
#include "tracking/synthetic_sequence.hpp"

namespace marionette::ar::synthetic {

// The truth at the mask's resolution: the frame-sized shares (targetCoverage) averaged over
// each mask pixel's block (scale x scale frame pixels, fewer at the last row and column).
struct MaskTruth {
  cv::Mat onTarget, hidden;  // CV_32FC1, mask-sized, 0..1
};
[[nodiscard]] MaskTruth maskTruth(const cv::Mat& onTarget, const cv::Mat& hidden, int scale);

// One frame. A mask pixel is truly hidden where at least half of its block is target hidden,
// truly visible where at least half is target showing; the mask says hidden at >= 128.
struct MaskScore {
  int truthHidden = 0, truthVisible = 0;  // mask pixels
  bool clipped = false;  // the mask said nothing: more than a quarter of the target clipped
  int predictedHidden = 0;
  int hiddenFound = 0;        // truly hidden and said hidden
  int visibleSaidHidden = 0;  // truly visible and said hidden
  int unionPixels = 0;        // truly hidden or said hidden
  // NaN where undefined (no hidden pixel either way; no visible or no hidden pixel of the truth).
  double iou = 0, falseHidden = 0, missedHidden = 0;
};
[[nodiscard]] MaskScore scoreMask(const OcclusionMask& mask, const MaskTruth& truth);

// Over a sequence's frames: the mean and the worst frame of each rate, over the frames where it
// means something (IoU and the missed share where the truth hides at least minHiddenPixels; the
// false share where at least minVisiblePixels show), and the rates pooled over all pixels.
struct MaskSummary {
  int frames = 0;                       // frames scored
  int hiddenFrames = 0, visibleFrames = 0;
  double iouMean = 0, iouWorst = 1;
  double falseHiddenMean = 0, falseHiddenWorst = 0;
  double missedHiddenMean = 0, missedHiddenWorst = 0;
  double pooledIou = 0, pooledFalseHidden = 0, pooledMissedHidden = 0;
  int worstIouFrame = -1, worstFalseFrame = -1, worstMissedFrame = -1;
  std::vector<double> ms;  // the mask's cost per frame, when measured
  int clippedFrames = 0;   // frames with more than a quarter of the target clipped (nothing said hidden)
  // Sums for the pooled rates.
  long long found = 0, truthHidden = 0, unionPixels = 0, visibleSaidHidden = 0, truthVisible = 0;
};
inline constexpr int kMinHiddenPixels = 20, kMinVisiblePixels = 50;
void addFrame(MaskSummary& summary, const MaskScore& score, int frame);
void finishSummary(MaskSummary& summary);

// A sequence with the truth of its occlusions: RGB8 frames, the exact poses, the truth at the
// mask's scale.
struct OcclusionSequence {
  std::string name;
  double fps = 30;
  std::vector<cv::Mat> frames;
  std::vector<glm::dmat4> poses;
  std::vector<MaskTruth> truth;
};
// A standard scenario (scenarios.hpp) of `frames` frames, rendered.
[[nodiscard]] OcclusionSequence standardOcclusionSequence(const SequenceRenderer& renderer, const std::string& scenario,
                                                          int frames, int scale);
// A stress sequence (stress_scenarios.hpp; frames 0: the class's default length), rendered or read
// from MN_STRESS_CACHE (stress_run.hpp's cachedRender).
[[nodiscard]] OcclusionSequence stressOcclusionSequence(const SequenceRenderer& renderer, StressClass kind,
                                                        std::uint64_t seed, int frames, int scale, int threads = 2);

// The standard target's reference as the markerless tracker keeps it (graf1.png in grey, the plane
// to its pixels), as a TargetOcclusion.
[[nodiscard]] std::unique_ptr<TargetOcclusion> standardTargetOcclusion(const CameraModel& camera,
                                                                       const OcclusionSettings& settings);

// The mask at the exact poses, every frame (TargetOcclusion::update's cost in summary.ms).
[[nodiscard]] MaskSummary maskAtExactPoses(const OcclusionSequence& sequence, const CameraModel& camera,
                                           const OcclusionSettings& settings, std::vector<MaskScore>* perFrame = nullptr);
// The mask a markerless tracker (from the standard target) gives through occlusionMask() over the
// frames it drew a pose for (occlusionMask()'s cost in summary.ms); drawnFrames gets how many.
// With `drawnPose`, also the mask a TargetOcclusion gives at the pose the tracker returned (the
// smoothed one) over the same frames.
[[nodiscard]] MaskSummary maskAtTrackerPoses(const OcclusionSequence& sequence, const CameraModel& camera,
                                             const MarkerlessSettings& settings, int& drawnFrames,
                                             std::vector<MaskScore>* perFrame = nullptr, MaskSummary* drawnPose = nullptr);

}  // namespace marionette::ar::synthetic
