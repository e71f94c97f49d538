// normalizeTiming: every kind of bad timing a speech source can hand over is
// repaired into sorted, non-overlapping phonemes inside [0, duration], with one
// warning per kind of repair saying how many were repaired.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "marionette/speech/utterance.hpp"

using namespace marionette::speech;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Phoneme ph(const char* name, double start, double end) {
  Phoneme p;
  p.name = name;
  p.start = start;
  p.end = end;
  return p;
}

// The warning that mentions `what`, or "" (and a failure) if there is none.
std::string warningAbout(const Utterance& u, std::string_view what) {
  for (const std::string& w : u.warnings)
    if (w.find(what) != std::string::npos) return w;
  ADD_FAILURE() << "no warning about '" << what << "'";
  return {};
}

int countWarningsAbout(const Utterance& u, std::string_view what) {
  return static_cast<int>(std::count_if(u.warnings.begin(), u.warnings.end(),
                                        [&](const std::string& w) { return w.find(what) != std::string::npos; }));
}

// The invariants the header promises, whatever went in.
void expectValid(const Utterance& u) {
  ASSERT_TRUE(std::isfinite(u.duration));
  EXPECT_GE(u.duration, 0.0);
  for (std::size_t i = 0; i < u.phonemes.size(); ++i) {
    const Phoneme& p = u.phonemes[i];
    EXPECT_TRUE(std::isfinite(p.start) && std::isfinite(p.end)) << i;
    EXPECT_GE(p.start, 0.0) << i;
    EXPECT_LE(p.end, u.duration) << i;
    EXPECT_LE(p.start, p.end) << i;
    if (i + 1 < u.phonemes.size()) {
      EXPECT_LE(p.end, u.phonemes[i + 1].start) << i;
    }
  }
  for (std::size_t i = 0; i < u.marks.size(); ++i) {
    EXPECT_TRUE(std::isfinite(u.marks[i].time)) << u.marks[i].id;
    EXPECT_GE(u.marks[i].time, 0.0) << u.marks[i].id;
    EXPECT_LE(u.marks[i].time, u.duration) << u.marks[i].id;
    if (i > 0) {
      EXPECT_LE(u.marks[i - 1].time, u.marks[i].time) << u.marks[i].id;
    }
  }
}

}  // namespace

TEST(Utterance, MarkTimeFindsTheIdAndNothingElse) {
  Utterance u;
  u.marks = {{"w1", 0.25}, {"w2", 0.5}};
  ASSERT_TRUE(u.markTime("w2").has_value());
  EXPECT_DOUBLE_EQ(*u.markTime("w2"), 0.5);
  EXPECT_DOUBLE_EQ(*u.markTime("w1"), 0.25);
  EXPECT_FALSE(u.markTime("w3").has_value());
  EXPECT_FALSE(u.markTime("").has_value());
}

TEST(NormalizeTiming, GoodTimingIsLeftAloneWithoutWarnings) {
  Utterance u;
  u.phonemes = {ph("h", 0.0, 0.05), ph("@", 0.05, 0.1), ph("l", 0.1, 0.2)};
  u.marks = {{"a", 0.0}, {"b", 0.1}};
  normalizeTiming(u);
  EXPECT_TRUE(u.warnings.empty()) << u.warnings.front();
  ASSERT_EQ(u.phonemes.size(), 3u);
  EXPECT_DOUBLE_EQ(u.phonemes[1].start, 0.05);
  EXPECT_DOUBLE_EQ(u.duration, 0.2);  // no audio: the largest end
}

TEST(NormalizeTiming, BackwardsStartsAreSortedStablyAndCounted) {
  Utterance u;
  u.phonemes = {ph("a", 0.3, 0.4), ph("b", 0.1, 0.2), ph("c", 0.2, 0.3), ph("d", 0.1, 0.15)};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 4u);
  // b and d start together: stable, so b (first in the source) stays first.
  EXPECT_EQ(u.phonemes[0].name, "b");
  EXPECT_EQ(u.phonemes[1].name, "d");
  EXPECT_EQ(u.phonemes[2].name, "c");
  EXPECT_EQ(u.phonemes[3].name, "a");
  // Two steps went backwards (0.3 -> 0.1 and 0.2 -> 0.1).
  EXPECT_NE(warningAbout(u, "went backwards").find("2 phoneme"), std::string::npos) << u.warnings.front();
  // b (0.1-0.2) overlapped d, which starts at 0.1: cut to zero length.
  EXPECT_DOUBLE_EQ(u.phonemes[0].end, 0.1);
  expectValid(u);
}

