// A speech backend that says a line only when the test opens it (passing it to
// another backend): a slow synthesizer, made deterministic, for the background
// synthesis tests. Open it before the service is destroyed (its thread waits here).
#pragma once
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string_view>
#include <utility>

#include "marionette/speech/speech_backend.hpp"

namespace marionette::test {

class GatedSpeechBackend final : public speech::SpeechBackend {
 public:
  explicit GatedSpeechBackend(std::shared_ptr<speech::SpeechBackend> inner) : inner_(std::move(inner)) {}
  std::string_view name() const noexcept override { return "gated"; }
  speech::SpeechResult synthesize(const speech::SpeechRequest& request) override {
    ++calls;
    std::unique_lock lock(mutex_);
    opened_.wait(lock, [&] { return open_; });
    return inner_->synthesize(request);
  }
  void setOpen(bool open) {
    {
      std::lock_guard lock(mutex_);
      open_ = open;
    }
    opened_.notify_all();
  }
  std::atomic<int> calls{0};

 private:
  std::shared_ptr<speech::SpeechBackend> inner_;
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

// Opens the gate when the test's scope ends, whatever happened in it.
struct GateOpener {
  GatedSpeechBackend& gate;
  ~GateOpener() { gate.setOpen(true); }
};

}  // namespace marionette::test
