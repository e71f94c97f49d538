// WAV reading and writing: the real ARCTIC recording, a bit-exact round trip,
// the sample formats and layouts other writers produce, and broken files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "marionette/speech/alignment_io.hpp"
#include "test_data.hpp"
#include "wav_bytes.hpp"

namespace {

using namespace marionette::speech;
using marionette::test::readFile;
using marionette::test::sharedAsset;
using namespace marionette::test::wav;

namespace fs = std::filesystem;

// A scratch folder per test program run, removed at the end.
class WavIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("marionette_wav_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path file(const std::string& name) const { return dir_ / name; }
  fs::path writeBytes(const std::string& name, const std::string& bytes) const {
    const fs::path p = file(name);
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p;
  }
  fs::path dir_;
};

TEST_F(WavIoTest, ReadsTheArcticRecording) {
  const std::string path = sharedAsset("speech/arctic_a0009.wav");
  MARIONETTE_REQUIRE_FILE(path);
  WavAudio audio;
  const std::string error = readWav(path, audio);
  ASSERT_TRUE(error.empty()) << error;
  // ASSETS.md: 16-bit mono 16,000 Hz, 49,520 frames, peak 21,297.
  EXPECT_EQ(audio.sampleRate, 16000);
  ASSERT_EQ(audio.samples.size(), 49520u);
  int peak = 0;
  for (std::int16_t s : audio.samples) peak = std::max(peak, std::abs(static_cast<int>(s)));
  EXPECT_EQ(peak, 21297);
  // The samples are the file's bytes after its 44-byte header (checked: "data" at 36).
  const std::string bytes = readFile(path);
  ASSERT_EQ(bytes.substr(36, 4), "data");
  for (std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{24760}, std::size_t{49519}}) {
    const auto lo = static_cast<unsigned char>(bytes[44 + 2 * i]), hi = static_cast<unsigned char>(bytes[45 + 2 * i]);
    EXPECT_EQ(audio.samples[i], static_cast<std::int16_t>(lo | (hi << 8))) << i;
  }
}

TEST_F(WavIoTest, RoundTripIsBitExact) {
  const std::string path = sharedAsset("speech/arctic_a0009.wav");
  MARIONETTE_REQUIRE_FILE(path);
  WavAudio audio;
  ASSERT_TRUE(readWav(path, audio).empty());
  const fs::path copy = file("copy.wav");
  const std::string error = writeWav(copy, audio.samples, audio.sampleRate);
  ASSERT_TRUE(error.empty()) << error;
  // The original is a canonical 44-byte-header mono 16-bit file, so the copy is byte-identical.
  EXPECT_EQ(readFile(copy.string()), readFile(path));
  WavAudio back;
  ASSERT_TRUE(readWav(copy, back).empty());
  EXPECT_EQ(back.sampleRate, 16000);
  EXPECT_EQ(back.samples, audio.samples);

  // Extremes and an empty file round-trip too.
  const std::vector<std::int16_t> extremes = {-32768, -1, 0, 1, 32767};
  ASSERT_TRUE(writeWav(file("x.wav"), extremes, 8000).empty());
  ASSERT_TRUE(readWav(file("x.wav"), back).empty());
  EXPECT_EQ(back.samples, extremes);
  EXPECT_EQ(back.sampleRate, 8000);
  ASSERT_TRUE(writeWav(file("empty.wav"), {}, 44100).empty());
  ASSERT_TRUE(readWav(file("empty.wav"), back).empty());
  EXPECT_TRUE(back.samples.empty());
}

