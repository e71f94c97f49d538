// Phonemes and what they look like on the lips. A phoneme from any source
// (espeak-ng's events, a recorded line's alignment) is classified once, at
// command time, into the viseme it shows, the VRM vowel shape it is closest to,
// how far it opens the jaw, and whether it closes the lips (P, B, M) or is a
// pause. The tables cover every mnemonic of espeak-ng's English phoneme set
// (including a#, t#, U@, r-, _:) and ARPAbet as CMU / festvox write it.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace marionette::speech {

// The 15 OVR / OpenXR visemes, in their standard order.
enum class Viseme : std::uint8_t { sil, PP, FF, TH, DD, kk, CH, SS, nn, RR, aa, E, ih, oh, ou };
inline constexpr int kVisemeCount = 15;
[[nodiscard]] std::string_view visemeName(Viseme viseme) noexcept;  // "sil", "PP", ...
[[nodiscard]] std::optional<Viseme> visemeFromName(std::string_view name) noexcept;

// The 5 VRM mouth shapes (VRM 1.0 names; VRM 0.0 calls them A I U E O).
enum class VrmViseme : std::uint8_t { aa, ih, ou, ee, oh, none };
inline constexpr int kVrmVisemeCount = 5;
[[nodiscard]] std::string_view vrmVisemeName(VrmViseme viseme) noexcept;  // "aa", ...; "" for none

// Espeak: espeak-ng's mnemonics. Arpabet: CMU / festvox phones, any case, stress
// digits allowed ("AH0"), "sil"/"pau"/"sp" silence. Rhubarb: Rhubarb Lip Sync's
// mouth shapes A-H and X (they are visemes already, not phonemes).
enum class PhonemeAlphabet : std::uint8_t { Espeak, Arpabet, Rhubarb };

// What a phoneme looks like.
struct PhonemeClass {
  Viseme viseme = Viseme::sil;
  VrmViseme vrm = VrmViseme::none;  // the VRM shape it shows (none: a closed or neutral mouth)
  float vrmAmount = 0.0f;           // how much of that shape, [0,1] (consonants show less)
  float jawOpen = 0.0f;             // [0,1]
  bool bilabial = false;            // P, B, M: the lips must close fully
  bool pause = false;               // silence: the mouth relaxes
};

struct Classification {
  PhonemeClass cls;
  bool known = true;  // false: not in the table; cls is the nearest class (the caller warns)
};
// Never fails: an unknown phoneme gets the class of its longest known prefix
// with stress and length marks stripped, else of its first letter's kind
// (vowel or consonant), else silence.
[[nodiscard]] Classification classifyPhoneme(std::string_view phoneme, PhonemeAlphabet alphabet) noexcept;

// One phoneme of an utterance.
struct Phoneme {
  double start = 0.0, end = 0.0;  // seconds from the utterance's start; end >= start
  std::string name;               // as the source spells it ("p", "a#", "sil")
  PhonemeClass cls;
  std::int64_t sample = -1;       // audio sample where it starts, when a synthesizer said so
};

}  // namespace marionette::speech
