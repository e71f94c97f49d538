// Phoneme tables: espeak-ng's English mnemonics, ARPAbet and Rhubarb's shapes,
// each mapped to an OVR viseme, a VRM shape, a jaw opening and flags.
//
// Viseme choices follow the Oculus / OVR viseme reference (PP: p b m, FF: f v,
// TH, DD: t d, kk: k g, CH: ch jh sh zh, SS: s z, nn: n l, RR: r, then the five
// vowel groups). Decisions the reference leaves open:
//   - ng is kk, not nn: it is made with the back of the tongue like k and g, and
//     the lips and jaw look like kk, not like the tongue-tip n.
//   - w is ou (rounded lips), y / j is ih (spread lips), h is kk (an open,
//     neutral mouth that takes the next vowel's shape).
//   - er / espeak's 3 and 3: are RR: American r-coloured vowels round the lips.
//   - schwa is a weak aa (the reference groups "ah" with aa).
//   - the glottal stop shows nothing: sil, not a pause.
// Stress, length, syllable and tone marks are not phonemes; alone they are
// known marks with a neutral mouth and pause=false (they last no time).
#include <algorithm>
#include <array>
#include <cstddef>

#include "marionette/speech/phoneme.hpp"
#include "marionette/core/enum_names.hpp"

namespace marionette::speech {
namespace {

struct Entry {
  std::string_view name;
  PhonemeClass cls;
};

// Builders that keep the tables readable. Full vowels show their VRM shape fully;
// reduced vowels (schwa, weak i) pass a smaller amount.
constexpr PhonemeClass vowel(Viseme v, VrmViseme vrm, float jaw, float amount = 1.0f) {
  return PhonemeClass{v, vrm, amount, jaw, false, false};
}
constexpr PhonemeClass consonant(Viseme v, VrmViseme vrm, float amount, float jaw) {
  return PhonemeClass{v, vrm, amount, jaw, false, false};
}
constexpr PhonemeClass bilabialClass(float jaw = 0.0f) {
  return PhonemeClass{Viseme::PP, VrmViseme::none, 0.0f, jaw, true, false};
}
constexpr PhonemeClass pauseClass() { return PhonemeClass{Viseme::sil, VrmViseme::none, 0.0f, 0.0f, false, true}; }
// A zero-length mark (stress, syllable, tone, word end): neutral, not a pause.
constexpr PhonemeClass markClass() { return PhonemeClass{Viseme::sil, VrmViseme::none, 0.0f, 0.0f, false, false}; }

using V = Viseme;
using R = VrmViseme;

// Shared consonant classes (jaw: fricatives and stops nearly closed).
constexpr PhonemeClass kPP = bilabialClass();
constexpr PhonemeClass kFF = consonant(V::FF, R::ih, 0.2f, 0.05f);
constexpr PhonemeClass kTH = consonant(V::TH, R::ee, 0.2f, 0.1f);
constexpr PhonemeClass kDD = consonant(V::DD, R::ee, 0.2f, 0.15f);
constexpr PhonemeClass kKK = consonant(V::kk, R::ee, 0.2f, 0.2f);
constexpr PhonemeClass kCH = consonant(V::CH, R::ou, 0.4f, 0.1f);
constexpr PhonemeClass kSS = consonant(V::SS, R::ih, 0.3f, 0.05f);
constexpr PhonemeClass kNN = consonant(V::nn, R::ee, 0.2f, 0.15f);
constexpr PhonemeClass kRR = consonant(V::RR, R::ou, 0.3f, 0.15f);
constexpr PhonemeClass kHH = consonant(V::kk, R::aa, 0.3f, 0.25f);
constexpr PhonemeClass kW = consonant(V::ou, R::ou, 0.8f, 0.1f);
constexpr PhonemeClass kY = consonant(V::ih, R::ih, 0.6f, 0.1f);
constexpr PhonemeClass kGlottal = consonant(V::sil, R::none, 0.0f, 0.1f);
constexpr PhonemeClass kPause = pauseClass();
constexpr PhonemeClass kMark = markClass();

// Vowel classes.
constexpr PhonemeClass kOpenA = vowel(V::aa, R::aa, 0.75f);   // ɑ, ɑː, aɪ, aʊ
constexpr PhonemeClass kAsh = vowel(V::aa, R::aa, 0.7f);      // æ
constexpr PhonemeClass kStrut = vowel(V::aa, R::aa, 0.6f);    // ʌ
constexpr PhonemeClass kSchwa = vowel(V::aa, R::aa, 0.35f, 0.6f);
constexpr PhonemeClass kOpenE = vowel(V::E, R::ee, 0.45f);    // ɛ
constexpr PhonemeClass kCloseE = vowel(V::E, R::ee, 0.35f);   // e, eɪ
constexpr PhonemeClass kLaxI = vowel(V::ih, R::ih, 0.2f);     // ɪ
constexpr PhonemeClass kWeakI = vowel(V::ih, R::ih, 0.15f, 0.7f);
constexpr PhonemeClass kCloseI = vowel(V::ih, R::ih, 0.15f);  // iː
constexpr PhonemeClass kOpenO = vowel(V::oh, R::oh, 0.55f);   // ɔ, ɒ
constexpr PhonemeClass kCloseO = vowel(V::oh, R::oh, 0.45f);  // o, oʊ
constexpr PhonemeClass kLaxU = vowel(V::ou, R::ou, 0.25f);    // ʊ
constexpr PhonemeClass kCloseU = vowel(V::ou, R::ou, 0.2f);   // uː
constexpr PhonemeClass kRhotic = vowel(V::RR, R::ou, 0.3f, 0.5f);  // ɚ, ɜː
constexpr PhonemeClass kSyllabicL = vowel(V::nn, R::ee, 0.2f, 0.3f);

// espeak-ng 1.51 English: the tables en and en-us and what they include (base1,
// base), read from phontab; plus a/ and aI2 from the other en-* accents.
// Stress marks (' , % = and doubles) are listed so a lone mark is known.
constexpr std::array kEspeak = std::to_array<Entry>({
    // pauses and marks (base)
    {"_", kPause}, {"_:", kPause}, {"_::", kPause}, {"_!", kPause}, {"_|", kPause}, {"_;_", kPause},
    {"||", kMark}, {"-", kMark}, {":", kMark}, {"1", kMark}, {"_^_", kMark}, {"_X1", kMark}, {"#X1", kMark},
    {"'", kMark}, {"''", kMark}, {"'!", kMark}, {",", kMark}, {",,", kMark}, {"%", kMark}, {"%%", kMark},
    {"=", kMark},
    // vowel-type placeholders used by espeak's rules (base)
    {"#@", kSchwa}, {"#a", kOpenA}, {"#e", kOpenE}, {"#i", kLaxI}, {"#o", kOpenO}, {"#u", kLaxU},
    // schwas
    {"@", kSchwa}, {"@-", kSchwa}, {"@2", kSchwa}, {"@#", kSchwa}, {"@5", vowel(V::ou, R::ou, 0.25f, 0.6f)},
    {"@L", kSyllabicL},
    // a-vowels
    {"a", kAsh}, {"a#", vowel(V::aa, R::aa, 0.5f, 0.7f)}, {"a#2", vowel(V::aa, R::aa, 0.5f, 0.7f)},
    {"a2", kAsh}, {"a/", kAsh}, {"aa", kOpenA}, {"A:", kOpenA}, {"A#", kOpenA}, {"A@", kOpenA}, {"A~", kOpenA},
    {"V", kStrut}, {"VR", kStrut}, {"0", kOpenA}, {"0#", kOpenA}, {"02", kOpenA},
    {"aI", kOpenA}, {"aI@", kOpenA}, {"aI3", kOpenA}, {"aI2", kOpenA}, {"aU", kOpenA}, {"aU@", kOpenA},
    // e-vowels
    {"e", kCloseE}, {"e:", kCloseE}, {"e#", kCloseE}, {"e@", kOpenE}, {"eI", kCloseE},
    {"E", kOpenE}, {"E#", kOpenE}, {"E2", kOpenE},
    // i-vowels
    {"i", kWeakI}, {"i:", kCloseI}, {"i@", kLaxI}, {"i@3", kLaxI}, {"I", kLaxI}, {"I#", kWeakI},
    {"I2", kWeakI}, {"I2#", kWeakI}, {"IR", kLaxI},
    // o-vowels
    {"o", kCloseO}, {"o:", kCloseO}, {"o@", kOpenO}, {"oU", kCloseO}, {"oU#", kCloseO},
    {"O", kOpenO}, {"O:", kOpenO}, {"O2", kOpenO}, {"O@", kOpenO}, {"OI", kOpenO}, {"O~", kOpenO},
    // u-vowels
    {"u", kLaxU}, {"u:", kCloseU}, {"U", kLaxU}, {"U@", kLaxU},
    // r-coloured
    {"3", kRhotic}, {"3:", kRhotic},
    // syllabic consonants (base1)
    {"m-", bilabialClass(0.0f)}, {"n-", kNN}, {"N-", kKK}, {"l-", kSyllabicL}, {"r-", kRR},
    // lips
    {"p", kPP}, {"b", kPP}, {"m", kPP},
    {"B", consonant(V::PP, R::none, 0.0f, 0.05f)},  // β: lips approach but do not close
    {"f", kFF}, {"v", kFF}, {"v#", kFF},
    {"w", kW}, {"w#", kW},
    // teeth and tongue tip
    {"T", kTH}, {"D", kTH},
    {"t", kDD}, {"d", kDD}, {"t2", kDD}, {"d#", kDD}, {"t#", kDD}, {"t[", kDD}, {"d[", kDD}, {"*", kDD},
    {"s", kSS}, {"z", kSS}, {"z#", kSS}, {"z/2", kSS}, {"s;", kSS}, {"z;", kSS},
    {"tS", kCH}, {"dZ", kCH}, {"S", kCH}, {"Z", kCH}, {"tS;", kCH}, {"dZ;", kCH}, {"S;", kCH}, {"Z;", kCH},
    {"s.", kCH}, {"z.", kCH}, {"C", kCH}, {"J^", kCH},
    {"n", kNN}, {"n.", kNN}, {"n^", kNN},
    {"l", kNN}, {"l/", kNN}, {"l/2", kNN}, {"l/3", kNN}, {"l^", kNN}, {"l.", kNN}, {"L", kNN}, {"L/", kNN},
    {"l#", kNN},
    {"r", kRR}, {"r/", kRR}, {"r.", kRR}, {"r\"", kRR}, {"R", kRR}, {"R2", kRR}, {"R3", kRR}, {"**", kRR},
    // palate and back
    {"j", kY}, {";", consonant(V::ih, R::ih, 0.3f, 0.1f)},
    {"k", kKK}, {"g", kKK}, {"c", kKK}, {"J", kKK}, {"q", kKK}, {"N", kKK},
    {"x", kKK}, {"X", kKK}, {"Q", kKK}, {"Q^", kKK}, {"Q\"", kKK},
    {"h", kHH}, {"?", kGlottal},
});

// ARPAbet as CMU and festvox write it (lower case here; lookups fold case).
constexpr std::array kArpabet = std::to_array<Entry>({
    {"sil", kPause}, {"pau", kPause}, {"sp", kPause}, {"h#", kPause},
    {"aa", kOpenA}, {"ae", kAsh}, {"ah", kStrut}, {"ao", kOpenO}, {"aw", kOpenA}, {"ax", kSchwa},
    {"axr", kRhotic}, {"ay", kOpenA}, {"eh", kOpenE}, {"er", kRhotic}, {"ey", kCloseE}, {"ih", kLaxI},
    {"ix", kWeakI}, {"iy", kCloseI}, {"ow", kCloseO}, {"oy", kOpenO}, {"uh", kLaxU}, {"uw", kCloseU},
    {"b", kPP}, {"p", kPP}, {"m", kPP}, {"em", bilabialClass(0.0f)},
    {"f", kFF}, {"v", kFF}, {"th", kTH}, {"dh", kTH},
    {"t", kDD}, {"d", kDD}, {"dx", kDD},
    {"k", kKK}, {"g", kKK}, {"ng", kKK},
    {"ch", kCH}, {"jh", kCH}, {"sh", kCH}, {"zh", kCH},
    {"s", kSS}, {"z", kSS},
    {"n", kNN}, {"en", kNN}, {"l", kNN}, {"el", kSyllabicL},
    {"r", kRR}, {"w", kW}, {"wh", kW}, {"y", kY}, {"hh", kHH},
});

// Rhubarb Lip Sync's mouth shapes (upper case here; lookups fold case).
constexpr std::array kRhubarb = std::to_array<Entry>({
    {"A", bilabialClass()},                               // closed lips: P B M
    {"B", consonant(V::SS, R::ih, 0.5f, 0.1f)},           // slightly open, teeth together: K S T, EE
    {"C", vowel(V::E, R::ee, 0.4f)},                      // open: EH, AE
    {"D", vowel(V::aa, R::aa, 0.75f)},                    // wide open: AA
    {"E", vowel(V::oh, R::oh, 0.35f, 0.8f)},              // slightly rounded: AO, ER
    {"F", vowel(V::ou, R::ou, 0.15f)},                    // puckered: UW, OW, W
    {"G", consonant(V::FF, R::ih, 0.2f, 0.05f)},          // upper teeth on lower lip: F V
    {"H", consonant(V::nn, R::ee, 0.5f, 0.45f)},          // tongue raised, mouth open: long L
    {"X", kPause},                                        // idle
});

constexpr std::size_t kMaxNameLength = 8;  // longer than any table key

template <std::size_t N>
const PhonemeClass* find(const std::array<Entry, N>& table, std::string_view name) noexcept {
  for (const Entry& e : table)
    if (e.name == name) return &e.cls;
  return nullptr;
}

const PhonemeClass* findIn(PhonemeAlphabet alphabet, std::string_view name) noexcept {
  switch (alphabet) {
    case PhonemeAlphabet::Espeak: return find(kEspeak, name);
    case PhonemeAlphabet::Arpabet: return find(kArpabet, name);
    case PhonemeAlphabet::Rhubarb: return find(kRhubarb, name);
  }
  return nullptr;
}

constexpr bool isStressMark(char c) { return c == '\'' || c == ',' || c == '%' || c == '='; }
constexpr char toLower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }
constexpr char toUpper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }
constexpr bool isDigit(char c) { return c >= '0' && c <= '9'; }

