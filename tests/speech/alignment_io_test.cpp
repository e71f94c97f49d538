// Alignment readers: the real CMU ARCTIC alignment in its two forms, Rhubarb's
// TSV, errors that name the file and line, time repairs, and mutated files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "marionette/speech/alignment_io.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette::speech;
using marionette::test::readFile;
using marionette::test::sharedAsset;

// The phone sequence ASSETS.md lists for arctic_a0009 (written down from the
// documentation, not from the reader's output).
const std::vector<std::string> kArcticPhones = {
    "sil", "hh", "iy", "t", "er", "n", "d", "sh", "aa", "r", "p", "l", "iy", "ae", "n", "d", "f", "ey", "s", "t",
    "g", "r", "eh", "g", "s", "ax", "n", "ax", "k", "r", "ao", "s", "dh", "ax", "t", "ey", "b", "ax", "l", "sil"};

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

// Every result is either an error or usable: finite, non-negative, sorted,
// non-overlapping times with end >= start.
::testing::AssertionResult usableOrError(const Alignment& a) {
  if (!a.error.empty()) return ::testing::AssertionSuccess();
  if (a.phonemes.empty()) return ::testing::AssertionFailure() << "no error and no phonemes";
  for (std::size_t i = 0; i < a.phonemes.size(); ++i) {
    const Phoneme& p = a.phonemes[i];
    if (!std::isfinite(p.start) || !std::isfinite(p.end) || p.start < 0.0 || p.end < p.start)
      return ::testing::AssertionFailure() << "phoneme " << i << " has times " << p.start << " .. " << p.end;
    if (i > 0 && p.start < a.phonemes[i - 1].start)
      return ::testing::AssertionFailure() << "phoneme " << i << " starts before phoneme " << i - 1;
    if (i > 0 && a.phonemes[i - 1].end > p.start)
      return ::testing::AssertionFailure() << "phoneme " << i - 1 << " overlaps phoneme " << i;
    if (!std::isfinite(p.cls.jawOpen)) return ::testing::AssertionFailure() << "non-finite jaw";
  }
  return ::testing::AssertionSuccess();
}

TEST(AlignmentIoTest, ArcticPhoneListAndLabelAgree) {
  const std::string phonesPath = sharedAsset("speech/arctic_a0009.phones.txt");
  const std::string labPath = sharedAsset("speech/arctic_a0009_phone.lab");
  MARIONETTE_REQUIRE_FILE(phonesPath);
  MARIONETTE_REQUIRE_FILE(labPath);
  const Alignment list = readAlignment(phonesPath);
  const Alignment lab = readAlignment(labPath);
  ASSERT_TRUE(list.error.empty()) << list.error;
  ASSERT_TRUE(lab.error.empty()) << lab.error;
  EXPECT_TRUE(list.warnings.empty()) << list.warnings.front();
  EXPECT_TRUE(lab.warnings.empty()) << lab.warnings.front();
  EXPECT_EQ(list.alphabet, PhonemeAlphabet::Arpabet);
  EXPECT_EQ(lab.alphabet, PhonemeAlphabet::Arpabet);
  ASSERT_EQ(list.phonemes.size(), 40u);
  ASSERT_EQ(lab.phonemes.size(), 40u);

  // The label's times, read here with nothing but a stream: integers in 100 ns.
  std::istringstream raw(readFile(labPath));
  std::vector<std::pair<double, double>> rawTimes;
  long long s = 0, e = 0;
  std::string label;
  while (raw >> s >> e >> label) rawTimes.emplace_back(static_cast<double>(s), static_cast<double>(e));
  ASSERT_EQ(rawTimes.size(), 40u);

  for (std::size_t i = 0; i < 40; ++i) {
    EXPECT_EQ(list.phonemes[i].name, kArcticPhones[i]) << i;
    EXPECT_EQ(lab.phonemes[i].name, kArcticPhones[i]) << i;
    EXPECT_NEAR(lab.phonemes[i].start, rawTimes[i].first / 1e7, 1e-12) << i;
    EXPECT_NEAR(lab.phonemes[i].end, rawTimes[i].second / 1e7, 1e-12) << i;
    EXPECT_NEAR(list.phonemes[i].start, lab.phonemes[i].start, 1e-9) << i;
    EXPECT_NEAR(list.phonemes[i].end, lab.phonemes[i].end, 1e-9) << i;
    EXPECT_EQ(list.phonemes[i].cls.viseme, lab.phonemes[i].cls.viseme) << i;
    EXPECT_EQ(list.phonemes[i].sample, -1) << "no synthesizer gave a sample position";
  }
  EXPECT_NEAR(lab.phonemes.back().end, 3.075, 1e-12);  // ASSETS.md: last segment ends at 30,750,000
  EXPECT_TRUE(list.phonemes.front().cls.pause);
  EXPECT_TRUE(list.phonemes.back().cls.pause);
  EXPECT_TRUE(list.phonemes[10].cls.bilabial) << "p of 'sharply'";
  EXPECT_TRUE(list.phonemes[36].cls.bilabial) << "b of 'table'";
  EXPECT_TRUE(usableOrError(list));
}

