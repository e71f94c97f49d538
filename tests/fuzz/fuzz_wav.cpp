// libFuzzer target: WAV files (RIFF/WAVE PCM 8/16/24/32-bit, float 32/64, extensible),
// read by speech::readWav from a temporary file. Contract: no crash; an error names the
// file; a success has a sample rate in 1..1000000 Hz and no more frames than the file
// has bytes, and writeWav's copy of it reads back the same. With
// MARIONETTE_FUZZ_WRITE_SEED=folder the program writes a short valid WAV seed there with
// writeWav and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <cmath>

#include "fuzz_support.hpp"
#include "marionette/speech/alignment_io.hpp"

using namespace marionette;
using fuzz::require;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    std::vector<std::int16_t> samples(160);
    for (std::size_t i = 0; i < samples.size(); ++i)
      samples[i] = static_cast<std::int16_t>(8000.0 * std::sin(0.2 * static_cast<double>(i)));
    const std::string why = speech::writeWav(std::string(dir) + "/sine.wav", samples, 16000);
    if (!why.empty()) std::fprintf(stderr, "%s\n", why.c_str());
    std::exit(why.empty() ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeInput(data, size, "in.wav");
  speech::WavAudio audio;
  const std::string error = speech::readWav(path, audio);
  if (!error.empty()) {
    require(error.find(path) != std::string::npos, "the error does not name the file");
    return 0;
  }
  require(audio.sampleRate >= 1 && audio.sampleRate <= 1'000'000, "sample rate out of range");
  require(audio.samples.size() <= size, "more frames than bytes");
  const std::string copy = (fuzz::tempDir() / "copy.wav").string();
  require(speech::writeWav(copy, audio.samples, audio.sampleRate).empty(), "writeWav failed on what readWav read");
  speech::WavAudio back;
  require(speech::readWav(copy, back).empty(), "writeWav's output does not read");
  require(back.sampleRate == audio.sampleRate && back.samples == audio.samples, "WAV does not round-trip");
  return 0;
}
