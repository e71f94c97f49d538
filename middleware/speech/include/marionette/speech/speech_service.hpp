// A scene's speech: the backends it asks (in order; the first that can say a
// text says it), a cache so that scheduling a BML <speech> and realizing it
// synthesize once, the lip-sync curves of each utterance, and where its audio
// is written as WAV for the engine to play. Nothing starts until the first
// speak() or prepare(): a scene without speech never loads a synthesizer nor
// starts a thread. Command time: not to be called from a scene update.
//
// speak() says a line in the caller's thread (it may take a tenth of a second for
// a long line). prepare() says it on the service's own worker thread and returns at
// once, so that no frame waits for a synthesizer: the BML realizer prepares a
// block's speech and realizes the block when its lines are ready.
#pragma once
#include <cstdint>
#include <filesystem>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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

// `request` with its voice mapped through `names` (keys lower case; looked up case-insensitively):
// a name found is replaced by its value, "default" fills an empty voice and an empty fallback.
// What a character's profile ("voices") and the scene's speech settings do, in that order.
[[nodiscard]] SpeechRequest withVoiceNames(SpeechRequest request, const std::map<std::string, std::string>& names);
// A voice-name map as read from a file: keys lower-cased (the later of two equal ones wins).
[[nodiscard]] std::map<std::string, std::string> voiceNameMap(const std::map<std::string, std::string>& names);

class SpeechService {
 public:
  SpeechService() = default;
  SpeechService(const SpeechService&) = delete;
  SpeechService& operator=(const SpeechService&) = delete;
  ~SpeechService();  // waits for the line being said in the background, drops the queued ones

  // Backends are asked in the order added, then the synthesizer when one is set
  // (made by its factory on the first speech it is asked for; useDefaultSynthesizer(false)
  // leaves it out). The middleware has none of its own: espeak-ng is the separate
  // library marionette::tts_espeak (GPL), set with speech::useEspeak(service).
  using SynthesizerFactory = std::function<std::shared_ptr<SpeechBackend>(std::string* whyNot)>;
  void addBackend(std::shared_ptr<SpeechBackend> backend);
  // A backend now says some text differently (a recorded line added to it): cached lines are
  // said again when next asked for. addBackend does this itself.
  void forgetCachedLines();
  void setSynthesizer(SynthesizerFactory factory);
  void useDefaultSynthesizer(bool use);
  [[nodiscard]] std::size_t backendCount() const;
  // Where each new utterance's audio is written ("utterance-<hash>.wav"); empty
  // (the default): not written. Created when needed. Changing it forgets cached lines.
  void setAudioDirectory(std::filesystem::path directory);
  [[nodiscard]] std::filesystem::path audioDirectory() const;
  void setLipSyncSettings(const LipSyncSettings& settings);
  // Voice names of other engines to the backends' (a scene's "speech": {"voices"}): a request's
  // voice found here (case-insensitive) is asked for by its mapped name; "default" names the
  // voice for requests without one and for a voice the backend lacks (SpeechRequest::fallbackVoice).
  void setVoiceNames(std::map<std::string, std::string> names);

  struct Result {
    std::shared_ptr<const SpokenLine> line;  // null on failure
    std::string error;  // why no backend could say it
  };
  // The same request gives the same line (cached; at most kCacheSize kept). A failure is
  // not cached: asked again, the backends are asked again. A request being prepared is
  // waited for, not said twice; a pinned one gives its result (below).
  Result speak(const SpeechRequest& request);
  static constexpr std::size_t kCacheSize = 256;

  // A line asked for with prepare(). ready() may be polled every frame (an atomic
  // load); result() is valid once ready() is true.
  class Preparation {
   public:
    [[nodiscard]] bool ready() const noexcept { return ready_.load(std::memory_order_acquire); }
    [[nodiscard]] const Result& result() const noexcept { return result_; }

   private:
    friend class SpeechService;
    SpeechRequest request_;
    std::string key_;
    Result result_;
    std::atomic<bool> ready_{false};
  };
  // Starts saying `request` on the service's worker thread and returns at once
  // (ready at once when it is cached, or breaks a limit). Lines are said in the order asked.
  [[nodiscard]] std::shared_ptr<const Preparation> prepare(const SpeechRequest& request);
  // Blocks until every prepared line is ready (offline tools, tests).
  void waitUntilPrepared();
  // While pinned, speak() answers these ready lines' requests with their results, failures
  // too, with the settings they were said with, however the cache changed: the realizer
  // pins a held block's lines while it realizes it, so that no line is said again then.
  void pin(const std::vector<std::shared_ptr<const Preparation>>& lines);
  void unpin(const std::vector<std::shared_ptr<const Preparation>>& lines);
  // Lines being said (by prepare() or a speak() in progress).
  [[nodiscard]] std::size_t preparing() const;

 private:
  struct Cached {
    std::string key;
    Result result;
  };
  // A ready preparation for a cached result, the one being said, or a new one to say (`fresh`).
  std::shared_ptr<Preparation> findOrStart(const SpeechRequest& request, bool& fresh);  // under the lock
  void say(Preparation& job);  // the backends, without the lock held; never throws
  static Result sayWith(const std::vector<std::shared_ptr<SpeechBackend>>& order, const Preparation& job,
                        const std::filesystem::path& audioDirectory, const LipSyncSettings& lipSync,
                        const std::string& missing);
  void workerLoop();
  mutable std::mutex mutex_;
  std::condition_variable finished_;              // a line became ready
  std::condition_variable work_;                  // the worker has something to do
  std::vector<std::shared_ptr<Preparation>> saying_;  // being said, in the background or by speak()
  std::deque<std::shared_ptr<Preparation>> queue_;    // waiting for the worker
  std::vector<std::shared_ptr<const Preparation>> pinned_;  // pin(): answers speak() before the backends
  std::thread worker_;                            // started by the first prepare()
  bool stopping_ = false;
  std::uint64_t generation_ = 0;  // settings changed: results of older settings are not cached
  std::vector<std::shared_ptr<SpeechBackend>> backends_;
  bool defaultSynthesizer_ = true;
  bool defaultTried_ = false;
  SynthesizerFactory synthesizerFactory_;
  std::shared_ptr<SpeechBackend> synthesizer_;  // made by the factory, once asked for
  std::string defaultMissing_;                  // why it is not there
  std::filesystem::path audioDirectory_;
  LipSyncSettings lipSync_;
  std::map<std::string, std::string> voiceNames_;  // keys lower case
  std::vector<Cached> cache_;  // oldest first
};

}  // namespace marionette::speech
