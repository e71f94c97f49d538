// marionette::tts_espeak: espeak-ng in process (Debian libespeak-ng-dev,
// GPL-3.0-or-later), a library of its own so that linking marionette::middleware or
// the C API never pulls GPL code in: a program that links this library is covered by
// the GPL (docs/credits.md). Built with MARIONETTE_WITH_TTS. The text's marks become SSML
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
#include "marionette/speech/speech_service.hpp"

namespace marionette::speech {

// The espeak-ng backend. A missing voice or data directory is reported by
// synthesize(), as an error naming the voice. `whyNot` is cleared (the signature of
// SpeechService::SynthesizerFactory).
[[nodiscard]] std::shared_ptr<SpeechBackend> makeEspeakBackend(std::string* whyNot = nullptr);

// Makes espeak-ng the service's synthesizer (asked after its added backends, started
// on the first line it is asked for): what an engine calls once per scene,
//   marionette::speech::useEspeak(scene.speech());
void useEspeak(SpeechService& service);

}  // namespace marionette::speech
