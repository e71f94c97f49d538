#include "marionette/speech/text_pieces.hpp"

#include <algorithm>

namespace marionette::speech {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// The best cut in (from, limit]: after a sentence end + space, after a clause mark + space,
// after a space; 0 when there is none.
std::size_t bestCut(std::string_view text, std::size_t from, std::size_t limit) {
  std::size_t sentence = 0, clause = 0, space = 0;
  for (std::size_t i = from + 1; i < limit; ++i) {  // a cut at i: text[i-1] is a space
    if (!isSpace(text[i - 1]) || isSpace(text[i])) continue;
    space = i;
    std::size_t k = i - 1;
    while (k > from && isSpace(text[k])) --k;
    const char c = text[k];
    if (c == '.' || c == '!' || c == '?') sentence = i;
    else if (c == ',' || c == ';' || c == ':') clause = i;
  }
  return sentence ? sentence : clause ? clause : space;
}

}  // namespace

std::vector<std::size_t> textPieceEnds(std::string_view text, std::size_t maxBytes) {
  maxBytes = std::max<std::size_t>(maxBytes, 4);  // room for any UTF-8 sequence
  std::vector<std::size_t> ends;
  std::size_t from = 0;
  while (text.size() - from > maxBytes) {
    const std::size_t limit = from + maxBytes;
    std::size_t cut = bestCut(text, from, limit + 1);
    if (cut == 0) {  // one word longer than a piece: cut at a code point's start
      cut = limit;
      while (cut > from + 1 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
    }
    ends.push_back(cut);
    from = cut;
  }
  ends.push_back(text.size());
  return ends;
}

}  // namespace marionette::speech
