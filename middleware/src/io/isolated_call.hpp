// Runs a piece of work in a forked child process with a time and memory limit,
// so that a crash or a hang inside a third-party parser becomes an error
// instead of taking the caller's process down. POSIX only.
//
// Why: Assimp 5.2.5 (Debian 12) dereferences bad pointers on some malformed
// files (found by tests/fuzz: an X file whose MeshMaterialList lacks a
// `Material {` keyword segfaults in its reader), and its OFF reader allocates
// what the header declares before reading. Neither can be fixed from outside.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace marionette::detail {

struct IsolatedOutcome {
  enum class Kind { Completed, Crashed, TimedOut, Unavailable } kind = Kind::Unavailable;
  int exitCode = 0;  // when Completed
  int signal = 0;    // when Crashed
  [[nodiscard]] std::string describe(double timeoutSeconds) const;
};

// `work` runs in the child; its return value is the child's exit code. The
// child never returns into the caller's code (it ends with _exit).
[[nodiscard]] IsolatedOutcome runIsolated(const std::function<int()>& work, double timeoutSeconds,
                                          std::size_t memoryLimitBytes);

}  // namespace marionette::detail
