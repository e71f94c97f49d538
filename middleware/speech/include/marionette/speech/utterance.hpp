// An utterance: what a speech backend returns for one line of text. Audio (may
// be empty), the phonemes with their times, and the times of the text's marks
// (BML <sync id> inside speech), all in seconds from the utterance's start.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/speech/phoneme.hpp"

namespace marionette::speech {

struct Mark {
  std::string id;
  double time = 0.0;
};

struct Utterance {
  std::string text;
  std::vector<Phoneme> phonemes;      // sorted by start, not overlapping, inside [0, duration]
  std::vector<Mark> marks;            // in text order, times non-decreasing
  std::vector<std::int16_t> audio;    // mono 16-bit PCM; empty when the source has none
  int sampleRate = 0;                 // of `audio`
  double duration = 0.0;              // seconds: the audio's length, else the last phoneme's end
  std::vector<std::string> warnings;  // what was repaired or guessed

  [[nodiscard]] std::optional<double> markTime(std::string_view id) const noexcept;
};

// Makes phoneme timing usable whatever the source did: drops non-finite times,
// sorts by start, clamps every time into [0, duration] (duration: the audio's
// length when there is audio, else the largest end), makes each phoneme end no
// later than the next one starts, and clamps mark times the same way. espeak-ng
// 1.51 at 450 words per minute and above reports times that go backwards and
// run past the end of the audio: this is where that is repaired. A note on each
// kind of repair goes to utterance.warnings.
void normalizeTiming(Utterance& utterance);

}  // namespace marionette::speech
