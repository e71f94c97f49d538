// Speech on a character's face: a speech request bound to a spoken line
// (speech/speech_service.hpp) plays its lip-sync curves from the request's
// start. Per frame the curves' channels go into the morph targets the rig maps
// them to (RigJoints::visemes) and the jaw-open channel rotates the jaw joint,
// where the character has one and no morph shows that channel, about the
// character's left axis (RigJoints::leftAxis: a positive angle drops the chin). bind at command
// time; apply per frame (no allocation, no exceptions).
#pragma once
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/speech/speech_backend.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

namespace speech {
struct SpokenLine;
}

struct SpeechState {
  std::shared_ptr<const speech::SpokenLine> line;
  std::size_t nextPhoneme = 0;  // the next phoneme whose start is reported as a viseme
};

// What to say, from a speech request's SpeechParameters (empty text for another
// kind): its text, voice, rate and marks, with a rate outside
// [kMinWordsPerMinute, kMaxWordsPerMinute] replaced by the voice's default and
// marks past the end of the text dropped, each with a note in `warning`.
inline constexpr int kMinWordsPerMinute = 1, kMaxWordsPerMinute = 10000;
[[nodiscard]] speech::SpeechRequest speechRequestOf(const BehaviorRequest& request, std::string& warning);

// Largest jaw rotation (jaw-open channel at 1), radians: a wide-open mouth.
inline constexpr float kMaxJawOpenRadians = 0.30f;

// Why speech will not move the rig's face (a note, not an error); empty when it will.
[[nodiscard]] std::string speechFaceNote(const Rig& rig);

// Channel weights of the line at `localTime` seconds from its start, times `weight`,
// into the morphs (added, clamped to [0,1]) and the jaw. `channels` is scratch of
// at least speech::kLipChannelCount floats.
void applySpeech(const SpeechState& state, float weight, double localTime, const Rig& rig,
                 std::span<float> channels, std::span<float> morphWeights, std::span<Transform> pose) noexcept;

}  // namespace marionette
