// Recorded voice lines: a backend that "says" a text by returning a recording of
// it and its phoneme alignment (alignment_io.hpp formats), with no synthesis. A
// request matches a line by its text, ignoring case, punctuation and spacing.
// The alignment has no word times, so the times of marks inside the text are
// estimated from how many letters precede them over the voiced part of the line
// (a warning in the utterance says so).
#pragma once
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/speech_backend.hpp"

namespace marionette::speech {

class RecordedSpeech final : public SpeechBackend {
 public:
  // Reads the audio (WAV; an empty path: no audio) and the alignment now, through `files`
  // (core/file_reader.hpp; empty: the disk). Returns an error naming the file, or "" when
  // the line was added.
  std::string addLine(std::string_view text, const std::filesystem::path& audio,
                      const std::filesystem::path& alignment, const FileReader& files = {});
  // The same from data already in memory (`source` names it in messages).
  std::string addLine(std::string_view text, WavAudio audio, Alignment alignment, std::string_view source);
  [[nodiscard]] std::size_t lineCount() const;

  [[nodiscard]] std::string_view name() const noexcept override { return "recorded"; }
  [[nodiscard]] SpeechResult synthesize(const SpeechRequest& request) override;

  // The text as lines are matched: lower-case letters and digits, single spaces.
  [[nodiscard]] static std::string matchKey(std::string_view text);

 private:
  struct Line {
    std::string key;
    std::shared_ptr<const Utterance> utterance;  // without marks
  };
  mutable std::mutex mutex_;
  std::vector<Line> lines_;
};

}  // namespace marionette::speech
