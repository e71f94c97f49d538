// The build without MARIONETTE_WITH_TTS: no espeak-ng backend.
#include "marionette/speech/espeak_backend.hpp"

namespace marionette::speech {

bool espeakAvailable() noexcept { return false; }

std::shared_ptr<SpeechBackend> makeEspeakBackend(std::string* whyNot) {
  if (whyNot)
    *whyNot = "this build has no speech synthesis (configured with MARIONETTE_WITH_TTS=OFF); "
              "speech needs recorded voice lines or an engine's own backend";
  return nullptr;
}

}  // namespace marionette::speech
