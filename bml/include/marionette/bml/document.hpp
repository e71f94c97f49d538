// BML 1.0 blocks as parsed documents: the block, its behaviors and their
// attributes, each with its line:column in the source. Scheduling and
// realization come on top of this (issue 3); this layer only reads and checks
// the XML structure and reports errors a user can act on.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::bml {

struct Attribute {
  std::string name, value;
};

struct Behavior {
  std::string type;  // element name without namespace prefix: "head", "speech", "gaze", ...
  std::string id;
  std::vector<Attribute> attributes;  // all attributes except id, in source order
  std::string text;                   // concatenated text content (speech), trimmed
  bool required = false;              // inside <required>: must not be dropped
  int line = 0, column = 0;

  [[nodiscard]] const std::string* attribute(std::string_view name) const noexcept;
};

struct Block {
  std::string id;
  std::string characterId;  // BML 1.0 default "" = the default character
  std::string composition;  // "MERGE" (default), "APPEND", "REPLACE"
  std::vector<Behavior> behaviors;
  int line = 0, column = 0;
};

struct ParseResult {
  std::optional<Block> block;  // empty on an error
  Diagnostics diagnostics;     // each names the source (file or block) and line:column
};

// Parses one <bml> block. `source` names the file or stream in diagnostics.
[[nodiscard]] ParseResult parseBlock(std::string_view text, const std::string& source);

}  // namespace marionette::bml
