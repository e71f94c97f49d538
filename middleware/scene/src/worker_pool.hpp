// WorkerPool: persistent threads that run one job at a time on every
// participant (the calling thread is participant 0). Scene::update uses it to
// update characters in parallel. Threads are started and joined at command time
// (resize, destructor); run() creates nothing and allocates nothing.
//
// Header-only and private to scene.cpp: nothing else needs it.
#pragma once
#include <cfenv>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace marionette::detail {

class WorkerPool {
 public:
  // A plain function pointer and context, not std::function: nothing to allocate per frame.
  using Job = void (*)(void* context, int participant) noexcept;

  WorkerPool() = default;
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() { stop(); }

  // Participants = workers + the calling thread.
  [[nodiscard]] int participants() const noexcept { return static_cast<int>(threads_.size()) + 1; }

  // Command time: joins the current workers and starts `participants - 1` new
  // ones. Returns how many participants there are now: fewer than asked when the
  // system refuses a thread (std::thread throws; the library does not).
  int resize(int participants) {
    stop();
    threads_.reserve(static_cast<std::size_t>(participants > 1 ? participants - 1 : 0));
    try {
      for (int k = 1; k < participants; ++k) threads_.emplace_back(&WorkerPool::loop, this, k, generation_);
    } catch (const std::system_error&) {
      // Keep the workers that did start; the caller reports the shortfall.
    }
    return this->participants();
  }

  // Runs job(context, k) once on every participant k and returns when all have
  // finished. Must not be called concurrently with itself or resize().
  void run(Job job, void* context) noexcept {
    if (threads_.empty()) {
      job(context, 0);
      return;
    }
    {
      std::lock_guard lock(mutex_);
      job_ = job;
      context_ = context;
      // Workers take on the caller's floating-point environment (rounding mode,
      // and on x86 MXCSR's flush-to-zero): an engine may change it on its own
      // thread, and results must not depend on which thread ran a character.
      std::fegetenv(&env_);
      pending_ = static_cast<int>(threads_.size());
      ++generation_;
    }
    wake_.notify_all();
    job(context, 0);
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
  }

 private:
  void loop(int participant, std::uint64_t seen) noexcept {
    for (;;) {
      Job job = nullptr;
      void* context = nullptr;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        job = job_;
        context = context_;
        std::fesetenv(&env_);
      }
      job(context, participant);
      // Notified under the lock, so run() cannot return (and its caller go on to
      // destroy the pool) between our decrement and the notify.
      std::lock_guard lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  void stop() noexcept {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
    threads_.clear();
    stop_ = false;  // no worker is left to read it
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;  // one per run(); a worker runs each generation once
  int pending_ = 0;               // workers still running the current job
  bool stop_ = false;
  Job job_ = nullptr;
  void* context_ = nullptr;
  std::fenv_t env_{};
};

}  // namespace marionette::detail