TEST(NormalizeTiming, TimesPastTheAudioAreClampedToItsLength) {
  Utterance u;
  u.sampleRate = 1000;
  u.audio.assign(500, 0);  // 0.5 s
  u.phonemes = {ph("a", 0.0, 0.3), ph("b", 0.3, 0.6), ph("c", 0.7, 0.9)};
  u.marks = {{"m", 0.8}};
  normalizeTiming(u);
  EXPECT_DOUBLE_EQ(u.duration, 0.5);  // the audio decides, not the phonemes
  ASSERT_EQ(u.phonemes.size(), 3u);
  EXPECT_DOUBLE_EQ(u.phonemes[1].end, 0.5);
  EXPECT_DOUBLE_EQ(u.phonemes[2].start, 0.5);
  EXPECT_DOUBLE_EQ(u.phonemes[2].end, 0.5);
  EXPECT_DOUBLE_EQ(u.marks[0].time, 0.5);
  EXPECT_NE(warningAbout(u, "outside the utterance").find("2 phoneme"), std::string::npos);
  EXPECT_NE(warningAbout(u, "mark time(s) were outside").find("1 mark"), std::string::npos);
  expectValid(u);
}

TEST(NormalizeTiming, NegativeTimesAreClampedToZero) {
  Utterance u;
  u.phonemes = {ph("a", -0.2, -0.1), ph("b", -0.05, 0.2)};
  u.marks = {{"m", -1.0}};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 2u);
  EXPECT_DOUBLE_EQ(u.phonemes[0].start, 0.0);
  EXPECT_DOUBLE_EQ(u.phonemes[0].end, 0.0);
  EXPECT_DOUBLE_EQ(u.phonemes[1].start, 0.0);
  EXPECT_DOUBLE_EQ(u.marks[0].time, 0.0);
  EXPECT_NE(warningAbout(u, "outside the utterance").find("2 phoneme"), std::string::npos);
  expectValid(u);
}

TEST(NormalizeTiming, NonFiniteStartsAreDroppedAndNonFiniteEndsFilled) {
  Utterance u;
  u.phonemes = {ph("a", 0.0, 0.1), ph("nan", kNaN, 0.2), ph("inf", kInf, kInf), ph("b", 0.1, kNaN),
                ph("c", 0.3, -kInf), ph("d", 0.4, 0.5)};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 4u);
  EXPECT_EQ(u.phonemes[0].name, "a");
  EXPECT_EQ(u.phonemes[1].name, "b");
  EXPECT_DOUBLE_EQ(u.phonemes[1].end, 0.3);  // filled: where c starts
  EXPECT_DOUBLE_EQ(u.phonemes[2].end, 0.4);  // filled: where d starts
  EXPECT_DOUBLE_EQ(u.duration, 0.5);         // the largest finite end
  EXPECT_NE(warningAbout(u, "dropped").find("2 phoneme"), std::string::npos);
  EXPECT_NE(warningAbout(u, "end time(s) were not finite").find("2 phoneme"), std::string::npos);
  expectValid(u);
}

TEST(NormalizeTiming, NonFiniteEndOfTheLastPhonemeBecomesTheAudioEnd) {
  Utterance u;
  u.sampleRate = 100;
  u.audio.assign(100, 0);
  u.phonemes = {ph("a", 0.2, kInf)};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 1u);
  EXPECT_DOUBLE_EQ(u.phonemes[0].end, 1.0);
  EXPECT_EQ(countWarningsAbout(u, "end time(s) were not finite"), 1);
  expectValid(u);
}

TEST(NormalizeTiming, OverlapsAreCutAtTheNextStart) {
  Utterance u;
  u.phonemes = {ph("a", 0.0, 0.25), ph("b", 0.2, 0.5), ph("c", 0.4, 0.45), ph("d", 0.45, 0.6)};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 4u);
  EXPECT_DOUBLE_EQ(u.phonemes[0].end, 0.2);
  EXPECT_DOUBLE_EQ(u.phonemes[1].end, 0.4);
  EXPECT_DOUBLE_EQ(u.phonemes[2].end, 0.45);
  EXPECT_NE(warningAbout(u, "overlapped").find("2 phoneme"), std::string::npos);
  expectValid(u);
}

