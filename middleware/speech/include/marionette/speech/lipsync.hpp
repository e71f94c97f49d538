// Lip-sync curves: phonemes with times -> one weight curve per channel, with
// co-articulation (neighbouring phonemes shape each other), full lip closure
// inside every P / B / M, a limit on how fast a channel may change, a minimum
// visible duration, and a relaxed mouth in pauses. Built once per utterance at
// command time, sampled at `sampleRate`; evaluated per frame by interpolation
// (no allocation, no exceptions).
#pragma once
#include <optional>
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
// The channel of a name lipChannelName gives; nullopt for any other text.
[[nodiscard]] std::optional<int> lipChannelFromName(std::string_view name) noexcept;

// Co-articulation (Cohen & Massaro 1993): every phoneme has a target for its
// channels and a dominance over time: flat over the central `dominanceWidth` of
// its interval, decaying exponentially outside it (before: anticipation, after:
// carry-over). A channel is the dominance-weighted average of all targets plus a
// weak rest target (sil = 1), so far from any phoneme the mouth is at rest. Pauses
// and time no phoneme covers pull toward rest with `pauseDominance`.
// Then, in this order: full closure pinned at the centre of every P / B / M, the speed
// limit (which starts the approach to a closure early instead of breaking it),
// and a clamp to [0,1]. Out-of-range settings are replaced by their defaults.
// Defaults chosen from docs/accuracy.md's lip-sync work-precision table.
struct LipSyncSettings {
  double sampleRate = 100.0;  // curve samples per second (the accuracy knob: higher, finer timing)
  // Curves longer than this many samples get a lower sample rate (memory bound:
  // 2^19 samples x 21 channels = 44 MB, 87 min at 100 Hz).
  int maxFrames = 1 << 19;
  double anticipationRate = 90.0;  // 1/s: how fast a phoneme's dominance rises before its interval
  double carryOverRate = 60.0;     // 1/s: how fast it decays after its interval
  double dominanceWidth = 1.0;     // share of the interval (around its centre) where dominance is flat; 0: peak at the centre
  double pauseDominance = 0.3;     // a pause's dominance against a spoken phoneme's 1: the mouth relaxes into it, not at once
  double restDominance = 0.01;     // the rest target's constant dominance: what the mouth returns to away from speech
  double minVisible = 0.05;        // s: a shorter phoneme's flat dominance is held from its start this long
  // Per second: no channel changes faster; <= 0: no limit. A step is spread over
  // 2 / maxSpeed s centred on it, the approach to a closure over 1 / maxSpeed s.
  double maxSpeed = 16.0;
  // s: a bilabial's full closure (PP = 1, jaw and every other channel 0) is held
  // this long around its centre, and always on the two samples either side of the
  // centre, so that the interpolated curve is closed at the centre itself: a
  // zero-length or 10 ms "m" between two samples closes too.
  double closureHold = 0.02;
};

struct VisemeCurves {
  double sampleRate = 100.0;  // as set, or lower when settings.maxFrames would be exceeded
  double duration = 0.0;      // seconds covered; outside [0, duration] the mouth is at rest
                              // (a non-finite or negative duration: the last finite phoneme end;
                              // 0: no frames, always at rest)
  int frames = 0;
  std::vector<float> values;  // frames x kLipChannelCount, frame-major
  // Samples pinned to full closure (PP = 1, every other channel 0) for a P / B / M,
  // in increasing order: the speed limit never moves them.
  std::vector<int> closureFrames;

  // Channel weights at time t (seconds from the utterance's start) into
  // out[0..kLipChannelCount). Per-frame: no allocation. At rest: sil = 1, others 0.
  void evaluate(double t, std::span<float> out) const noexcept;
};

[[nodiscard]] VisemeCurves buildVisemeCurves(std::span<const Phoneme> phonemes, double duration,
                                             const LipSyncSettings& settings = {});

}  // namespace marionette::speech
