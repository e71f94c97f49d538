#include "isolated_call.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

namespace marionette::detail {

namespace {
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;  // ASan reserves terabytes of address space: no RLIMIT_AS
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif
// Exit codes below this did not come from `work` returning.
constexpr int kExitBase = 64;
}  // namespace

std::string IsolatedOutcome::describe(double timeoutSeconds) const {
  switch (kind) {
    case Kind::Completed: return "completed with exit code " + std::to_string(exitCode);
    case Kind::Crashed: {
      if (signal == 0) return "crashed (ended abnormally with exit code " + std::to_string(exitCode) + ")";
      const char* name = strsignal(signal);
      return "crashed (signal " + std::to_string(signal) + (name ? std::string(", ") + name : "") + ")";
    }
    case Kind::TimedOut: return "did not finish within " + std::to_string(static_cast<int>(timeoutSeconds)) + " s";
    case Kind::Unavailable: break;
  }
  return "could not be isolated";
}

IsolatedOutcome runIsolated(const std::function<int()>& work, double timeoutSeconds, std::size_t memoryLimitBytes) {
  IsolatedOutcome out;
  const pid_t pid = fork();
  if (pid < 0) return out;  // Unavailable: the caller runs the work in-process
  if (pid == 0) {
    if (!kAddressSanitizer && memoryLimitBytes > 0) {
      rlimit limit{memoryLimitBytes, memoryLimitBytes};
      setrlimit(RLIMIT_AS, &limit);
    }
    // A crash should end the child by its signal; a sanitizer's handler would
    // turn it into an ordinary exit, hence also the exit-code offset below.
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
    int code = 3;
    try {
      code = work();
    } catch (...) {
      code = 4;
    }
    _exit(kExitBase + (code & 0x3f));  // no atexit handlers, no flushing the parent's buffers twice
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
  auto pause = std::chrono::microseconds(200);
  for (;;) {
    int status = 0;
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) {
      if (WIFEXITED(status) && WEXITSTATUS(status) >= kExitBase) {
        out.kind = IsolatedOutcome::Kind::Completed;
        out.exitCode = WEXITSTATUS(status) - kExitBase;
      } else if (WIFEXITED(status)) {  // ended before `work` returned: a sanitizer report, exit() in a library
        out.kind = IsolatedOutcome::Kind::Crashed;
        out.exitCode = WEXITSTATUS(status);
      } else if (WIFSIGNALED(status)) {
        out.kind = IsolatedOutcome::Kind::Crashed;
        out.signal = WTERMSIG(status);
      }
      return out;
    }
    if (done < 0 && errno != EINTR) return out;
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      out.kind = IsolatedOutcome::Kind::TimedOut;
      return out;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
}

}  // namespace marionette::detail