TEST(AlignmentIoTest, SpeakCsvWithHeaderInEspeakMnemonics) {
  const Alignment a = parseAlignment("start,end,phoneme\n0,0.1,h\n0.1,0.25,@\n0.25,0.4,l\n0.4,0.6,oU\n0.6,0.7,_\n",
                                     "hello.csv");
  ASSERT_TRUE(a.error.empty()) << a.error;
  EXPECT_EQ(a.alphabet, PhonemeAlphabet::Espeak);
  ASSERT_EQ(a.phonemes.size(), 5u);
  EXPECT_EQ(a.phonemes[3].name, "oU");
  EXPECT_DOUBLE_EQ(a.phonemes[3].start, 0.4);
  EXPECT_DOUBLE_EQ(a.phonemes[3].end, 0.6);
  EXPECT_EQ(a.phonemes[3].cls.viseme, Viseme::oh);
  EXPECT_TRUE(a.phonemes[4].cls.pause);
  EXPECT_TRUE(a.warnings.empty());
}

TEST(AlignmentIoTest, RhubarbTsvEachShapeLastsUntilTheNext) {
  // Rhubarb's output for a short "bob": rest, open, closed lips, open, rest.
  const std::string tsv = "0.00\tX\n0.05\tB\n0.27\tC\n0.41\tA\n0.50\tD\n0.62\tX\n";
  const Alignment a = parseAlignment(tsv, "bob.tsv");
  ASSERT_TRUE(a.error.empty()) << a.error;
  EXPECT_EQ(a.alphabet, PhonemeAlphabet::Rhubarb);
  ASSERT_EQ(a.phonemes.size(), 6u);
  const double starts[] = {0.0, 0.05, 0.27, 0.41, 0.50, 0.62};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(a.phonemes[i].start, starts[i]);
    EXPECT_DOUBLE_EQ(a.phonemes[i].end, i + 1 < 6 ? starts[i + 1] : starts[i]) << "last one marks the end";
  }
  EXPECT_TRUE(a.phonemes[0].cls.pause);
  EXPECT_TRUE(a.phonemes[3].cls.bilabial);
  EXPECT_EQ(a.phonemes[4].cls.viseme, Viseme::aa);
  EXPECT_TRUE(usableOrError(a));

  // The same through a file, and lower-case shapes.
  const auto path = std::filesystem::temp_directory_path() / ("marionette_rhubarb_" + std::to_string(::getpid()) + ".tsv");
  {
    std::ofstream out(path);
    out << "0.00\tx\n0.10\ta\n0.20\tx\n";
  }
  const Alignment f = readAlignment(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(f.error.empty()) << f.error;
  ASSERT_EQ(f.phonemes.size(), 3u);
  EXPECT_TRUE(f.phonemes[1].cls.bilabial);

  const Alignment bad = parseAlignment("0.00\tX\n0.05\tQ\n", "bad.tsv", AlignmentFormat::Rhubarb);
  EXPECT_TRUE(contains(bad.error, "bad.tsv:2:")) << bad.error;
  EXPECT_TRUE(contains(bad.error, "A-H or X")) << bad.error;
}