TEST_F(WavIoTest, SampleFormatsAndMixdown) {
  WavAudio a;
  {  // 8-bit unsigned: 128 is silence
    const std::string data = {'\x00', '\x80', '\xff'};
    ASSERT_TRUE(readWav(writeBytes("u8.wav", makeWav(fmtBody(1, 1, 8000, 8), data + '\0')), a).empty());
    // Four one-byte frames: 0, 128, 255, 0.
    ASSERT_EQ(a.samples.size(), 4u);
    EXPECT_EQ(a.samples[0], -32768);
    EXPECT_EQ(a.samples[1], 0);
    EXPECT_EQ(a.samples[2], 127 * 256);
  }
  {  // 24-bit signed, reduced to 16 bits with rounding
    std::string data;
    put(data, 0x123456, 3);  // 1193046 / 256 = 4660.34
    put(data, 0xFFFF00, 3);  // -256 / 256 = -1
    put(data, 0x7FFFFF, 3);  // rounds to 32768: clamped
    ASSERT_TRUE(readWav(writeBytes("s24.wav", makeWav(fmtBody(1, 1, 48000, 24), data)), a).empty());
    ASSERT_EQ(a.samples.size(), 3u);
    EXPECT_EQ(a.samples[0], 4660);
    EXPECT_EQ(a.samples[1], -1);
    EXPECT_EQ(a.samples[2], 32767);
    EXPECT_EQ(a.sampleRate, 48000);
  }
  {  // 32-bit signed
    std::string data;
    put(data, 0x40000000u, 4);
    put(data, 0x80000000u, 4);
    ASSERT_TRUE(readWav(writeBytes("s32.wav", makeWav(fmtBody(1, 1, 16000, 32), data)), a).empty());
    ASSERT_EQ(a.samples.size(), 2u);
    EXPECT_EQ(a.samples[0], 16384);
    EXPECT_EQ(a.samples[1], -32768);
  }
  {  // float32, clamped, NaN silenced
    std::string data;
    for (float f : {0.5f, -1.0f, 2.0f, std::nanf("")}) {
      std::uint32_t bits;
      std::memcpy(&bits, &f, 4);
      put(data, bits, 4);
    }
    ASSERT_TRUE(readWav(writeBytes("f32.wav", makeWav(fmtBody(3, 1, 22050, 32), data)), a).empty());
    ASSERT_EQ(a.samples.size(), 4u);
    EXPECT_EQ(a.samples[0], 16384);
    EXPECT_EQ(a.samples[1], -32768);
    EXPECT_EQ(a.samples[2], 32767);
    EXPECT_EQ(a.samples[3], 0);
  }
  {  // stereo 16-bit mixed to the mean
    std::string data;
    put(data, 1000, 2);
    put(data, 3000, 2);
    put(data, static_cast<std::uint16_t>(-4000), 2);
    put(data, 0, 2);
    ASSERT_TRUE(readWav(writeBytes("st.wav", makeWav(fmtBody(1, 2, 16000, 16), data)), a).empty());
    ASSERT_EQ(a.samples.size(), 2u);
    EXPECT_EQ(a.samples[0], 2000);
    EXPECT_EQ(a.samples[1], -2000);
  }
  {  // WAVE_FORMAT_EXTENSIBLE 16-bit PCM, after an odd-sized LIST chunk and its pad byte
    std::string ext = extensibleFmt(1, 1, 16000, 16);
    std::string list = "LIST";
    put(list, 3, 4);
    list += std::string("abc") + '\0';  // 3 bytes and the pad
    std::string data;
    put(data, static_cast<std::uint16_t>(-123), 2);
    put(data, 456, 2);
    ASSERT_TRUE(readWav(writeBytes("ext.wav", makeWav(ext, data, list)), a).empty());
    ASSERT_EQ(a.samples.size(), 2u);
    EXPECT_EQ(a.samples[0], -123);
    EXPECT_EQ(a.samples[1], 456);
    // A sub-format that is not PCM or float is refused.
    ext[24] = 0x55;
    const std::string error = readWav(writeBytes("ext_mp3.wav", makeWav(ext, data, list)), a);
    EXPECT_NE(error.find("ext_mp3.wav"), std::string::npos) << error;
  }
  {  // data before fmt is allowed by RIFF
    std::string data;
    put(data, 777, 2);
    std::string chunks = "data";
    put(chunks, 2, 4);
    chunks += data;
    chunks += "fmt ";
    put(chunks, 16, 4);
    chunks += fmtBody(1, 1, 16000, 16);
    std::string wav = "RIFF";
    put(wav, static_cast<std::uint32_t>(4 + chunks.size()), 4);
    ASSERT_TRUE(readWav(writeBytes("late_fmt.wav", wav + "WAVE" + chunks), a).empty());
    ASSERT_EQ(a.samples.size(), 1u);
    EXPECT_EQ(a.samples[0], 777);
  }
}

