// espeak-ng in process (Debian libespeak-ng-dev, GPL-3.0-or-later: a build with
// MARIONETTE_WITH_TTS links it; see docs/credits.md). The text's marks become SSML
// <mark/> elements; espeak-ng's phoneme events give sample-accurate phoneme
// times (their `sample` field) and its mark events the marks' times. espeak-ng
// keeps global state, so every backend shares one engine behind a first-come
// first-served lock, and a line longer than kSpeechPieceBytes is said in pieces
// (text_pieces.hpp), handing the engine on between them: a short line asked from
// another scene or thread waits for one piece (about 11 ms), not for the whole long
// line. It is started on the first synthesize(), not before (a scene without speech pays nothing).
// It keeps its last 32 results process-wide: espeak-ng's wave generator carries
// state between calls, so only a repeat from that store is sample-identical. (A
// scene's SpeechService caches lines too, with their curves and WAV files; this
// one makes repeats across scenes identical.)
#pragma once
#include <memory>
#include <string>

#include "marionette/speech/speech_backend.hpp"

namespace marionette::speech {

// Whether this build has the espeak-ng backend.
[[nodiscard]] bool espeakAvailable() noexcept;
// The espeak-ng backend; null (and `whyNot` says so) when the build has no TTS.
// A missing voice or data directory is reported by synthesize(), as an error naming the voice.
[[nodiscard]] std::shared_ptr<SpeechBackend> makeEspeakBackend(std::string* whyNot = nullptr);

}  // namespace marionette::speech
