// Where a long line is cut for the synthesizer: after sentences, then clauses,
// then words, never inside a UTF-8 sequence, every piece within the limit.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "marionette/speech/text_pieces.hpp"

using marionette::speech::textPieceEnds;

namespace {

std::vector<std::string> pieces(const std::string& text, std::size_t maxBytes) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t end : textPieceEnds(text, maxBytes)) {
    EXPECT_GT(end, from) << "an empty piece in \"" << text << "\"";
    EXPECT_LE(end - from, maxBytes) << "a piece over the limit in \"" << text << "\"";
    out.push_back(text.substr(from, end - from));
    from = end;
  }
  EXPECT_EQ(from, text.size());
  return out;
}

}  // namespace

TEST(TextPieces, AShortTextIsOnePiece) {
  EXPECT_EQ(textPieceEnds("Hello world.", 240), std::vector<std::size_t>{12});
  EXPECT_EQ(textPieceEnds("", 240), std::vector<std::size_t>{0});
}

TEST(TextPieces, CutsAfterASentenceBeforeAClauseOrAWord) {
  EXPECT_EQ(pieces("One two. Three, four five six", 20), (std::vector<std::string>{"One two. ", "Three, four five six"}));
  EXPECT_EQ(pieces("One, two three four five six", 20), (std::vector<std::string>{"One, ", "two three four five ", "six"}));
  EXPECT_EQ(pieces("aaaa bbbb cccc dddd eeee", 12), (std::vector<std::string>{"aaaa bbbb ", "cccc dddd ", "eeee"}));
  // A question or an exclamation ends a sentence too, and spaces after it stay with it.
  EXPECT_EQ(pieces("Really?  Yes it is so.", 12), (std::vector<std::string>{"Really?  ", "Yes it is ", "so."}));
}

TEST(TextPieces, AWordLongerThanAPieceIsCutAtACodePoint) {
  std::string word;
  for (int i = 0; i < 10; ++i) word += "\xC3\xA9";  // é, two bytes each
  const std::vector<std::string> p = pieces(word, 5);
  ASSERT_EQ(p.size(), 5u);
  for (const std::string& s : p) EXPECT_EQ(s, "\xC3\xA9\xC3\xA9");
}

TEST(TextPieces, ALongLineKeepsEveryByteInOrder) {
  std::string text;
  for (int i = 0; i < 100; ++i) text += "Sentence number " + std::to_string(i) + ", with a clause. ";
  std::string joined;
  for (const std::string& s : pieces(text, 240)) joined += s;
  EXPECT_EQ(joined, text);
}
