// Where a long line of speech is cut so that a synthesizer can say it in pieces:
// espeak-ng has one engine per process, and a line said in one call holds it for
// as long as the line takes (about 0.05 ms a character here: 46.5 ms for 1000), so a
// short line asked meanwhile, from another scene, would wait behind it. Said in
// pieces of at most a few hundred bytes, with the engine handed on between them,
// it waits one piece at most. Cuts fall after a sentence's end when there is one,
// else after a clause's punctuation, else at a space, else (one very long word, or
// a script written without spaces) at a UTF-8 boundary. Each piece is its own
// synthesis and ends as a clause ends: after a sentence that is what the speaker does
// anyway; a cut at a clause or a space (a 240-byte run without a full stop) adds a
// short pause and a falling pitch there.
#pragma once
#include <cstddef>
#include <string_view>
#include <vector>

namespace marionette::speech {

// Bytes per piece when a synthesizer cuts a line (espeak-ng: about 11 ms to say).
inline constexpr std::size_t kSpeechPieceBytes = 240;

// The end offset of each piece, in order; the last is text.size(). Each piece
// holds at most maxBytes bytes (maxBytes >= 4). A text no longer than maxBytes is one piece.
[[nodiscard]] std::vector<std::size_t> textPieceEnds(std::string_view text, std::size_t maxBytes = kSpeechPieceBytes);

}  // namespace marionette::speech
