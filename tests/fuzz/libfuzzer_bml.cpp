// libFuzzer target: BML parser + scheduler on arbitrary bytes. Built and run by
// scripts/fuzz-bml (clang). Any crash it finds is kept as a regression test in
// tests/bml/scheduler_test.cpp.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "marionette/bml/scheduler.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const marionette::bml::Schedule s = marionette::bml::scheduleText(text);
  // The contract: every scheduled time is finite and every behavior is in order.
  for (const auto& b : s.behaviors)
    for (std::size_t k = 0; k < b.syncs.size(); ++k) {
      if (!(b.syncs[k].time == b.syncs[k].time) || b.syncs[k].time > 1e300 || b.syncs[k].time < -1e300) __builtin_trap();
      if (k > 0 && b.syncs[k].time < b.syncs[k - 1].time - 1e-6) __builtin_trap();
    }
  return 0;
}