// The nearest class for a name no table knows, by its first letter.
PhonemeClass fallbackByFirstLetter(std::string_view name) noexcept {
  if (name.empty()) return kPause;
  switch (toLower(name.front())) {
    case 'a': return kOpenA;
    case 'e': return kOpenE;
    case 'i': case 'y': return kLaxI;
    case 'o': return kOpenO;
    case 'u': return kLaxU;
    default: break;
  }
  const char c = toLower(name.front());
  if (c >= 'a' && c <= 'z') return kDD;  // the most common consonant place
  return kPause;
}

Classification classifyEspeak(std::string_view name) noexcept {
  if (name.empty()) return {kPause, false};
  if (const PhonemeClass* c = find(kEspeak, name)) return {*c, true};
  // Stress marks before or after a mnemonic ("'i:", "aI,") are not part of it.
  std::string_view bare = name;
  while (!bare.empty() && (isStressMark(bare.front()) || bare.front() == '!')) bare.remove_prefix(1);
  while (!bare.empty() && isStressMark(bare.back())) bare.remove_suffix(1);
  if (bare.empty()) return {kMark, true};  // marks only
  if (const PhonemeClass* c = find(kEspeak, bare)) return {*c, true};
  // An extra length mark on a known phoneme ("a:" where only "a" exists).
  std::string_view unlengthened = bare;
  while (!unlengthened.empty() && unlengthened.back() == ':') unlengthened.remove_suffix(1);
  if (!unlengthened.empty() && unlengthened.size() != bare.size())
    if (const PhonemeClass* c = find(kEspeak, unlengthened)) return {*c, true};
  for (std::size_t n = std::min(bare.size(), kMaxNameLength); n > 0; --n)
    if (const PhonemeClass* c = find(kEspeak, bare.substr(0, n))) return {*c, false};
  return {fallbackByFirstLetter(bare), false};
}

