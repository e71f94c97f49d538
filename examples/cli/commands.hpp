// Subcommands of the `marionette` tool. Each returns the process exit code:
// 0 success, 1 warnings, 2 errors (errors on stderr as file:line:col: error: ...).
#pragma once
#include <string>
#include <vector>

namespace marionette::cli {

int inspectCommand(const std::vector<std::string>& args);
int runCommand(const std::vector<std::string>& args);
int speakCommand(const std::vector<std::string>& args);
int lipsyncCommand(const std::vector<std::string>& args);
int retargetCommand(const std::vector<std::string>& args);
#ifdef MARIONETTE_CLI_HAS_PRT
int prtCommand(const std::vector<std::string>& args);
int prtReportCommand(const std::vector<std::string>& args);  // `prt report` (prt_report.cpp)
#endif
#ifdef MARIONETTE_CLI_HAS_BML
int bmlCheckCommand(const std::vector<std::string>& args);
#endif

}  // namespace marionette::cli
