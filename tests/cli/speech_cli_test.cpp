// `marionette speak`, `marionette lipsync` and speech in `marionette run`, run as a user would.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/lipsync.hpp"
#include "test_data.hpp"

using namespace marionette::test;

namespace {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

Csv readCsv(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (first) csv.header = std::move(cells), first = false;
    else csv.rows.push_back(std::move(cells));
  }
  return csv;
}

std::string tempPath(const std::string& name) { return ::testing::TempDir() + name; }

// V.csv as the issue defines it: time, then every lip channel; a row per 1/100 s; weights in [0,1].
void expectVisemeCsv(const Csv& v, double duration) {
  ASSERT_EQ(v.header.size(), static_cast<std::size_t>(marionette::speech::kLipChannelCount) + 1);
  EXPECT_EQ(v.header[0], "time");
  for (int c = 0; c < marionette::speech::kLipChannelCount; ++c)
    EXPECT_EQ(v.header[static_cast<std::size_t>(c) + 1], marionette::speech::lipChannelName(c));
  EXPECT_EQ(v.rows.size(), static_cast<std::size_t>(std::ceil(duration * 100.0 - 1e-9)) + 1);
  for (std::size_t i = 0; i < v.rows.size(); ++i) {
    ASSERT_EQ(v.rows[i].size(), v.header.size()) << "row " << i;
    EXPECT_NEAR(std::stod(v.rows[i][0]), static_cast<double>(i) / 100.0, 1e-9);
    for (std::size_t c = 1; c < v.rows[i].size(); ++c) {
      const double w = std::stod(v.rows[i][c]);
      ASSERT_TRUE(w >= 0.0 && w <= 1.0) << "row " << i << " " << v.header[c] << " = " << w;
    }
  }
}

std::size_t column(const Csv& csv, const std::string& name) {
  for (std::size_t i = 0; i < csv.header.size(); ++i)
    if (csv.header[i] == name) return i;
  return csv.header.size();
}

}  // namespace

