// Lip-sync curves: phonemes with times -> one weight curve per channel, with
// co-articulation (neighbouring phonemes shape each other), full lip closure
// inside every P / B / M, a limit on how fast a channel may change, a minimum
// visible duration, and a relaxed mouth in pauses. Built once per utterance at
// command time, sampled at `sampleRate`; evaluated per frame by interpolation
// (no allocation, no exceptions).
#pragma once
#include <span>
#include <string_view>
#include <vector>

#include "marionette/speech/phoneme.hpp"

namespace marionette::speech {

// Channels: the 15 OVR visemes (0..14, in Viseme order), the 5 VRM shapes
// (15..19, VrmViseme order), then the jaw opening (20). All weights are in [0,1].
inline constexpr int kLipChannelCount = 21;
inline constexpr int kVrmChannelBase = 15;
inline constexpr int kJawOpenChannel = 20;
// "sil" .. "ou", "vrm_aa" .. "vrm_oh", "jawOpen"; "" out of range.
[[nodiscard]] std::string_view lipChannelName(int channel) noexcept;

struct LipSyncSettings {
  double sampleRate = 100.0;  // curve samples per second (the accuracy knob: higher, finer timing)
};

struct VisemeCurves {
  double sampleRate = 100.0;
  double duration = 0.0;      // seconds covered; outside [0, duration] the mouth is at rest
  int frames = 0;
  std::vector<float> values;  // frames x kLipChannelCount, frame-major

  // Channel weights at time t (seconds from the utterance's start) into
  // out[0..kLipChannelCount). Per-frame: no allocation. At rest: sil = 1, others 0.
  void evaluate(double t, std::span<float> out) const noexcept;
};

[[nodiscard]] VisemeCurves buildVisemeCurves(std::span<const Phoneme> phonemes, double duration,
                                             const LipSyncSettings& settings = {});

}  // namespace marionette::speech