TEST_F(WavIoTest, BrokenFilesGiveErrorsNamingTheFile) {
  WavAudio a;
  auto expectError = [&](const std::string& name, const std::string& bytes, const char* why) {
    const std::string error = readWav(writeBytes(name, bytes), a);
    EXPECT_FALSE(error.empty()) << name << ": " << why;
    EXPECT_NE(error.find(name), std::string::npos) << error;
  };
  expectError("empty.wav", "", "empty");
  expectError("text.wav", "hello, this is not audio at all", "not RIFF");
  expectError("mp3.wav", makeWav(fmtBody(0x55, 1, 16000, 16), "ab"), "MP3 tag");
  expectError("bits12.wav", makeWav(fmtBody(1, 1, 16000, 12), "ab"), "12-bit");
  expectError("rate0.wav", makeWav(fmtBody(1, 1, 0, 16), "ab"), "zero rate");
  expectError("chan0.wav", makeWav(fmtBody(1, 0, 16000, 16), "ab"), "zero channels");
  expectError("shortfmt.wav", makeWav(fmtBody(1, 1, 16000, 16).substr(0, 12), "ab"), "fmt too short");
  std::string noData = makeWav(fmtBody(1, 1, 16000, 16), "");
  noData.resize(noData.size() - 8);
  expectError("nodata.wav", noData, "no data chunk");
  const std::string missing = (dir_ / "missing.wav").string();
  EXPECT_NE(readWav(missing, a).find("missing.wav"), std::string::npos);

  // Every truncation of the real file is an error: its data chunk declares its size.
  const std::string path = sharedAsset("speech/arctic_a0009.wav");
  MARIONETTE_REQUIRE_FILE(path);
  const std::string real = readFile(path);
  for (std::size_t length : {std::size_t{0}, std::size_t{4}, std::size_t{11}, std::size_t{12}, std::size_t{20},
                             std::size_t{35}, std::size_t{36}, std::size_t{43}, std::size_t{44}, std::size_t{45},
                             std::size_t{1000}, real.size() - 1}) {
    const std::string error = readWav(writeBytes("cut.wav", real.substr(0, length)), a);
    EXPECT_FALSE(error.empty()) << "cut at " << length;
    EXPECT_NE(error.find("cut.wav"), std::string::npos) << error;
  }

  EXPECT_NE(writeWav(file("bad_rate.wav"), std::vector<std::int16_t>{1, 2}, 0).find("bad_rate.wav"), std::string::npos);
  const std::string unwritable = (dir_ / "no_such_dir" / "out.wav").string();
  EXPECT_NE(writeWav(unwritable, std::vector<std::int16_t>{1, 2}, 16000).find(unwritable), std::string::npos);
}

// Header mutations of a short copy of the real file: an error or sane audio, never a crash.
TEST_F(WavIoTest, MutatedHeadersNeverCrash) {
  const std::string path = sharedAsset("speech/arctic_a0009.wav");
  MARIONETTE_REQUIRE_FILE(path);
  WavAudio audio;
  ASSERT_TRUE(readWav(path, audio).empty());
  const fs::path shortPath = file("short.wav");
  ASSERT_TRUE(writeWav(shortPath, std::span(audio.samples).subspan(20000, 300), 16000).empty());
  const std::string original = readFile(shortPath.string());
  std::uint64_t state = 88172645463325252ull;
  auto next = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  int errors = 0, read = 0;
  for (int iteration = 0; iteration < 3000; ++iteration) {
    std::string bytes = original;
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = next() % 48;  // the header and the first samples
      switch (next() % 3) {
        case 0: bytes[at] = static_cast<char>(next() & 0xff); break;
        case 1: bytes.insert(at, 1, static_cast<char>(next() & 0xff)); break;
        default: bytes.erase(at, 1); break;
      }
    }
    if (next() % 4 == 0) bytes.resize(next() % bytes.size());
    WavAudio out;
    const std::string error = readWav(writeBytes("fuzz.wav", bytes), out);
    if (!error.empty()) {
      ++errors;
      continue;
    }
    ++read;
    ASSERT_GT(out.sampleRate, 0) << iteration;
    ASSERT_LE(out.samples.size(), bytes.size()) << iteration;
  }
  EXPECT_GT(errors, 100);
  EXPECT_GT(read, 100);
}

}  // namespace
