// WAV files as float clips (speech/audio_clip.hpp): the real ARCTIC recording, every sample
// format and layout other writers produce, and broken files, each error naming the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/audio_clip.hpp"
#include "test_data.hpp"
#include "wav_bytes.hpp"

namespace {

using namespace marionette::speech;
using namespace marionette::test::wav;
using marionette::test::sharedAsset;

std::string parse(const std::string& bytes, AudioClip& clip) {
  return parseAudioClip(std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), "x.wav", clip);
}

std::string floatBits(float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  std::string s;
  put(s, bits, 4);
  return s;
}

TEST(AudioClip, ReadsTheArcticRecordingAsTheMonoReaderDoes) {
  const std::string path = sharedAsset("speech/arctic_a0009.wav");
  MARIONETTE_REQUIRE_FILE(path);
  AudioClip clip;
  const std::string error = readAudioClip({}, path, clip);
  ASSERT_TRUE(error.empty()) << error;
  // ASSETS.md: 16-bit mono 16,000 Hz, 49,520 frames = 3.095 s, peak 21,297.
  EXPECT_EQ(clip.channels, 1);
  EXPECT_EQ(clip.sampleRate, 16000);
  EXPECT_EQ(clip.sourceBits, 16);
  EXPECT_FALSE(clip.sourceFloat);
  ASSERT_EQ(clip.frames(), 49520u);
  EXPECT_DOUBLE_EQ(clip.duration(), 3.095);
  WavAudio mono;
  ASSERT_TRUE(readWav(path, mono).empty());
  float peak = 0.0f;
  for (std::size_t i = 0; i < clip.frames(); ++i) {
    ASSERT_EQ(clip.samples[i] * 32768.0f, static_cast<float>(mono.samples[i])) << i;  // exact: a power of two
    peak = std::max(peak, std::abs(clip.samples[i]));
  }
  EXPECT_FLOAT_EQ(peak * 32768.0f, 21297.0f);
}

TEST(AudioClip, EverySampleFormatKeepsItsChannels) {
  AudioClip c;
  {  // 8-bit unsigned, stereo: 128 is silence
    const std::string data = {'\x00', '\x80', '\xff', '\x40'};
    ASSERT_TRUE(parse(makeWav(fmtBody(1, 2, 8000, 8), data), c).empty());
    EXPECT_EQ(c.channels, 2);
    ASSERT_EQ(c.frames(), 2u);
    EXPECT_FLOAT_EQ(c.samples[0], -1.0f);
    EXPECT_FLOAT_EQ(c.samples[1], 0.0f);
    EXPECT_FLOAT_EQ(c.samples[2], 127.0f / 128.0f);
    EXPECT_FLOAT_EQ(c.samples[3], -0.5f);
  }
  {  // 16-bit stereo: left and right stay apart (the mono reader would mix them)
    std::string data;
    put(data, 16384, 2);
    put(data, static_cast<std::uint16_t>(-32768), 2);
    ASSERT_TRUE(parse(makeWav(fmtBody(1, 2, 44100, 16), data), c).empty());
    ASSERT_EQ(c.samples.size(), 2u);
    EXPECT_FLOAT_EQ(c.samples[0], 0.5f);
    EXPECT_FLOAT_EQ(c.samples[1], -1.0f);
    EXPECT_EQ(c.sampleRate, 44100);
  }
  {  // 24-bit, three channels
    std::string data;
    put(data, 0x400000, 3);
    put(data, 0xC00000, 3);
    put(data, 0x000001, 3);
    ASSERT_TRUE(parse(makeWav(fmtBody(1, 3, 48000, 24), data), c).empty());
    EXPECT_EQ(c.channels, 3);
    EXPECT_EQ(c.frames(), 1u);
    EXPECT_FLOAT_EQ(c.samples[0], 0.5f);
    EXPECT_FLOAT_EQ(c.samples[1], -0.5f);
    EXPECT_FLOAT_EQ(c.samples[2], 1.0f / 8388608.0f);
    EXPECT_EQ(c.sourceBits, 24);
  }
  {  // 32-bit PCM
    std::string data;
    put(data, 0xC0000000u, 4);
    ASSERT_TRUE(parse(makeWav(fmtBody(1, 1, 16000, 32), data), c).empty());
    EXPECT_FLOAT_EQ(c.samples[0], -0.5f);
  }
  {  // float 32: kept as stored (no clamp at 1: headroom is the engine's), NaN silenced
    const std::string data = floatBits(0.25f) + floatBits(1.5f) + floatBits(std::nanf(""));
    ASSERT_TRUE(parse(makeWav(fmtBody(3, 1, 22050, 32), data), c).empty());
    ASSERT_EQ(c.samples.size(), 3u);
    EXPECT_FLOAT_EQ(c.samples[0], 0.25f);
    EXPECT_FLOAT_EQ(c.samples[1], 1.5f);
    EXPECT_EQ(c.samples[2], 0.0f);
    EXPECT_TRUE(c.sourceFloat);
  }
  {  // float 64 beyond float's range: the largest float, never infinity
    std::string data;
    const double huge = 1e300;
    std::uint64_t bits;
    std::memcpy(&bits, &huge, 8);
    put(data, static_cast<std::uint32_t>(bits), 4);
    put(data, static_cast<std::uint32_t>(bits >> 32), 4);
    ASSERT_TRUE(parse(makeWav(fmtBody(3, 1, 8000, 64), data), c).empty());
    EXPECT_EQ(c.samples[0], std::numeric_limits<float>::max());
  }
  {  // WAVE_FORMAT_EXTENSIBLE stereo 24-bit, after an odd-sized chunk and its pad byte
    std::string list = "LIST";
    put(list, 5, 4);
    list += std::string("abcde") + '\0';
    std::string data;
    put(data, 0x200000, 3);
    put(data, 0xE00000, 3);
    ASSERT_TRUE(parse(makeWav(extensibleFmt(1, 2, 96000, 24), data, list), c).empty());
    EXPECT_EQ(c.channels, 2);
    EXPECT_EQ(c.sampleRate, 96000);
    EXPECT_FLOAT_EQ(c.samples[0], 0.25f);
    EXPECT_FLOAT_EQ(c.samples[1], -0.25f);
  }
  {  // extensible float
    ASSERT_TRUE(parse(makeWav(extensibleFmt(3, 1, 8000, 32), floatBits(-0.75f)), c).empty());
    EXPECT_FLOAT_EQ(c.samples[0], -0.75f);
  }
}

