// libFuzzer target: phone alignments (plain phone lists, HTS labels, Rhubarb TSV) from
// text. Built by scripts/fuzz.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "marionette/speech/alignment_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marionette::speech;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (AlignmentFormat format : {AlignmentFormat::Auto, AlignmentFormat::PhoneList, AlignmentFormat::HtsLabel,
                                 AlignmentFormat::Rhubarb}) {
    const Alignment a = parseAlignment(text, "fuzz.txt", format);
    if (!a.error.empty()) continue;
    // The contract (phoneme.hpp): finite times, end >= start.
    for (const Phoneme& p : a.phonemes)
      if (!std::isfinite(p.start) || !std::isfinite(p.end) || p.end < p.start) __builtin_trap();
  }
  return 0;
}
