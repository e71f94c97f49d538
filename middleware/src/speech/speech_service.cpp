#include "marionette/speech/speech_service.hpp"

#include "marionette/core/limits.hpp"

#include <cstdio>
#include <system_error>

#include "marionette/speech/alignment_io.hpp"
#include "marionette/speech/espeak_backend.hpp"

namespace marionette::speech {

namespace {

// FNV-1a: names WAV files after what they say, the same in every run.
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string cacheKey(const SpeechRequest& r) {
  std::string key = r.voice + '\x1f' + std::to_string(r.wordsPerMinute) + '\x1f' + r.text;
  for (const TextMark& m : r.marks) key += '\x1f' + m.id + '@' + std::to_string(m.characterOffset);
  return key;
}

}  // namespace

void SpeechService::addBackend(std::shared_ptr<SpeechBackend> backend) {
  if (!backend) return;
  std::lock_guard lock(mutex_);
  backends_.push_back(std::move(backend));
  cache_.clear();  // an added backend may say a text differently
}

void SpeechService::useDefaultSynthesizer(bool use) {
  std::lock_guard lock(mutex_);
  defaultSynthesizer_ = use;
}

std::size_t SpeechService::backendCount() const {
  std::lock_guard lock(mutex_);
  return backends_.size();
}

void SpeechService::setAudioDirectory(std::filesystem::path directory) {
  std::lock_guard lock(mutex_);
  audioDirectory_ = std::move(directory);
  cache_.clear();  // lines said before have no file there
}

std::filesystem::path SpeechService::audioDirectory() const {
  std::lock_guard lock(mutex_);
  return audioDirectory_;
}

void SpeechService::setLipSyncSettings(const LipSyncSettings& settings) {
  std::lock_guard lock(mutex_);
  lipSync_ = settings;
  cache_.clear();
}

SpeechService::Result SpeechService::speak(const SpeechRequest& request) {
  // Limits first: synthesis time grows with the text (and faster with the marks).
  if (request.text.size() > limits::kMaxSpeechCharacters)
    return {nullptr, "the text has " + std::to_string(request.text.size()) + " characters, more than the " +
                         std::to_string(limits::kMaxSpeechCharacters) +
                         " one line may have (limits::kMaxSpeechCharacters): split it into several lines"};
  if (request.marks.size() > limits::kMaxSpeechMarks)
    return {nullptr, "the text has " + std::to_string(request.marks.size()) + " word marks, more than the " +
                         std::to_string(limits::kMaxSpeechMarks) + " one line may have (limits::kMaxSpeechMarks)"};
  if (request.text.find_first_not_of(" \t\r\n") == std::string::npos)
    return {nullptr, "the text is empty: nothing to say"};
  std::lock_guard lock(mutex_);
  const std::string key = cacheKey(request);
  for (const Cached& c : cache_)
    if (c.key == key) return {c.line, {}};
  std::vector<SpeechBackend*> order;
  for (const auto& b : backends_) order.push_back(b.get());
  if (defaultSynthesizer_) {
    if (!defaultTried_) {
      defaultTried_ = true;
      synthesizer_ = makeEspeakBackend(&defaultMissing_);
    }
    if (synthesizer_) order.push_back(synthesizer_.get());
  }
  if (order.empty())
    return {nullptr, "no speech backend: " + (defaultMissing_.empty() ? std::string("none was added") : defaultMissing_)};
  std::string errors;
  for (SpeechBackend* backend : order) {
    SpeechResult said = backend->synthesize(request);
    if (!said.utterance) {
      errors += (errors.empty() ? "" : "; ") + std::string(backend->name()) + ": " + said.error;
      continue;
    }
    auto line = std::make_shared<SpokenLine>();
    line->utterance = said.utterance;
    line->backend = std::string(backend->name());
    line->curves = buildVisemeCurves(said.utterance->phonemes, said.utterance->duration, lipSync_);
    // Every line's audio goes to the one directory, recordings too: the engine plays from one place.
    if (!audioDirectory_.empty() && !said.utterance->audio.empty()) {
      char name[40];
      std::snprintf(name, sizeof name, "utterance-%016llx.wav", static_cast<unsigned long long>(fnv1a(key)));
      std::error_code ec;
      std::filesystem::create_directories(audioDirectory_, ec);
      const std::filesystem::path file = audioDirectory_ / name;
      line->audioError = writeWav(file, said.utterance->audio, said.utterance->sampleRate);
      if (line->audioError.empty()) line->audioFile = file;
    }
    if (cache_.size() >= kCacheSize) cache_.erase(cache_.begin());
    cache_.push_back({key, line});
    return {std::move(line), {}};
  }
  return {nullptr, errors};
}

}  // namespace marionette::speech
