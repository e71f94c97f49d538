// Runs the `marionette` tool (the MARIONETTE_CLI path the test target defines)
// as a user would, capturing its exit status and its stdout and stderr together.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace marionette::test {

struct CliRun {
  int status = -1;
  std::string out;  // stdout and stderr
};

inline CliRun runCli(const std::string& args) {
  const std::string cmd = std::string(MARIONETTE_CLI) + " " + args + " 2>&1";
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int s = pclose(p);
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  return r;
}

}  // namespace marionette::test
