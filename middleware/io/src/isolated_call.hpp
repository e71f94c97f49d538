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
  int exitCode = 0;  // what `work` returned (Completed), or the raw exit code of an abnormal end (Crashed)
  int signal = 0;    // the signal that ended the child (Crashed), 0 if it exited
  [[nodiscard]] std::string describe(double timeoutSeconds) const;
};

// `work` runs in the child and returns a code in [0, 63]. The child never
// returns into the caller's code (it ends with _exit). An exit that did not come
// from `work` returning (a sanitizer turning a SEGV into exit(1)) counts as a crash.
[[nodiscard]] IsolatedOutcome runIsolated(const std::function<int()>& work, double timeoutSeconds,
                                          std::size_t memoryLimitBytes);

}  // namespace marionette::detail
