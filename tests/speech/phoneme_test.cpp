// Phoneme classification: the tables against the OVR viseme reference, every
// phoneme of the installed espeak-ng English tables, ARPAbet, Rhubarb, and
// names no table knows (never a crash, always a usable class).
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "marionette/speech/phoneme.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette::speech;

// ---- espeak-ng's compiled phoneme tables (phontab) -------------------------
// Layout (espeak-ng synthdata.c LoadPhData, phoneme.h PHONEME_TAB): a byte with
// the number of tables, 3 padding bytes; per table a byte with its phoneme count,
// a byte with 1 + the index of the table it includes (0: none), 2 padding bytes,
// a 32-byte name, then count 16-byte entries: uint32 mnemonic (up to 4 chars,
// first in the low byte), uint32 flags, uint16 program, uint8 code, uint8 type, ...
constexpr const char* kPhontab = "/usr/lib/x86_64-linux-gnu/espeak-ng-data/phontab";
constexpr int kPhStress = 1, kPhPause = 0, kPhVowel = 2;

struct PhontabEntry {
  std::string mnemonic;
  int type = -1;
};
struct PhontabTable {
  std::string name;
  int includes = 0;
  std::vector<PhontabEntry> entries;
};

std::vector<PhontabTable> parsePhontab(const std::string& bytes, std::string& error) {
  std::vector<PhontabTable> tables;
  auto byte = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
  if (bytes.size() < 4) {
    error = "phontab shorter than its header";
    return {};
  }
  const int count = byte(0);
  std::size_t p = 4;
  for (int t = 0; t < count; ++t) {
    if (p + 36 > bytes.size()) {
      error = "phontab truncated in table " + std::to_string(t);
      return {};
    }
    PhontabTable table;
    const int phonemes = byte(p);
    table.includes = byte(p + 1);
    table.name = std::string(bytes.c_str() + p + 4, strnlen(bytes.c_str() + p + 4, 32));
    p += 36;
    if (p + 16u * phonemes > bytes.size()) {
      error = "phontab truncated in table " + table.name;
      return {};
    }
    for (int i = 0; i < phonemes; ++i, p += 16) {
      PhontabEntry e;
      for (int k = 0; k < 4 && bytes[p + k] != '\0'; ++k) e.mnemonic += bytes[p + k];
      e.type = byte(p + 11);
      table.entries.push_back(e);
    }
    tables.push_back(std::move(table));
  }
  if (p != bytes.size()) error = "phontab has " + std::to_string(bytes.size() - p) + " bytes after its tables";
  return tables;
}

bool printable(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < 0x21 || c > 0x7e) return false;
  return true;
}

