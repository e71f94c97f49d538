// A scene's speech: the backends it asks (in order; the first that can say a
// text says it), a cache so that scheduling a BML <speech> and realizing it
// synthesize once, the lip-sync curves of each utterance, and where its audio
// is written as WAV for the engine to play. Nothing starts until the first
// speak(): a scene without speech never loads a synthesizer. Command time only.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "marionette/speech/lipsync.hpp"
#include "marionette/speech/speech_backend.hpp"

namespace marionette::speech {

// An utterance ready to perform.
struct SpokenLine {
  std::shared_ptr<const Utterance> utterance;
  VisemeCurves curves;
  std::string backend;              // the backend that said it
  std::filesystem::path audioFile;  // its WAV, when an audio directory is set and it has audio
  std::string audioError;           // why its WAV could not be written (the line still plays)
};

class SpeechService {
 public:
  // Backends are asked in the order added, then espeak-ng when the build has it
  // (started on the first speech it is asked for; useDefaultSynthesizer(false) leaves it out).
  void addBackend(std::shared_ptr<SpeechBackend> backend);
  void useDefaultSynthesizer(bool use);
  [[nodiscard]] std::size_t backendCount() const;
  // Where each new utterance's audio is written ("utterance-<hash>.wav"); empty
  // (the default): not written. Created when needed. Changing it forgets cached lines.
  void setAudioDirectory(std::filesystem::path directory);
  [[nodiscard]] std::filesystem::path audioDirectory() const;
  void setLipSyncSettings(const LipSyncSettings& settings);

  struct Result {
    std::shared_ptr<const SpokenLine> line;  // null on failure
    std::string error;  // why no backend could say it
  };
  // The same request gives the same line (cached; at most kCacheSize kept).
  Result speak(const SpeechRequest& request);
  static constexpr std::size_t kCacheSize = 256;

 private:
  struct Cached {
    std::string key;
    std::shared_ptr<const SpokenLine> line;
  };
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<SpeechBackend>> backends_;
  bool defaultSynthesizer_ = true;
  bool defaultTried_ = false;
  std::shared_ptr<SpeechBackend> synthesizer_;  // espeak-ng, once asked for
  std::string defaultMissing_;                  // why it is not there
  std::filesystem::path audioDirectory_;
  LipSyncSettings lipSync_;
  std::vector<Cached> cache_;  // oldest first
};

}  // namespace marionette::speech
