// Runs the `marionette` tool (built by this configuration: test_paths.hpp),
// or another program, as a user would, capturing its exit status and its stdout and stderr together.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "test_paths.hpp"

namespace marionette::test {

struct CliRun {
  int status = -1;
  std::string out;  // stdout and stderr
};

// Runs a shell command line (stderr joined to stdout).
inline CliRun runCommand(const std::string& commandLine) {
  const std::string cmd = commandLine + " 2>&1";
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int s = pclose(p);
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return r;
}

inline CliRun runCli(const std::string& args) { return runCommand(programPath("marionette") + " " + args); }

}  // namespace marionette::test
