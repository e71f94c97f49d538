// A progress bar on the terminal for long precomputes:
//   prt RobotExpressive.glb  [##############..........]  58 %  4102/7070 vertices  1.1 s
// redrawn in place on stderr when stderr is a terminal; otherwise silent (CI logs, pipes).
#pragma once
#include <string>

#include "marionette/prt/transfer.hpp"

namespace marionette::prt {

// A TransferProgress that draws the bar; the last call (done == total) ends the line.
[[nodiscard]] TransferProgress terminalProgressBar(std::string label);
// The bar's text for a state (no terminal codes), for tests.
[[nodiscard]] std::string progressBarText(const std::string& label, std::size_t done, std::size_t total, double seconds);

}  // namespace marionette::prt
