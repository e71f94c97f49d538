#include "marionette/prt/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

namespace marionette::prt {

std::string progressBarText(const std::string& label, std::size_t done, std::size_t total, double seconds) {
  constexpr int kWidth = 24;
  const double fraction = total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 1.0;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  char tail[96];
  std::snprintf(tail, sizeof tail, "] %3d %%  %zu/%zu vertices  %.1f s", static_cast<int>(fraction * 100.0), done, total,
                seconds);
  return label + "  [" + bar + tail;
}

TransferProgress terminalProgressBar(std::string label) {
  if (!isatty(fileno(stderr))) return {};
  auto start = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  return [label = std::move(label), start](std::size_t done, std::size_t total) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - *start).count();
    std::fprintf(stderr, "\r%s%s", progressBarText(label, done, total, s).c_str(), done >= total ? "\n" : "");
    std::fflush(stderr);
  };
}

}  // namespace marionette::prt