TEST(AudioClip, BrokenFilesAreErrorsNamingTheProblem) {
  AudioClip c;
  auto error = [&](const std::string& bytes) {
    const std::string e = parse(bytes, c);
    EXPECT_EQ(e.rfind("x.wav: ", 0), 0u) << e;  // every error names the file first
    EXPECT_TRUE(c.samples.empty());
    return e;
  };
  std::string data;
  put(data, 1000, 2);
  put(data, 2000, 2);
  const std::string good = makeWav(fmtBody(1, 1, 16000, 16), data);
  ASSERT_TRUE(parse(good, c).empty());

  EXPECT_NE(error("RIFX....WAVEfmt ").find("not a RIFF/WAVE file"), std::string::npos);
  EXPECT_NE(error("").find("not a RIFF/WAVE file"), std::string::npos);
  // Truncated: the data chunk says 4 bytes, 3 are there.
  EXPECT_NE(error(good.substr(0, good.size() - 1)).find("truncated: the data chunk declares 4 bytes, the file holds 3"),
            std::string::npos);
  // A chunk that lies about its size (a LIST of 1000 bytes in a short file).
  std::string lying = "LIST";
  put(lying, 1000, 4);
  EXPECT_NE(error(makeWav(fmtBody(1, 1, 16000, 16), data, lying)).find("chunk 'LIST' at byte 12 declares 1000 bytes"),
            std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(1, 1, 0, 16), data)).find("sample rate 0 Hz"), std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(1, 0, 16000, 16), data)).find("0 channels"), std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(1, 1, 16000, 12), data)).find("12-bit PCM is not supported"), std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(2, 1, 16000, 16), data)).find("format tag 2 is not supported"), std::string::npos);
  EXPECT_NE(error(makeWav(extensibleFmt(0x55, 1, 16000, 16), data)).find("format tag 85 is not supported"),
            std::string::npos);  // MP3 inside an extensible header
  std::string notKsdata = extensibleFmt(1, 1, 16000, 16);
  notKsdata[30] = 0x11;  // the GUID's fixed tail differs: a vendor's sub-format
  EXPECT_NE(error(makeWav(notKsdata, data)).find("unknown WAVE_FORMAT_EXTENSIBLE sub-format"), std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(1, 1, 16000, 16), "")).find("no samples"), std::string::npos);
  EXPECT_NE(error(makeWav(fmtBody(1, 2, 16000, 16), "ab")).find("no samples"), std::string::npos);  // half a frame
  std::string noData = good.substr(0, 12 + 8 + 16);
  EXPECT_NE(error(noData).find("no data chunk"), std::string::npos);
  // The data chunk first, without any fmt.
  std::string onlyData = "RIFF";
  put(onlyData, 12, 4);
  onlyData += "WAVEdata";
  put(onlyData, 0, 4);
  EXPECT_NE(error(onlyData).find("no fmt chunk"), std::string::npos);

  const std::string missing = readAudioClip({}, "/nonexistent/marionette/none.wav", c);
  EXPECT_EQ(missing.rfind("/nonexistent/marionette/none.wav: cannot read the WAV file", 0), 0u) << missing;
}

TEST(AudioClip, AnEnginesReaderGivesTheBytes) {
  std::string data;
  put(data, 8192, 2);
  const std::string wav = makeWav(fmtBody(1, 1, 8000, 16), data);
  std::string asked;
  const marionette::FileReader reader = [&](const std::string& path, std::string& bytes, std::string&) {
    asked = path;
    bytes = wav;
    return true;
  };
  AudioClip c;
  ASSERT_TRUE(readAudioClip(reader, "sounds/ping.wav", c).empty());
  EXPECT_EQ(asked, "sounds/ping.wav");
  ASSERT_EQ(c.samples.size(), 1u);
  EXPECT_FLOAT_EQ(c.samples[0], 0.25f);
}

}  // namespace