TEST(AlignmentIoTest, HtsMonophoneAndStateLevelLabels) {
  const Alignment mono = parseAlignment("0 1300000 sil\n1300000 2050000 hh\n2050000 2700000 iy\n", "mono.lab");
  ASSERT_TRUE(mono.error.empty()) << mono.error;
  ASSERT_EQ(mono.phonemes.size(), 3u);
  EXPECT_EQ(mono.phonemes[1].name, "hh");
  EXPECT_DOUBLE_EQ(mono.phonemes[1].start, 0.13);
  EXPECT_DOUBLE_EQ(mono.phonemes[2].end, 0.27);
  // Small integer times are HTS only when the caller says so.
  const Alignment small = parseAlignment("0 500 sil\n500 900 aa\n", "s.lab", AlignmentFormat::HtsLabel);
  ASSERT_TRUE(small.error.empty()) << small.error;
  EXPECT_DOUBLE_EQ(small.phonemes[1].end, 900e-7);
  // State-level: five states of one phone make one phoneme.
  std::string states;
  for (int k = 0; k < 5; ++k)
    states += std::to_string(k * 100000) + " " + std::to_string((k + 1) * 100000) + " a^b-p+c=d@1_1/A:x[" +
              std::to_string(k + 2) + "]\n";
  states += "500000 900000 b^p-aa+c=d@1_1/A:x[2]\n";
  const Alignment st = parseAlignment(states, "state.lab");
  ASSERT_TRUE(st.error.empty()) << st.error;
  ASSERT_EQ(st.phonemes.size(), 2u);
  EXPECT_EQ(st.phonemes[0].name, "p");
  EXPECT_DOUBLE_EQ(st.phonemes[0].end, 0.05);
  EXPECT_EQ(st.phonemes[1].name, "aa");
}

TEST(AlignmentIoTest, ErrorsNameTheFileTheLineAndWhatWasExpected) {
  const std::string head = "# comment\n0.0 0.1 sil\n";
  {
    const Alignment a = parseAlignment(head + "0.1 abc hh\n", "bad_number.txt");
    EXPECT_TRUE(a.phonemes.empty());
    EXPECT_TRUE(contains(a.error, "bad_number.txt:3:")) << a.error;
    EXPECT_TRUE(contains(a.error, "end time")) << a.error;
    EXPECT_TRUE(contains(a.error, "'abc'")) << a.error;
  }
  {
    const Alignment a = parseAlignment(head + "0.1 0.2 hh\n\n0.2 0.3\n", "missing.txt");
    EXPECT_TRUE(contains(a.error, "missing.txt:5:")) << a.error;
    EXPECT_TRUE(contains(a.error, "3 columns")) << a.error;
  }
  {
    const Alignment a = parseAlignment("0 1300000 x^x-sil+hh=iy\n1300000 2O50000 x^sil-hh+iy=t\n", "typo.lab");
    EXPECT_TRUE(contains(a.error, "typo.lab:2:")) << a.error;
    EXPECT_TRUE(contains(a.error, "100 ns")) << a.error;
  }
  {
    const Alignment a = parseAlignment("0 100000 x^x-+hh=iy\n", "nophone.lab", AlignmentFormat::HtsLabel);
    EXPECT_TRUE(contains(a.error, "nophone.lab:1:")) << a.error;
  }
  {
    // Reversed times are repaired, and the warning names the line.
    const Alignment a = parseAlignment(head + "0.3 0.1 hh\n0.3 0.4 iy\n", "reversed.txt");
    ASSERT_TRUE(a.error.empty()) << a.error;
    ASSERT_FALSE(a.warnings.empty());
    EXPECT_TRUE(contains(a.warnings.front(), "reversed.txt:3:")) << a.warnings.front();
    EXPECT_TRUE(contains(a.warnings.front(), "swapped")) << a.warnings.front();
    EXPECT_DOUBLE_EQ(a.phonemes[1].start, 0.1);
    EXPECT_DOUBLE_EQ(a.phonemes[1].end, 0.3);
    EXPECT_TRUE(usableOrError(a));
  }
  for (const char* empty : {"", "\n\n", "# only a comment\n", "start,end,phoneme\n", "\xEF\xBB\xBF"}) {
    const Alignment a = parseAlignment(empty, "empty.txt");
    EXPECT_TRUE(contains(a.error, "empty.txt")) << "for " << empty << ": " << a.error;
    EXPECT_TRUE(a.phonemes.empty());
  }
  const Alignment missing = readAlignment("/nonexistent/dir/nothing.lab");
  EXPECT_TRUE(contains(missing.error, "/nonexistent/dir/nothing.lab")) << missing.error;
}

