// The example programs' speech synthesizer: espeak-ng (marionette::tts_espeak, GPL)
// when the build has it; otherwise a synthesizer that is not there, saying why.
// The programs link espeak-ng on purpose (they are tools, and say lines); an engine
// that links only the middleware or the C API gets no GPL code.
#pragma once
#include <memory>
#include <string>

#include "marionette/speech/speech_service.hpp"
#ifdef MARIONETTE_HAS_TTS
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif

namespace marionette::examples {

// The synthesizer itself (SpeechService::SynthesizerFactory's signature).
inline std::shared_ptr<speech::SpeechBackend> exampleSynthesizer(std::string* whyNot) {
#ifdef MARIONETTE_HAS_TTS
  return speech::makeEspeakBackend(whyNot);
#else
  if (whyNot)
    *whyNot = "this build has no speech synthesis (configured with MARIONETTE_WITH_TTS=OFF); "
              "speech needs recorded voice lines or an engine's own backend";
  return nullptr;
#endif
}

inline void useExampleSynthesizer(speech::SpeechService& service) { service.setSynthesizer(&exampleSynthesizer); }

}  // namespace marionette::examples
