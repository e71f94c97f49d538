// libFuzzer target: WAV files decoded as float clips (speech::parseAudioClip, what
// <bmlt:audiofile> plays), from memory. Contract: no crash; an error names the source; a
// success has 1..64 channels, 1..1000000 Hz, whole frames, no more frames than bytes, every
// sample finite (PCM in [-1, 1)); and the mono reader (readWav) agrees on the rate and the
// frame count. With MARIONETTE_FUZZ_WRITE_SEED=folder the program writes two seeds there
// (stereo 24-bit WAVE_FORMAT_EXTENSIBLE after an odd-sized chunk; stereo float) and exits.
#include <cmath>
#include <cstring>

#include "fuzz_support.hpp"
#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/audio_clip.hpp"
#include "wav_bytes.hpp"

using namespace marionette;
using fuzz::require;
namespace wav = marionette::test::wav;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    std::string list = "LIST";
    wav::put(list, 3, 4);
    list += std::string("abc") + '\0';
    std::string pcm24, f32;
    for (int i = 0; i < 64; ++i) {
      const double s = std::sin(0.3 * i);
      wav::put(pcm24, static_cast<std::uint32_t>(static_cast<std::int32_t>(s * 4e6)) & 0xFFFFFFu, 3);
      wav::put(pcm24, static_cast<std::uint32_t>(static_cast<std::int32_t>(-s * 4e6)) & 0xFFFFFFu, 3);
      for (const float v : {static_cast<float>(s), static_cast<float>(s * 0.5)}) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        wav::put(f32, bits, 4);
      }
    }
    std::ofstream(std::string(dir) + "/extensible24.wav", std::ios::binary)
        << wav::makeWav(wav::extensibleFmt(1, 2, 48000, 24), pcm24, list);
    std::ofstream(std::string(dir) + "/float_stereo.wav", std::ios::binary)
        << wav::makeWav(wav::fmtBody(3, 2, 44100, 32), f32);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  speech::AudioClip clip;
  const std::string error = speech::parseAudioClip(std::span(data, size), "in.wav", clip);
  if (!error.empty()) {
    require(error.rfind("in.wav: ", 0) == 0, "the error does not name the source");
    require(clip.samples.empty(), "an error left samples");
    return 0;
  }
  require(clip.channels >= 1 && clip.channels <= 64, "channels out of range");
  require(clip.sampleRate >= 1 && clip.sampleRate <= 1'000'000, "sample rate out of range");
  require(clip.samples.size() % static_cast<std::size_t>(clip.channels) == 0, "not whole frames");
  require(clip.frames() >= 1 && clip.frames() <= size, "frame count out of range");
  for (const float s : clip.samples) {
    require(std::isfinite(s), "a sample is not finite");
    require(clip.sourceFloat || (s >= -1.0f && s <= 1.0f), "a PCM sample outside [-1, 1]");
  }
  require(std::isfinite(clip.duration()) && clip.duration() > 0.0, "duration");
  // The mono reader walks the same chunks: it agrees.
  const std::string path = fuzz::writeInput(data, size, "in.wav");
  speech::WavAudio mono;
  require(speech::readWav(path, mono).empty(), "readWav refuses what parseAudioClip read");
  require(mono.sampleRate == clip.sampleRate && mono.samples.size() == clip.frames(), "the two readers disagree");
  return 0;
}
