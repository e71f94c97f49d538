// WAV files as float clips (audio_clip.hpp), on the chunk walk the mono reader uses too.
#include "marionette/speech/audio_clip.hpp"

#include <algorithm>
#include <limits>

#include "wav_format.hpp"

namespace marionette::speech {

namespace {
constexpr double kFloatMax = std::numeric_limits<float>::max();
}  // namespace

std::string parseAudioClip(std::span<const unsigned char> bytes, std::string_view source, AudioClip& out) {
  out = {};
  const std::string name = source.empty() ? std::string("<audio>") : std::string(source);
  detail::WavLayout wav;
  if (std::string why = detail::parseWavLayout(bytes, wav); !why.empty()) return name + ": " + why;
  // A clip of no length would end as it starts: nothing to play, nothing to time.
  if (wav.frames == 0) return name + ": the data chunk holds no whole frame (no samples to play)";
  const detail::WavFormat& f = wav.format;
  const std::size_t channels = f.channels, bytesPerSample = f.bits / 8u;
  out.samples.resize(wav.frames * channels);
  for (std::size_t i = 0; i < wav.frames; ++i) {
    const unsigned char* frame = wav.data + i * f.blockAlign;
    for (std::size_t c = 0; c < channels; ++c)
      out.samples[i * channels + c] = static_cast<float>(std::clamp(detail::wavSample(frame + c * bytesPerSample, f),
                                                                    -kFloatMax, kFloatMax));  // a 64-bit float: no inf
  }
  out.channels = f.channels;
  out.sampleRate = static_cast<int>(f.sampleRate);
  out.sourceBits = f.bits;
  out.sourceFloat = f.tag == 3;
  return {};
}

std::string readAudioClip(const FileReader& files, const std::filesystem::path& file, AudioClip& out) {
  out = {};
  std::string bytes, why;
  if (!readWholeFile(files, file.generic_string(), kMaxAudioClipBytes, bytes, why))
    return file.string() + ": cannot read the WAV file (" + why + ")";
  return parseAudioClip(std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), file.string(), out);
}

}  // namespace marionette::speech