TEST(AlignmentIoTest, BadTimesAreRepairedWithWarnings) {
  const Alignment a = parseAlignment(
      "-0.05 0.1 sil\n0.1 nan hh\n0.2 0.5 iy\n0.4 0.6 t\n0.6 inf er\n0.8 0.9 zz\n", "repair.txt");
  ASSERT_TRUE(a.error.empty()) << a.error;
  ASSERT_EQ(a.phonemes.size(), 6u);
  EXPECT_TRUE(usableOrError(a));
  EXPECT_DOUBLE_EQ(a.phonemes[0].start, 0.0);
  EXPECT_DOUBLE_EQ(a.phonemes[1].end, 0.2) << "a non-finite end takes the next start";
  EXPECT_DOUBLE_EQ(a.phonemes[2].end, 0.4) << "an overlap ends the earlier phoneme";
  EXPECT_DOUBLE_EQ(a.phonemes[4].end, 0.8);
  EXPECT_FALSE(classifyPhoneme("zz", PhonemeAlphabet::Arpabet).known);
  const std::string all = joined(a.warnings);
  for (const char* line : {"repair.txt:1:", "repair.txt:2:", "repair.txt:4:", "repair.txt:5:", "repair.txt:6:"})
    EXPECT_TRUE(contains(all, line)) << line << " missing in\n" << all;
  EXPECT_TRUE(contains(all, "unknown phoneme 'zz'")) << all;

  // Rows out of order are sorted.
  const Alignment sorted = parseAlignment("0.2 0.3 b\n0.0 0.1 sil\n0.1 0.2 aa\n", "order.txt");
  ASSERT_TRUE(sorted.error.empty());
  EXPECT_EQ(sorted.phonemes[0].name, "sil");
  EXPECT_EQ(sorted.phonemes[2].name, "b");
  EXPECT_FALSE(sorted.warnings.empty());
}

// Flips, inserts and deletes bytes of real files; every result must be an error
// or usable. A fixed-seed generator keeps failures reproducible.
TEST(AlignmentIoTest, MutatedFilesGiveErrorsOrUsableAlignments) {
  const std::string phonesPath = sharedAsset("speech/arctic_a0009.phones.txt");
  const std::string labPath = sharedAsset("speech/arctic_a0009_phone.lab");
  MARIONETTE_REQUIRE_FILE(phonesPath);
  MARIONETTE_REQUIRE_FILE(labPath);
  const std::vector<std::string> originals = {readFile(phonesPath), readFile(labPath),
                                              "0.00\tX\n0.05\tB\n0.27\tC\n0.41\tA\n0.50\tD\n0.62\tX\n",
                                              "start,end,phoneme\n0,0.1,h\n0.1,0.25,@\n0.25,0.4,l\n"};
  const char interesting[] = "0123456789.-+eE\t\n ,#nanif[]";
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state] {  // xorshift64*
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return state * 2685821657736338717ull;
  };
  int errors = 0, usable = 0;
  for (int iteration = 0; iteration < 4000; ++iteration) {
    std::string text = originals[static_cast<std::size_t>(iteration) % originals.size()];
    const int edits = 1 + static_cast<int>(next() % 8);
    for (int k = 0; k < edits && !text.empty(); ++k) {
      const std::size_t at = next() % text.size();
      switch (next() % 4) {
        case 0: text[at] = static_cast<char>(next() & 0xff); break;
        case 1: text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), interesting[next() % (sizeof interesting - 1)]); break;
        case 2: text.erase(at, 1 + next() % 4); break;
        default: text[at] = interesting[next() % (sizeof interesting - 1)]; break;
      }
    }
    const auto format = static_cast<AlignmentFormat>(next() % 4);
    const Alignment a = parseAlignment(text, "fuzz", format);
    ASSERT_TRUE(usableOrError(a)) << "iteration " << iteration << ":\n" << text;
    (a.error.empty() ? usable : errors) += 1;
  }
  // Both outcomes occur, or the mutations test nothing.
  EXPECT_GT(errors, 100);
  EXPECT_GT(usable, 100);
}

}  // namespace