TEST(NormalizeTiming, ZeroLengthPhonemesAreKeptAndEndsBeforeStartsRepaired) {
  Utterance u;
  u.phonemes = {ph("a", 0.0, 0.1), ph("zero", 0.1, 0.1), ph("rev", 0.2, 0.15), ph("b", 0.3, 0.4)};
  normalizeTiming(u);
  ASSERT_EQ(u.phonemes.size(), 4u);  // a zero-length phoneme is valid, not dropped
  EXPECT_EQ(u.phonemes[1].name, "zero");
  EXPECT_DOUBLE_EQ(u.phonemes[1].start, u.phonemes[1].end);
  EXPECT_EQ(u.phonemes[2].name, "rev");
  EXPECT_DOUBLE_EQ(u.phonemes[2].end, 0.2);
  // Only the reversed one is a repair; the zero-length one is not.
  EXPECT_NE(warningAbout(u, "ended before they started").find("1 phoneme"), std::string::npos);
  EXPECT_EQ(u.warnings.size(), 1u);
  expectValid(u);
}

TEST(NormalizeTiming, MarksAreClampedMadeNonDecreasingAndKept) {
  Utterance u;
  u.phonemes = {ph("a", 0.0, 1.0)};
  u.marks = {{"m1", 0.5}, {"m2", 0.3}, {"m3", kNaN}, {"m4", 2.0}, {"m5", kInf}, {"m6", 0.9}};
  normalizeTiming(u);
  ASSERT_EQ(u.marks.size(), 6u);  // a scheduler waits on each id: none is dropped
  EXPECT_DOUBLE_EQ(*u.markTime("m1"), 0.5);
  EXPECT_DOUBLE_EQ(*u.markTime("m2"), 0.5);  // backwards: moved up to m1
  EXPECT_DOUBLE_EQ(*u.markTime("m3"), 0.5);  // NaN: the previous mark's time
  EXPECT_DOUBLE_EQ(*u.markTime("m4"), 1.0);  // past the end: clamped
  EXPECT_DOUBLE_EQ(*u.markTime("m5"), 1.0);  // +inf: the end
  EXPECT_DOUBLE_EQ(*u.markTime("m6"), 1.0);  // behind m5 now: moved up
  EXPECT_NE(warningAbout(u, "mark time(s) were not finite").find("2 mark"), std::string::npos);
  EXPECT_NE(warningAbout(u, "mark time(s) were outside").find("1 mark"), std::string::npos);
  EXPECT_NE(warningAbout(u, "mark time(s) went backwards").find("2 mark"), std::string::npos);
  expectValid(u);
}

TEST(NormalizeTiming, OneWarningPerKindAndIdempotent) {
  Utterance u;
  u.sampleRate = 1000;
  u.audio.assign(1000, 0);
  u.phonemes = {ph("a", 0.5, 0.7), ph("b", 0.1, 0.6), ph("c", 0.3, 0.35), ph("d", 0.9, 1.4), ph("e", 1.2, 1.3)};
  normalizeTiming(u);
  EXPECT_EQ(countWarningsAbout(u, "went backwards"), 1);
  EXPECT_EQ(countWarningsAbout(u, "outside the utterance"), 1);
  EXPECT_EQ(countWarningsAbout(u, "overlapped"), 1);
  expectValid(u);
  const auto once = u.phonemes;
  const auto warnings = u.warnings.size();
  normalizeTiming(u);  // already normal: nothing to repair, nothing changes
  EXPECT_EQ(u.warnings.size(), warnings);
  ASSERT_EQ(u.phonemes.size(), once.size());
  for (std::size_t i = 0; i < once.size(); ++i) {
    EXPECT_EQ(u.phonemes[i].start, once[i].start);
    EXPECT_EQ(u.phonemes[i].end, once[i].end);
  }
}

TEST(NormalizeTiming, EmptyUtteranceIsValid) {
  Utterance u;
  normalizeTiming(u);
  EXPECT_DOUBLE_EQ(u.duration, 0.0);
  EXPECT_TRUE(u.warnings.empty());
  Utterance silent;
  silent.sampleRate = 22050;
  silent.audio.assign(2205, 0);
  silent.marks = {{"m", 0.05}};
  normalizeTiming(silent);
  EXPECT_NEAR(silent.duration, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(*silent.markTime("m"), 0.05);
}

TEST(NormalizeTiming, AudioWithoutSampleRateFallsBackToThePhonemesWithAWarning) {
  Utterance u;
  u.audio.assign(100, 0);
  u.phonemes = {ph("a", 0.0, 0.4)};
  normalizeTiming(u);
  EXPECT_DOUBLE_EQ(u.duration, 0.4);
  EXPECT_EQ(countWarningsAbout(u, "no sample rate"), 1);
}
