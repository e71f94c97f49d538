#include "marionette/speech/speech_service.hpp"

#include "marionette/core/limits.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <system_error>

#include "marionette/speech/alignment_io.hpp"

namespace marionette::speech {

namespace {

// FNV-1a: names WAV files after what they say, the same in every run.
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string cacheKey(const SpeechRequest& r) {
  std::string key = r.voice + '\x1f' + r.fallbackVoice + '\x1f' + std::to_string(r.wordsPerMinute) + '\x1f' + r.text;
  for (const TextMark& m : r.marks) key += '\x1f' + m.id + '@' + std::to_string(m.characterOffset);
  return key;
}

// Limits first: synthesis time grows with the text (and faster with the marks).
std::string limitProblem(const SpeechRequest& request) {
  if (request.text.size() > limits::kMaxSpeechCharacters)
    return "the text has " + std::to_string(request.text.size()) + " characters, more than the " +
           std::to_string(limits::kMaxSpeechCharacters) +
           " one line may have (limits::kMaxSpeechCharacters): split it into several lines";
  if (request.marks.size() > limits::kMaxSpeechMarks)
    return "the text has " + std::to_string(request.marks.size()) + " word marks, more than the " +
           std::to_string(limits::kMaxSpeechMarks) + " one line may have (limits::kMaxSpeechMarks)";
  if (request.text.find_first_not_of(" \t\r\n") == std::string::npos) return "the text is empty: nothing to say";
  return {};
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::map<std::string, std::string> voiceNameMap(const std::map<std::string, std::string>& names) {
  std::map<std::string, std::string> out;
  for (const auto& [k, v] : names) out[lower(k)] = v;
  return out;
}

SpeechRequest withVoiceNames(SpeechRequest request, const std::map<std::string, std::string>& names) {
  if (names.empty()) return request;
  if (!request.voice.empty()) {
    if (const auto it = names.find(lower(request.voice)); it != names.end()) request.voice = it->second;
  }
  if (const auto it = names.find("default"); it != names.end()) {
    if (request.voice.empty()) request.voice = it->second;
    if (request.fallbackVoice.empty()) request.fallbackVoice = it->second;
  }
  return request;
}

SpeechService::~SpeechService() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    for (const auto& job : queue_) {  // never to be said: ready, with the reason
      job->result_ = {nullptr, "the speech service was destroyed before the line was said"};
      job->ready_.store(true, std::memory_order_release);
    }
    queue_.clear();
  }
  work_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void SpeechService::addBackend(std::shared_ptr<SpeechBackend> backend) {
  if (!backend) return;
  std::lock_guard lock(mutex_);
  backends_.push_back(std::move(backend));
  cache_.clear();  // an added backend may say a text differently
  ++generation_;
}

void SpeechService::forgetCachedLines() {
  std::lock_guard lock(mutex_);
  cache_.clear();
  ++generation_;
}

void SpeechService::setSynthesizer(SynthesizerFactory factory) {
  std::lock_guard lock(mutex_);
  synthesizerFactory_ = std::move(factory);
  synthesizer_.reset();
  defaultTried_ = false;
  defaultMissing_.clear();
  cache_.clear();
  ++generation_;
}

void SpeechService::useDefaultSynthesizer(bool use) {
  std::lock_guard lock(mutex_);
  defaultSynthesizer_ = use;
  cache_.clear();
  ++generation_;
}

std::size_t SpeechService::backendCount() const {
  std::lock_guard lock(mutex_);
  return backends_.size();
}

void SpeechService::setAudioDirectory(std::filesystem::path directory) {
  std::lock_guard lock(mutex_);
  audioDirectory_ = std::move(directory);
  cache_.clear();  // lines said before have no file there
  ++generation_;
}

std::filesystem::path SpeechService::audioDirectory() const {
  std::lock_guard lock(mutex_);
  return audioDirectory_;
}

void SpeechService::setVoiceNames(std::map<std::string, std::string> names) {
  std::lock_guard lock(mutex_);
  voiceNames_ = voiceNameMap(names);
  cache_.clear();
  ++generation_;
}

void SpeechService::setLipSyncSettings(const LipSyncSettings& settings) {
  std::lock_guard lock(mutex_);
  lipSync_ = settings;
  cache_.clear();
  ++generation_;
}

std::shared_ptr<SpeechService::Preparation> SpeechService::findOrStart(const SpeechRequest& asked, bool& fresh) {
  fresh = false;
  const SpeechRequest request = withVoiceNames(asked, voiceNames_);  // other engines' voice names
  auto job = std::make_shared<Preparation>();
  job->key_ = cacheKey(request);
  for (const Cached& c : cache_)
    if (c.key == job->key_) {
      job->result_ = c.result;
      job->ready_.store(true, std::memory_order_release);
      return job;
    }
  for (const auto& other : saying_)
    if (other->key_ == job->key_) return other;
  // A pinned line (a held block being realized): its result, even when the cache let it
  // go or never kept it (a failure, or a line said before a setting changed).
  for (const auto& held : pinned_)
    if (held->key_ == job->key_) return std::const_pointer_cast<Preparation>(held);
  job->request_ = request;
  saying_.push_back(job);
  fresh = true;
  return job;
}

SpeechService::Result SpeechService::speak(const SpeechRequest& request) {
  if (std::string why = limitProblem(request); !why.empty()) return {nullptr, std::move(why)};
  std::unique_lock lock(mutex_);
  bool fresh = false;
  const std::shared_ptr<Preparation> job = findOrStart(request, fresh);
  if (fresh) {
    lock.unlock();
    say(*job);
  } else {
    finished_.wait(lock, [&] { return job->ready(); });
  }
  return job->result_;
}

std::shared_ptr<const SpeechService::Preparation> SpeechService::prepare(const SpeechRequest& request) {
  if (std::string why = limitProblem(request); !why.empty()) {
    auto refused = std::make_shared<Preparation>();
    refused->result_ = {nullptr, std::move(why)};
    refused->ready_.store(true, std::memory_order_release);
    return refused;
  }
  std::unique_lock lock(mutex_);
  bool fresh = false;
  std::shared_ptr<Preparation> job = findOrStart(request, fresh);
  if (!fresh) return job;
  try {
    if (!worker_.joinable()) worker_ = std::thread([this] { workerLoop(); });
  } catch (const std::exception&) {  // no thread: said here, as speak() would
    lock.unlock();
    say(*job);
    return job;
  }
  queue_.push_back(job);
  work_.notify_one();
  return job;
}

void SpeechService::pin(const std::vector<std::shared_ptr<const Preparation>>& lines) {
  std::lock_guard lock(mutex_);
  for (const auto& line : lines)
    if (line && line->ready()) pinned_.push_back(line);
}

void SpeechService::unpin(const std::vector<std::shared_ptr<const Preparation>>& lines) {
  std::lock_guard lock(mutex_);
  for (const auto& line : lines) {
    const auto it = std::find(pinned_.begin(), pinned_.end(), line);
    if (it != pinned_.end()) pinned_.erase(it);
  }
}

void SpeechService::waitUntilPrepared() {
  std::unique_lock lock(mutex_);
  finished_.wait(lock, [&] { return saying_.empty(); });
}

std::size_t SpeechService::preparing() const {
  std::lock_guard lock(mutex_);
  return saying_.size();
}

void SpeechService::workerLoop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    const std::shared_ptr<Preparation> job = queue_.front();
    queue_.pop_front();
    lock.unlock();
    say(*job);
    lock.lock();
  }
}