// Case-folds into a small buffer; folded is empty when the name is too long for any key.
std::string_view fold(std::string_view name, std::array<char, kMaxNameLength>& buffer, bool upper) noexcept {
  if (name.size() > buffer.size()) return {};
  for (std::size_t i = 0; i < name.size(); ++i) buffer[i] = upper ? toUpper(name[i]) : toLower(name[i]);
  return {buffer.data(), name.size()};
}

Classification classifyTable(std::string_view name, PhonemeAlphabet alphabet) noexcept {
  const bool upper = alphabet == PhonemeAlphabet::Rhubarb;
  std::string_view trimmed = name;
  if (alphabet == PhonemeAlphabet::Arpabet)  // stress digits: "AH0", "IY1"
    while (!trimmed.empty() && isDigit(trimmed.back())) trimmed.remove_suffix(1);
  std::array<char, kMaxNameLength> buffer{};
  const std::string_view folded = fold(trimmed, buffer, upper);
  if (!folded.empty())
    if (const PhonemeClass* c = findIn(alphabet, folded)) return {*c, true};
  std::array<char, kMaxNameLength> prefixBuffer{};
  const std::string_view head = fold(trimmed.substr(0, std::min(trimmed.size(), kMaxNameLength)), prefixBuffer, upper);
  for (std::size_t n = head.size(); n > 0; --n)
    if (const PhonemeClass* c = findIn(alphabet, head.substr(0, n))) return {*c, false};
  return {fallbackByFirstLetter(trimmed), false};
}

