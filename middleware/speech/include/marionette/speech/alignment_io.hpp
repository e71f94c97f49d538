// Phoneme alignments of recorded voice lines, and 16-bit PCM WAV files.
// Formats read:
//   - "start end phone" per line, seconds, tab or space separated, '#' comments
//     (../shared/assets/speech/*.phones.txt; also `marionette speak --phonemes` CSV
//     "start,end,phoneme" with its header);
//   - HTS full-context labels (.lab): "start end label", times in 100 ns units,
//     the phone is the text between '-' and '+' (a monophone label is taken whole);
//   - Rhubarb Lip Sync TSV: "time<TAB>shape" (A-H, X), each shape lasting until the next.
// Errors name the file, the line and what was expected.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/file_reader.hpp"
#include "marionette/speech/phoneme.hpp"

namespace marionette::speech {

enum class AlignmentFormat : std::uint8_t { Auto, PhoneList, HtsLabel, Rhubarb };

struct Alignment {
  std::vector<Phoneme> phonemes;  // classified (Phoneme::cls set), in file order
  PhonemeAlphabet alphabet = PhonemeAlphabet::Arpabet;
  std::vector<std::string> warnings;  // unknown phonemes, repaired times
  std::string error;                  // non-empty: nothing usable was read
};

// Auto picks the format from the extension (.lab, .tsv) and the content.
[[nodiscard]] Alignment readAlignment(const std::filesystem::path& file, AlignmentFormat format = AlignmentFormat::Auto);
// The same through an engine's reader (core/file_reader.hpp; empty: the disk).
[[nodiscard]] Alignment readAlignment(const FileReader& files, const std::filesystem::path& file,
                                      AlignmentFormat format = AlignmentFormat::Auto);
[[nodiscard]] Alignment parseAlignment(std::string_view text, std::string_view sourceName,
                                       AlignmentFormat format = AlignmentFormat::Auto);

struct WavAudio {
  std::vector<std::int16_t> samples;  // mono (multi-channel files are mixed down)
  int sampleRate = 0;
};
// Reads RIFF/WAVE PCM 8/16/24/32-bit and 32-bit float; returns an error text (empty on success).
[[nodiscard]] std::string readWav(const std::filesystem::path& file, WavAudio& out);
[[nodiscard]] std::string readWav(const FileReader& files, const std::filesystem::path& file, WavAudio& out);
// Writes mono 16-bit PCM; returns an error text (empty on success).
[[nodiscard]] std::string writeWav(const std::filesystem::path& file, std::span<const std::int16_t> samples,
                                   int sampleRate);

}  // namespace marionette::speech
