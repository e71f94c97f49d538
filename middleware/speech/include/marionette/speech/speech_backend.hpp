// Speech backends: text in, an Utterance out (audio, phoneme times, mark times).
// An interface with several implementations: espeak-ng in-process
// (marionette::tts_espeak, a separate GPL library), recorded voice lines
// (recorded_speech.hpp), or an engine's own. Backends run at command time only.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/speech/utterance.hpp"

namespace marionette::speech {

// A mark inside the text (BML <sync id="w3"/>): its id and how many characters
// (bytes of the UTF-8 text) come before it.
struct TextMark {
  std::string id;
  std::size_t characterOffset = 0;
};

struct SpeechRequest {
  std::string text{};             // plain text, UTF-8
  std::vector<TextMark> marks{};  // in text order
  std::string voice{};            // empty: fallbackVoice
  int wordsPerMinute = 0;       // 0: the backend's default (175 for espeak-ng)
  // The voice for a request without one, and for one whose voice the backend does not have
  // (said with this one, with a warning in the utterance); empty: the backend's default
  // ("en-us" for espeak-ng). SpeechService sets it from its voice names (setVoiceNames).
  std::string fallbackVoice{};
};

struct SpeechResult {
  std::shared_ptr<const Utterance> utterance;  // null on failure
  std::string error;                           // why it failed, for users
};

class SpeechBackend {
 public:
  virtual ~SpeechBackend() = default;
  [[nodiscard]] virtual std::string_view name() const noexcept = 0;
  // Command time: may allocate, read files, run a synthesizer. Safe to call from
  // several threads (a backend serialises what it must). The utterance's phonemes
  // and marks are normalised (normalizeTiming).
  [[nodiscard]] virtual SpeechResult synthesize(const SpeechRequest& request) = 0;
};

}  // namespace marionette::speech