// The effective phonemes of a table: its own and those of the tables it includes.
std::map<std::string, int> englishPhonemes(const std::vector<PhontabTable>& tables,
                                           const std::vector<std::string>& names) {
  std::map<std::string, int> out;  // mnemonic -> type (the most derived table wins)
  for (const std::string& name : names) {
    int index = -1;
    for (std::size_t i = 0; i < tables.size(); ++i)
      if (tables[i].name == name) index = static_cast<int>(i);
    EXPECT_GE(index, 0) << "phontab has no table " << name;
    std::vector<int> chain;
    for (int guard = 0; index >= 0 && guard < 16; ++guard) {
      chain.push_back(index);
      index = tables[static_cast<std::size_t>(index)].includes - 1;
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
      for (const PhontabEntry& e : tables[static_cast<std::size_t>(*it)].entries)
        if (printable(e.mnemonic)) out[e.mnemonic] = e.type;
  }
  return out;
}

void expectSane(const PhonemeClass& c, const std::string& what) {
  EXPECT_LT(static_cast<int>(c.viseme), kVisemeCount) << what;
  EXPECT_LE(static_cast<int>(c.vrm), static_cast<int>(VrmViseme::none)) << what;
  EXPECT_TRUE(std::isfinite(c.jawOpen) && c.jawOpen >= 0.0f && c.jawOpen <= 1.0f) << what << " jaw " << c.jawOpen;
  EXPECT_TRUE(std::isfinite(c.vrmAmount) && c.vrmAmount >= 0.0f && c.vrmAmount <= 1.0f) << what;
  if (c.vrm == VrmViseme::none) {
    EXPECT_EQ(c.vrmAmount, 0.0f) << what << ": no shape, no amount";
  }
  if (c.bilabial) {
    EXPECT_EQ(c.viseme, Viseme::PP) << what;
    EXPECT_EQ(c.jawOpen, 0.0f) << what << ": closed lips need a closed jaw";
  }
  if (c.pause) {
    EXPECT_EQ(c.viseme, Viseme::sil) << what;
  }
}

TEST(PhonemeTest, EveryEspeakEnglishPhonemeIsKnown) {
  MARIONETTE_REQUIRE_FILE(kPhontab);
  std::string error;
  const auto tables = parsePhontab(marionette::test::readFile(kPhontab), error);
  ASSERT_TRUE(error.empty()) << error;
  const auto phonemes = englishPhonemes(tables, {"en", "en-us"});
  // en, en-us, base1, base hold 163 printable mnemonics in espeak-ng 1.51; a
  // different data version may add some, but never this few.
  EXPECT_GE(phonemes.size(), 150u);
  for (const char* expected : {"a#", "t#", "U@", "r-", "_:", "_!", "_|", "3:", "aI@", "@L", "i:", "tS", "dZ"})
    EXPECT_TRUE(phonemes.count(expected)) << "phontab parse lost " << expected;
  int vowels = 0, pauses = 0;
  for (const auto& [name, type] : phonemes) {
    const Classification c = classifyPhoneme(name, PhonemeAlphabet::Espeak);
    EXPECT_TRUE(c.known) << "espeak-ng English phoneme '" << name << "' (type " << type << ") is not in the table";
    expectSane(c.cls, "espeak " + name);
    // espeak's own phoneme type must agree with the class.
    if (type == kPhVowel) {
      ++vowels;
      EXPECT_FALSE(c.cls.pause) << name;
      if (name == "m-") {  // syllabic m: a vowel to espeak, closed lips to the eye
        EXPECT_TRUE(c.cls.bilabial);
      } else {
        EXPECT_GT(c.cls.jawOpen, 0.0f) << name << " is a vowel";
        EXPECT_NE(c.cls.vrm, VrmViseme::none) << name << " is a vowel";
      }
    }
    if (type == kPhStress) {
      EXPECT_FALSE(c.cls.pause) << name << " is a stress mark, not a pause";
    }
    if (type == kPhPause && name.size() > 1 && name[0] == '_' && name != "_^_" && name != "_X1") {
      ++pauses;
      EXPECT_TRUE(c.cls.pause) << name << " is a pause";
    }
    // Stress marks around a phoneme are not part of it.
    if (type != kPhStress && name.find_first_of("',%=") == std::string::npos) {
      const Classification stressed = classifyPhoneme("'" + name, PhonemeAlphabet::Espeak);
      EXPECT_TRUE(stressed.known) << "'" << name;
      EXPECT_EQ(stressed.cls.viseme, c.cls.viseme) << "'" << name;
      EXPECT_EQ(classifyPhoneme(",," + name + ",", PhonemeAlphabet::Espeak).cls.jawOpen, c.cls.jawOpen) << name;
    }
  }
  EXPECT_GE(vowels, 50);
  EXPECT_GE(pauses, 5);
}

// The OVR viseme reference, written down independently of the implementation.
TEST(PhonemeTest, ArpabetFullSetFollowsOvrReference) {
  const std::map<std::string, Viseme> expected = {
      {"aa", Viseme::aa}, {"ae", Viseme::aa}, {"ah", Viseme::aa}, {"ao", Viseme::oh}, {"aw", Viseme::aa},
      {"ax", Viseme::aa}, {"axr", Viseme::RR}, {"ay", Viseme::aa}, {"b", Viseme::PP}, {"ch", Viseme::CH},
      {"d", Viseme::DD}, {"dh", Viseme::TH}, {"dx", Viseme::DD}, {"eh", Viseme::E}, {"el", Viseme::nn},
      {"em", Viseme::PP}, {"en", Viseme::nn}, {"er", Viseme::RR}, {"ey", Viseme::E}, {"f", Viseme::FF},
      {"g", Viseme::kk}, {"hh", Viseme::kk}, {"ih", Viseme::ih}, {"ix", Viseme::ih}, {"iy", Viseme::ih},
      {"jh", Viseme::CH}, {"k", Viseme::kk}, {"l", Viseme::nn}, {"m", Viseme::PP}, {"n", Viseme::nn},
      {"ng", Viseme::kk}, {"ow", Viseme::oh}, {"oy", Viseme::oh}, {"p", Viseme::PP}, {"r", Viseme::RR},
      {"s", Viseme::SS}, {"sh", Viseme::CH}, {"t", Viseme::DD}, {"th", Viseme::TH}, {"uh", Viseme::ou},
      {"uw", Viseme::ou}, {"v", Viseme::FF}, {"w", Viseme::ou}, {"wh", Viseme::ou}, {"y", Viseme::ih},
      {"z", Viseme::SS}, {"zh", Viseme::CH}, {"sil", Viseme::sil}, {"pau", Viseme::sil}, {"sp", Viseme::sil},
      {"h#", Viseme::sil}};
  EXPECT_EQ(expected.size(), 51u);
  const std::set<std::string> bilabials = {"p", "b", "m", "em"};
  const std::set<std::string> pauses = {"sil", "pau", "sp", "h#"};
  for (const auto& [name, viseme] : expected) {
    std::string upper = name;
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    for (const std::string& spelling : {name, upper, upper + "0", name + "1", upper + "2"}) {
      if (pauses.count(name) && spelling != name && spelling != upper) continue;  // no stress on silence
      const Classification c = classifyPhoneme(spelling, PhonemeAlphabet::Arpabet);
      EXPECT_TRUE(c.known) << spelling;
      EXPECT_EQ(c.cls.viseme, viseme) << spelling << " is " << visemeName(c.cls.viseme);
      EXPECT_EQ(c.cls.bilabial, bilabials.count(name) == 1) << spelling;
      EXPECT_EQ(c.cls.pause, pauses.count(name) == 1) << spelling;
      expectSane(c.cls, "arpabet " + spelling);
    }
  }
}

TEST(PhonemeTest, EspeakConsonantsFollowOvrReference) {
  const std::map<std::string, Viseme> expected = {
      {"p", Viseme::PP}, {"b", Viseme::PP}, {"m", Viseme::PP}, {"f", Viseme::FF}, {"v", Viseme::FF},
      {"T", Viseme::TH}, {"D", Viseme::TH}, {"t", Viseme::DD}, {"d", Viseme::DD}, {"t#", Viseme::DD},
      {"k", Viseme::kk}, {"g", Viseme::kk}, {"N", Viseme::kk}, {"tS", Viseme::CH}, {"dZ", Viseme::CH},
      {"S", Viseme::CH}, {"Z", Viseme::CH}, {"s", Viseme::SS}, {"z", Viseme::SS}, {"n", Viseme::nn},
      {"l", Viseme::nn}, {"r", Viseme::RR}, {"r-", Viseme::RR}, {"w", Viseme::ou}, {"j", Viseme::ih},
      {"_", Viseme::sil}, {"_:", Viseme::sil}};
  for (const auto& [name, viseme] : expected) {
    const Classification c = classifyPhoneme(name, PhonemeAlphabet::Espeak);
    EXPECT_TRUE(c.known) << name;
    EXPECT_EQ(c.cls.viseme, viseme) << name << " is " << visemeName(c.cls.viseme);
  }
}

TEST(PhonemeTest, BilabialsCloseLipsAndJaw) {
  for (const char* name : {"p", "b", "m", "m-"}) {
    const PhonemeClass c = classifyPhoneme(name, PhonemeAlphabet::Espeak).cls;
    EXPECT_TRUE(c.bilabial) << name;
    EXPECT_EQ(c.viseme, Viseme::PP) << name;
    EXPECT_EQ(c.jawOpen, 0.0f) << name;
  }
  const PhonemeClass a = classifyPhoneme("A", PhonemeAlphabet::Rhubarb).cls;
  EXPECT_TRUE(a.bilabial);
  EXPECT_EQ(a.jawOpen, 0.0f);
  // Nothing else closes the lips: f, v, w and espeak's B (a fricative) do not.
  for (const char* name : {"f", "v", "w", "B", "n", "a"})
    EXPECT_FALSE(classifyPhoneme(name, PhonemeAlphabet::Espeak).cls.bilabial) << name;
}

TEST(PhonemeTest, VowelsShowTheirVrmShapeAndOpenTheJawByHeight) {
  struct Case {
    const char* arpabet;
    const char* espeak;
    VrmViseme vrm;
  };
  // VRM: aa = A, ih = I, ou = U, ee = E, oh = O.
  const Case cases[] = {{"aa", "A:", VrmViseme::aa}, {"iy", "i:", VrmViseme::ih}, {"uw", "u:", VrmViseme::ou},
                        {"eh", "E", VrmViseme::ee}, {"ao", "O:", VrmViseme::oh}};
  for (const Case& k : cases) {
    for (const auto& [name, alphabet] : {std::pair{k.arpabet, PhonemeAlphabet::Arpabet},
                                         std::pair{k.espeak, PhonemeAlphabet::Espeak}}) {
      const PhonemeClass c = classifyPhoneme(name, alphabet).cls;
      EXPECT_EQ(c.vrm, k.vrm) << name << " shows " << vrmVisemeName(c.vrm);
      EXPECT_EQ(c.vrmAmount, 1.0f) << name << ": a full vowel shows its shape fully";
    }
  }
  auto jaw = [](const char* name) { return classifyPhoneme(name, PhonemeAlphabet::Arpabet).cls.jawOpen; };
  EXPECT_GE(jaw("aa"), 0.6f);
  EXPECT_LE(jaw("aa"), 0.8f);
  EXPECT_GT(jaw("aa"), jaw("eh"));
  EXPECT_GT(jaw("eh"), jaw("iy"));
  EXPECT_GT(jaw("ao"), jaw("uw"));
  EXPECT_LT(jaw("iy"), 0.3f);
  EXPECT_LT(jaw("f"), jaw("aa"));
  EXPECT_LT(jaw("s"), 0.15f);
  // Consonants show the VRM shape partly or not at all.
  for (const char* name : {"p", "t", "k", "s", "sh", "f", "th", "n", "l", "r"})
    EXPECT_LT(classifyPhoneme(name, PhonemeAlphabet::Arpabet).cls.vrmAmount, 1.0f) << name;
}

TEST(PhonemeTest, RhubarbShapes) {
  const std::map<std::string, Viseme> expected = {
      {"A", Viseme::PP}, {"B", Viseme::SS}, {"C", Viseme::E},  {"D", Viseme::aa}, {"E", Viseme::oh},
      {"F", Viseme::ou}, {"G", Viseme::FF}, {"H", Viseme::nn}, {"X", Viseme::sil}};
  for (const auto& [name, viseme] : expected) {
    for (const std::string& spelling : {name, std::string(1, static_cast<char>(std::tolower(name[0])))}) {
      const Classification c = classifyPhoneme(spelling, PhonemeAlphabet::Rhubarb);
      EXPECT_TRUE(c.known) << spelling;
      EXPECT_EQ(c.cls.viseme, viseme) << spelling;
      EXPECT_EQ(c.cls.pause, name == "X") << spelling;
      expectSane(c.cls, "rhubarb " + spelling);
    }
  }
  auto jaw = [](const char* s) { return classifyPhoneme(s, PhonemeAlphabet::Rhubarb).cls.jawOpen; };
  EXPECT_GT(jaw("D"), jaw("C"));  // wide open beyond open
  EXPECT_GT(jaw("C"), jaw("B"));  // open beyond teeth together
  EXPECT_GE(jaw("H"), jaw("C"));  // H: at least as open as C
  EXPECT_LT(jaw("H"), jaw("D"));  // but not as far as D
}

TEST(PhonemeTest, UnknownNamesGetTheNearestClass) {
  struct Case {
    const char* name;
    PhonemeAlphabet alphabet;
    const char* nearest;  // the known name whose class it must get
  };
  const Case cases[] = {
      {"aI5", PhonemeAlphabet::Espeak, "aI"},     // longest known prefix
      {"tSx", PhonemeAlphabet::Espeak, "tS"},
      {"'kq", PhonemeAlphabet::Espeak, "k"},      // stress stripped, then prefix
      {"_zz", PhonemeAlphabet::Espeak, "_"},
      {"zhh", PhonemeAlphabet::Arpabet, "zh"},
      {"CHX1", PhonemeAlphabet::Arpabet, "ch"},
      {"Xy", PhonemeAlphabet::Rhubarb, "X"},
  };
  for (const Case& k : cases) {
    const Classification c = classifyPhoneme(k.name, k.alphabet);
    const Classification ref = classifyPhoneme(k.nearest, k.alphabet);
    ASSERT_TRUE(ref.known) << k.nearest;
    EXPECT_FALSE(c.known) << k.name;
    EXPECT_EQ(c.cls.viseme, ref.cls.viseme) << k.name;
    EXPECT_EQ(c.cls.jawOpen, ref.cls.jawOpen) << k.name;
  }
  // No known prefix: the kind of the first letter.
  const Classification ux = classifyPhoneme("ux", PhonemeAlphabet::Arpabet);  // TIMIT's fronted u
  EXPECT_FALSE(ux.known);
  EXPECT_EQ(ux.cls.viseme, Viseme::ou);
  const Classification q = classifyPhoneme("q", PhonemeAlphabet::Arpabet);  // TIMIT glottal stop
  EXPECT_FALSE(q.known);
  EXPECT_FALSE(q.cls.pause);
  EXPECT_GT(q.cls.jawOpen, 0.0f);
  const Classification rz = classifyPhoneme("Z", PhonemeAlphabet::Rhubarb);
  EXPECT_FALSE(rz.known);
  EXPECT_FALSE(rz.cls.pause) << "a letter is a consonant, not silence";
  // Nothing letter-like: silence.
  for (const std::string& s : {std::string(), std::string("\xca\x83"), std::string("\xff\xfe"), std::string("\0x", 2)}) {
    for (PhonemeAlphabet a : {PhonemeAlphabet::Espeak, PhonemeAlphabet::Arpabet, PhonemeAlphabet::Rhubarb}) {
      const Classification c = classifyPhoneme(s, a);
      EXPECT_FALSE(c.known) << "bytes of size " << s.size();
      EXPECT_TRUE(c.cls.pause);
      EXPECT_EQ(c.cls.viseme, Viseme::sil);
    }
  }
  // A length mark on a known phoneme is not a new phoneme.
  const Classification longA = classifyPhoneme("a:", PhonemeAlphabet::Espeak);
  EXPECT_TRUE(longA.known);
  EXPECT_EQ(longA.cls.viseme, classifyPhoneme("a", PhonemeAlphabet::Espeak).cls.viseme);
}

TEST(PhonemeTest, GarbageBytesNeverBreakClassification) {
  std::mt19937 rng(12345);
  for (int i = 0; i < 20000; ++i) {
    std::string s(rng() % 40, '\0');
    for (char& c : s) c = static_cast<char>(rng() & 0xff);
    for (PhonemeAlphabet a : {PhonemeAlphabet::Espeak, PhonemeAlphabet::Arpabet, PhonemeAlphabet::Rhubarb,
                              static_cast<PhonemeAlphabet>(7)}) {
      const Classification c = classifyPhoneme(s, a);
      const PhonemeClass& k = c.cls;
      // Cheap checks per sample; expectSane's messages would flood a failure.
      ASSERT_LT(static_cast<int>(k.viseme), kVisemeCount);
      ASSERT_LE(static_cast<int>(k.vrm), static_cast<int>(VrmViseme::none));
      ASSERT_TRUE(k.jawOpen >= 0.0f && k.jawOpen <= 1.0f);
      ASSERT_TRUE(k.vrmAmount >= 0.0f && k.vrmAmount <= 1.0f);
    }
  }
}

TEST(PhonemeTest, VisemeNames) {
  const char* names[] = {"sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
  for (int i = 0; i < kVisemeCount; ++i) {
    const auto v = static_cast<Viseme>(i);
    EXPECT_EQ(visemeName(v), names[i]);
    ASSERT_TRUE(visemeFromName(names[i]).has_value()) << names[i];
    EXPECT_EQ(*visemeFromName(names[i]), v);
  }
  EXPECT_FALSE(visemeFromName("").has_value());
  EXPECT_FALSE(visemeFromName("xx").has_value());
  EXPECT_EQ(visemeName(static_cast<Viseme>(200)), "");
  EXPECT_EQ(vrmVisemeName(VrmViseme::aa), "aa");
  EXPECT_EQ(vrmVisemeName(VrmViseme::ih), "ih");
  EXPECT_EQ(vrmVisemeName(VrmViseme::ou), "ou");
  EXPECT_EQ(vrmVisemeName(VrmViseme::ee), "ee");
  EXPECT_EQ(vrmVisemeName(VrmViseme::oh), "oh");
  EXPECT_EQ(vrmVisemeName(VrmViseme::none), "");
}

}  // namespace