void SpeechService::say(Preparation& job) {
  // The settings as they are now; the backends run without the lock, so that
  // polling, preparing and other lines are never held up by a synthesis.
  std::vector<std::shared_ptr<SpeechBackend>> order;
  std::filesystem::path audioDirectory;
  LipSyncSettings lipSync;
  std::uint64_t generation = 0;
  std::string missing;
  {
    std::lock_guard lock(mutex_);
    order = backends_;
    if (defaultSynthesizer_) {
      if (!defaultTried_) {
        defaultTried_ = true;
        if (synthesizerFactory_) synthesizer_ = synthesizerFactory_(&defaultMissing_);
        else defaultMissing_ = "no synthesizer was set (link marionette::tts_espeak and call "
                               "speech::useEspeak(scene.speech()), or add recorded lines or an engine's own backend)";
      }
      if (synthesizer_) order.push_back(synthesizer_);
    }
    audioDirectory = audioDirectory_;
    lipSync = lipSync_;
    generation = generation_;
    missing = defaultMissing_;
  }
  Result result;
  bool keep = true;
  try {
    result = sayWith(order, job, audioDirectory, lipSync, missing);
  } catch (const std::exception& e) {  // a backend's, or no memory: this line fails, nothing waits forever
    result = {nullptr, std::string("the speech backend failed: ") + e.what()};
    keep = false;
  } catch (...) {
    result = {nullptr, "the speech backend failed with an unknown exception"};
    keep = false;
  }
  {
    std::lock_guard lock(mutex_);
    // Said with the settings in force: kept. Failures are not: a line a backend learns
    // later (RecordedSpeech::addLine), or a transient error, is tried again next time.
    if (keep && result.line && generation == generation_) {
      if (cache_.size() >= kCacheSize) cache_.erase(cache_.begin());
      cache_.push_back({job.key_, result});
    }
    saying_.erase(std::remove_if(saying_.begin(), saying_.end(), [&](const auto& j) { return j.get() == &job; }),
                  saying_.end());
    job.result_ = std::move(result);
    job.ready_.store(true, std::memory_order_release);
  }
  finished_.notify_all();
}

SpeechService::Result SpeechService::sayWith(const std::vector<std::shared_ptr<SpeechBackend>>& order,
                                             const Preparation& job, const std::filesystem::path& audioDirectory,
                                             const LipSyncSettings& lipSync, const std::string& missing) {
  Result result;
  if (order.empty()) result.error = "no speech backend: " + (missing.empty() ? std::string("none was added") : missing);
  for (const auto& backend : order) {
    SpeechResult said = backend->synthesize(job.request_);
    if (!said.utterance) {
      result.error += (result.error.empty() ? "" : "; ") + std::string(backend->name()) + ": " + said.error;
      continue;
    }
    auto line = std::make_shared<SpokenLine>();
    line->utterance = said.utterance;
    line->backend = std::string(backend->name());
    line->curves = buildVisemeCurves(said.utterance->phonemes, said.utterance->duration, lipSync);
    // Every line's audio goes to the one directory, recordings too: the engine plays from one place.
    if (!audioDirectory.empty() && !said.utterance->audio.empty()) {
      char name[40];
      std::snprintf(name, sizeof name, "utterance-%016llx.wav", static_cast<unsigned long long>(fnv1a(job.key_)));
      std::error_code ec;
      std::filesystem::create_directories(audioDirectory, ec);
      const std::filesystem::path file = audioDirectory / name;
      line->audioError = writeWav(file, said.utterance->audio, said.utterance->sampleRate);
      if (line->audioError.empty()) line->audioFile = file;
    }
    return {std::move(line), {}};
  }
  return result;
}

}  // namespace marionette::speech
