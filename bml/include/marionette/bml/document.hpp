// BML 1.0 blocks as parsed documents: the block, its behaviors (with their
// attributes and speech word marks) and its constraints, each with its
// line:column in the source. Every problem is a typed BML warning; nothing is
// dropped silently.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bml/feedback.hpp"

namespace marionette::bml {

inline constexpr std::string_view kBmlNamespace = "http://www.bml-initiative.org/bml/bml-1.0";
inline constexpr std::string_view kCoreExtensionsNamespace = "http://www.bml-initiative.org/bml/coreextensions-1.0";
// The draft namespace of BML before 1.0, still written by Greta and older Elckerlyc scripts:
// read as BML 1.0 (issue 24).
inline constexpr std::string_view kDraftBmlNamespace = "http://www.mindmakers.org/projects/BML";
// AsapRealizer's BML Agent extensions (BMLA): how a block is planned and started.
inline constexpr std::string_view kBmlaNamespace = "http://www.asap-project.org/bmla";
// AsapRealizer's (Elckerlyc's) own behaviors, BMLT: read here, <bmlt:blinkemitter> and
// <bmlt:breathingemitter> (idle life), and <bmlt:audiofile fileName>.
inline constexpr std::string_view kBmltNamespace = "http://hmi.ewi.utwente.nl/bmlt";

// Size limits of one block. Real blocks have tens of behaviors; the limits keep
// scheduling time and memory bounded on any input (a block over them fails with
// a PARSING_FAILURE saying so).
inline constexpr std::size_t kMaxBehaviorsPerBlock = 1000;
inline constexpr std::size_t kMaxConstraintSyncsPerBlock = 1000;

struct Attribute {
  std::string name, value;
  int line = 0, column = 0;
};

// A <sync id> inside speech text: its id and how many characters of text come before it.
struct WordMark {
  std::string id;
  std::size_t characterOffset = 0;
};

struct Behavior {
  std::string type;  // local element name: "head", "speech", "gaze", ...
  std::string id;
  std::vector<Attribute> attributes;  // attributes in the BML namespaces, except id, in source order
  std::string text;                   // speech: the text, whitespace collapsed
  std::vector<WordMark> marks;        // speech: word marks in text order
  bool required = false;              // inside <required>
  int line = 0, column = 0;

  [[nodiscard]] const Attribute* attribute(std::string_view name) const noexcept;
};

struct ConstraintSync {
  std::string ref;  // the sync reference text
  int line = 0, column = 0;
};

struct Constraint {
  enum class Kind { Synchronize, Before, After } kind = Kind::Synchronize;
  std::string id;
  ConstraintSync anchor;             // before/after: the ref="..." of the element
  std::vector<ConstraintSync> syncs; // synchronize: all equal; before/after: each before/after the anchor
  bool required = false;
  int line = 0, column = 0;
};

struct Block {
  std::string id;
  bool smartBody = false;   // read in SmartBody mode (ParseOptions), given or detected
  bool generatedIds = false;  // some ids were generated (SmartBody mode)
  std::string characterId;  // "" = the default character
  std::string composition;  // "MERGE" (default), "APPEND", "REPLACE"
  // BMLA's block attributes (lists of block ids): interrupt them when this block starts; start
  // after they end (appendAfter) or once they relax (chunkAfter: their behaviors past their
  // relax sync point); activate preplanned ones when this starts (onStart); preplan: plan
  // now, start when activated (Realizer::activate, <bmla:activate>, another's onStart).
  struct Bmla {
    std::vector<std::string> interrupt, appendAfter, chunkAfter, onStart;
    bool preplan = false;
  } bmla;
  std::vector<Behavior> behaviors;
  std::vector<Constraint> constraints;
  int line = 0, column = 0;
};

struct ParseResult {
  std::optional<Block> block;     // empty when the block failed as a whole
  std::vector<Warning> warnings;  // every problem, typed, with line:column

  // "source:line:col: warning: TYPE: message" lines (error: for fatal ones).
  [[nodiscard]] std::string format(const std::string& source) const;
};

// Which realizer's users wrote the block. SmartBody's execBML adds the ids its
// scripts leave out; in SmartBody mode they are generated: the block's from
// ParseOptions::generatedBlockId (else from a hash of the text, stable across runs),
// a behavior's as TYPE_N (head_1, gaze_2, ...), never one the block uses itself,
// with one warning naming them. Auto is SmartBody mode when the block uses SmartBody's
// forms (an <act> wrapper, an sbm: prefix), else BML 1.0, where a missing id fails.
enum class Dialect { Auto, Bml, SmartBody };
[[nodiscard]] std::string_view toString(Dialect d) noexcept;  // "auto", "bml", "smartbody"
[[nodiscard]] std::optional<Dialect> dialectFromName(std::string_view name) noexcept;

struct ParseOptions {
  Dialect dialect = Dialect::Auto;
  std::string generatedBlockId;  // for a block without id in SmartBody mode ("" = from the text's hash)
};

// Parses one <bml> block (or a SmartBody <act> wrapping one).
[[nodiscard]] ParseResult parseBlock(std::string_view text, const ParseOptions& options = {});

}  // namespace marionette::bml