TEST(CliLipsync, RecordedLineGivesVisemeCurvesThatCloseTheLipsOnP) {
  const std::string wav = sharedAsset("speech/arctic_a0009.wav"), phones = sharedAsset("speech/arctic_a0009.phones.txt");
  MARIONETTE_REQUIRE_FILE(wav);
  const std::string out = tempPath("arctic_visemes.csv");
  const CliRun r = runCli("lipsync --audio " + wav + " --phones " + phones + " --visemes " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  const Csv v = readCsv(out);
  expectVisemeCsv(v, 49520.0 / 16000.0);
  // "sharply": p from 0.815 to 0.905 s in the alignment; the lips close inside it.
  const std::size_t pp = column(v, "PP"), jaw = column(v, "jawOpen");
  double closest = 0.0;
  for (int k = 82; k <= 90; ++k)
    if (std::stod(v.rows[static_cast<std::size_t>(k)][jaw]) <= 0.1) closest = std::max(closest, std::stod(v.rows[static_cast<std::size_t>(k)][pp]));
  EXPECT_GE(closest, 0.9);
  // The HTS label of the same recording gives the same curves, up to where times in
  // 100 ns units and in decimal seconds round to different doubles at a sample boundary.
  const std::string fromLab = tempPath("arctic_visemes_lab.csv");
  ASSERT_EQ(runCli("lipsync --audio " + wav + " --phones " + sharedAsset("speech/arctic_a0009_phone.lab") +
                   " --visemes " + fromLab).status, 0);
  const Csv lab = readCsv(fromLab);
  ASSERT_EQ(lab.rows.size(), v.rows.size());
  double sum = 0.0, largest = 0.0;
  std::size_t cells = 0;
  for (std::size_t i = 0; i < v.rows.size(); ++i)
    for (std::size_t c = 1; c < v.header.size(); ++c, ++cells) {
      const double d = std::abs(std::stod(lab.rows[i][c]) - std::stod(v.rows[i][c]));
      sum += d, largest = std::max(largest, d);
    }
  EXPECT_LT(sum / static_cast<double>(cells), 0.002);
  EXPECT_LT(largest, 0.3);
}

TEST(CliLipsync, BadInputIsAnErrorNamingTheFile) {
  const CliRun missing = runCli("lipsync --phones /nonexistent/p.txt --visemes " + tempPath("x.csv"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.out.find("/nonexistent/p.txt"), std::string::npos) << missing.out;
  const std::string bad = tempPath("bad.phones.txt");
  std::ofstream(bad) << "0.0 0.1 sil\n0.1 zero p\n";
  const CliRun garbled = runCli("lipsync --phones " + bad + " --visemes " + tempPath("y.csv"));
  EXPECT_EQ(garbled.status, 2) << garbled.out;
  EXPECT_NE(garbled.out.find(bad + ":2"), std::string::npos) << garbled.out;
  EXPECT_EQ(runCli("lipsync --visemes " + tempPath("z.csv")).status, 2);  // no --phones
  EXPECT_EQ(runCli("lipsync --phones a --visemes b --frobnicate c").status, 2);
}

#ifdef MARIONETTE_CLI_HAS_TTS
TEST(CliSpeak, WritesAudioVisemesAndPhonemes) {
  const std::string wav = tempPath("hello.wav"), v = tempPath("hello_v.csv"), p = tempPath("hello_p.csv");
  const CliRun r = runCli("speak \"Hello world, this is Marionette.\" --voice en-us --rate 160 -o " + wav +
                          " --visemes " + v + " --phonemes " + p);
  ASSERT_LE(r.status, 1) << r.out;
  marionette::speech::WavAudio audio;
  ASSERT_EQ(marionette::speech::readWav(wav, audio), "");
  ASSERT_GT(audio.sampleRate, 0);
  const double duration = static_cast<double>(audio.samples.size()) / audio.sampleRate;
  EXPECT_GT(duration, 1.0);
  expectVisemeCsv(readCsv(v), duration);
  const Csv phonemes = readCsv(p);
  ASSERT_EQ(phonemes.header, (std::vector<std::string>{"start", "end", "phoneme"}));
  ASSERT_GT(phonemes.rows.size(), 15u);
  double last = 0.0;
  for (const auto& row : phonemes.rows) {
    const double start = std::stod(row[0]), end = std::stod(row[1]);
    EXPECT_GE(start, last - 1e-9);
    EXPECT_GE(end, start);
    EXPECT_LE(end, duration + 1e-5);  // the CSV has 5 decimals
    last = start;
  }
  // The phoneme CSV reads back as an alignment (the same format lipsync takes).
  const marionette::speech::Alignment back = marionette::speech::readAlignment(p);
  EXPECT_EQ(back.error, "");
  EXPECT_EQ(back.phonemes.size(), phonemes.rows.size());
}

TEST(CliSpeak, BadArgumentsAndVoicesAreErrors) {
  EXPECT_EQ(runCli("speak \"hi\" -o " + tempPath("a.wav")).status, 2);  // no --visemes
  EXPECT_EQ(runCli("speak \"hi\" --rate fast -o a.wav --visemes v.csv").status, 2);
  // A voice espeak-ng lacks: said in its default voice, a warning naming both (status 1).
  const CliRun voice = runCli("speak \"hi\" --voice xx-nosuchvoice -o " + tempPath("b.wav") + " --visemes " + tempPath("b.csv"));
  EXPECT_EQ(voice.status, 1) << voice.out;
  EXPECT_NE(voice.out.find("no voice 'xx-nosuchvoice'"), std::string::npos) << voice.out;
  EXPECT_NE(voice.out.find("said with 'en-us'"), std::string::npos) << voice.out;
}
#else
TEST(CliSpeak, WithoutTtsSaysTheBuildHasNone) {
  const CliRun r = runCli("speak \"hi\" -o " + tempPath("a.wav") + " --visemes " + tempPath("a.csv"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("MARIONETTE_WITH_TTS"), std::string::npos) << r.out;
}
#endif

#ifdef MARIONETTE_CLI_HAS_BML
// The done-when on a real character: Godette says a recorded line, her
// mouth shapes move while the WAV plays, the nod starts on the word mark.
TEST(CliRunSpeech, GodetteSpeaksWithHerVisemesAndTheWavIsWritten) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
  const std::string morphs = tempPath("godette_morphs.csv"), dir = tempPath("godette_speech");
  std::filesystem::remove_all(dir);
  const CliRun r = runCli("run " + sourceFile("assets/scenes/godette_speaks.json") + " --frames 270 --fps 60 --morphs " +
                          morphs + " --audio-dir " + dir + " --stats");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("speech: godette 'godetteSpeaks:line' at 0.500 s for 3.095 s, audio " + dir), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("speech "), std::string::npos);  // --stats lists the speech controller
  std::size_t wavs = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) wavs += e.path().extension() == ".wav";
  EXPECT_EQ(wavs, 1u);
  // Mouth shapes: at rest before 0.5 s, moving while the line plays (3.1 s), at rest after.
  const Csv m = readCsv(morphs);
  double before = 0.0, during = 0.0, after = 0.0;
  int changes = 0;
  double previous = 0.0;
  for (const auto& row : m.rows) {
    if (row[3] != "ah" && row[3] != "oh" && row[3] != "ih" && row[3] != "ee" && row[3] != "uu") continue;
    const double t = std::stod(row[1]), w = std::stod(row[4]);
    if (t < 0.5) before = std::max(before, w);
    else if (t < 0.5 + 3.095) during = std::max(during, w);
    else if (t > 0.5 + 3.095 + 0.2) after = std::max(after, w);
    if (row[3] == "ah") changes += std::abs(w - previous) > 0.02, previous = w;
  }
  EXPECT_EQ(before, 0.0);
  EXPECT_GT(during, 0.5);
  EXPECT_LT(after, 0.05);
  EXPECT_GT(changes, 20) << "the 'ah' shape should open and close many times over 40 phones";
}
#endif