constexpr std::array<std::string_view, kVisemeCount> kVisemeNames = {
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
constexpr std::array<std::string_view, kVrmVisemeCount> kVrmNames = {"aa", "ih", "ou", "ee", "oh"};

}  // namespace

std::string_view visemeName(Viseme viseme) noexcept {
  const auto i = static_cast<std::size_t>(viseme);
  return i < kVisemeNames.size() ? kVisemeNames[i] : std::string_view{};
}

std::optional<Viseme> visemeFromName(std::string_view name) noexcept {
  return valueOfIndexedName<Viseme>(name, kVisemeNames);
}

std::string_view vrmVisemeName(VrmViseme viseme) noexcept {
  const auto i = static_cast<std::size_t>(viseme);
  return i < kVrmNames.size() ? kVrmNames[i] : std::string_view{};
}

Classification classifyPhoneme(std::string_view phoneme, PhonemeAlphabet alphabet) noexcept {
  if (alphabet == PhonemeAlphabet::Espeak) return classifyEspeak(phoneme);
  if (alphabet == PhonemeAlphabet::Arpabet || alphabet == PhonemeAlphabet::Rhubarb)
    return classifyTable(phoneme, alphabet);
  return {fallbackByFirstLetter(phoneme), false};  // an out-of-range enum value
}

}  // namespace marionette::speech
