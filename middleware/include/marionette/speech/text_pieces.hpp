// Where a long line of speech is cut so that a synthesizer can say it in pieces:
// espeak-ng has one engine per process, and a line said in one call holds it for
// as long as the line takes (about half a millisecond per character here), so a
// short line asked meanwhile, from another scene, would wait behind it. Said in
// pieces of at most a few hundred bytes, with the engine handed on between them,
// it waits one piece at most. Cuts fall after a sentence's end when there is one,
// else after a clause's punctuation, else at a space, else (one very long word) at
// a UTF-8 boundary: cutting where the speaker would pause anyway keeps the prosody.
#pragma once
#include <cstddef>
#include <string_view>
#include <vector>

namespace marionette::speech {

// Bytes per piece when a synthesizer cuts a line (espeak-ng: about 0.1 s to say).
inline constexpr std::size_t kSpeechPieceBytes = 240;

// The end offset of each piece, in order; the last is text.size(). Each piece
// holds at most maxBytes bytes (maxBytes >= 4). A text no longer than maxBytes is one piece.
[[nodiscard]] std::vector<std::size_t> textPieceEnds(std::string_view text, std::size_t maxBytes = kSpeechPieceBytes);

}  // namespace marionette::speech
