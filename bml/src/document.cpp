#include "marionette/bml/document.hpp"

#include <array>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "dialect_forms.hpp"
#include "document_detail.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/core/enum_names.hpp"

namespace marionette::bml {

namespace {

constexpr std::array kCoreBehaviors = {"posture",  "postureShift", "locomotion", "gaze",     "gazeShift",
                                       "head",     "headDirectionShift", "faceLexeme", "faceFacs", "face",
                                       "faceShift", "gesture",     "pointing",   "speech",   "wait"};

// The attributes each behavior has in BML 1.0 (its sync points included), with those this
// realizer reads beyond it (locomotion's speed, proximity and facing; speech's voice and
// rate) and SmartBody's spellings of the same things (head type/repeats, face type/au,
// gesture name). Anything else is named in a warning: a misspelt "strok" is not silent.
struct KnownAttributes {
  const char* type;
  std::initializer_list<const char*> names;
};
const KnownAttributes kKnownAttributes[] = {
    // lexeme and stance: the attribute forms of <stance>/<pose>; posture: SmartBody's <body>.
    {"posture", {"start", "ready", "relax", "end", "priority", "lexeme", "stance", "posture"}},
    {"postureShift", {"start", "end", "lexeme", "stance", "posture"}},
    {"locomotion", {"start", "ready", "relax", "end", "target", "manner", "speed", "proximity", "facing"}},
    {"gaze", {"start", "ready", "relax", "end", "target", "influence", "offsetAngle", "offsetDirection"}},
    {"gazeShift", {"start", "end", "target", "influence", "offsetAngle", "offsetDirection"}},
    {"head", {"start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end", "lexeme", "repetition", "amount",
              "type", "repeats"}},
    {"headDirectionShift", {"start", "end", "target"}},
    {"faceLexeme", {"start", "attackPeak", "relax", "end", "lexeme", "amount"}},
    {"faceFacs", {"start", "attackPeak", "relax", "end", "au", "side", "amount"}},
    {"face", {"start", "attackPeak", "relax", "end", "lexeme", "amount", "type", "au", "side"}},
    {"faceShift", {"start", "end", "lexeme", "amount"}},
    {"gesture", {"start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end", "lexeme", "mode", "repetition",
                 "name", "target"}},  // target: a DEICTIC's (AsapRealizer, Greta)
    {"pointing", {"start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end", "target", "mode"}},
    {"speech", {"start", "end", "voice", "rate", "type"}},  // type: SmartBody's text/plain or SSML
    {"wait", {"start", "end"}},
    // SmartBody's own behaviors (dialect_forms.hpp): a clip by name, a message at a sync point.
    {"animation", {"start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end", "name", "speed"}},
    {"event", {"start", "stroke", "end", "message"}},
    {"saccade", {"start", "end", "mode", "finish", "direction", "magnitude", "duration"}},
    // SmartBody's <sbm:reach> (its sbm: attributes read without the prefix) and Marionette's
    // <reach target mode> (behavior/reach.hpp); the last ones are SmartBody's, read to be named.
    {"reach", {"start", "ready", "stroke", "relax", "end", "target", "mode", "action", "reach-type", "target-pos",
               "reach-duration", "reach-finish", "handle", "use-locomotion", "foot-ik", "fade-in", "fade-out",
               "reach-velocity", "grab-speed", "cons-joint", "cons-target"}},
    // Read so that it is named for what it is, not as unknown: not realized (yet).
    {"blend", {"start", "ready", "relax", "end", "name", "x", "y", "z"}},
    // BMLA's behaviors: interrupt or activate the target block at their start.
    {"interrupt", {"start", "end", "target"}},
    {"activate", {"start", "end", "target"}},
    // BMLT's idle life (AsapRealizer): seconds between blinks or breaths, +- range; amplitude is ours.
    {"blinkemitter", {"start", "end", "range", "avgwaitingtime"}},
    {"breathingemitter", {"start", "end", "range", "avgwaitingtime", "amplitude"}},
    // AsapRealizer's <bmlt:audiofile>: a WAV played from its start (audio_files.hpp).
    {"audiofile", {"start", "end", "fileName"}},
};

// Behaviors only SmartBody has, read in every dialect (their use makes Auto read the block
// as SmartBody's): <animation name>, <event message> (also as <sbm:event>), <saccade>, <blend>,
// <reach> (also as <sbm:reach>).
bool isSmartBodyBehavior(std::string_view name) {
  return name == "animation" || name == "event" || name == "saccade" || name == "blend" || name == "reach";
}

// "" when `type` has `attribute`, else the list of what it has (for the warning).
std::string unknownAttribute(std::string_view type, std::string_view attribute) {
  for (const KnownAttributes& k : kKnownAttributes) {
    if (type != k.type) continue;
    std::string list;
    for (const char* name : k.names) {
      if (attribute == name) return {};
      list += (list.empty() ? "" : ", ") + std::string(name);
    }
    return list;
  }
  return {};  // a type without a table: nothing to say
}

bool isCoreBehavior(std::string_view name) {
  for (const char* b : kCoreBehaviors)
    if (name == b) return true;
  return false;
}

std::string_view localName(std::string_view n) {
  auto colon = n.find(':');
  return colon == std::string_view::npos ? n : n.substr(colon + 1);
}
std::string_view prefixOf(std::string_view n) {
  auto colon = n.find(':');
  return colon == std::string_view::npos ? std::string_view{} : n.substr(0, colon);
}

std::string collapse(const std::string& s) {
  std::string out;
  bool space = false;
  for (char c : s) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      space = !out.empty();
    } else {
      if (space) out += ' ';
      space = false;
      out += c;
    }
  }
  return out;
}

// SmartBody's forms: an sbm: prefix on any element or attribute, or its declaration.
// Iterative: blocks may nest deeply (DeepNestingAndHugeBlocksFailCleanlyAndQuickly).
bool usesSmartBodyForms(const detail::XmlTree& tree, int root) {
  std::vector<int> stack{root};
  while (!stack.empty()) {
    const detail::XmlNode& n = tree[stack.back()];
    stack.pop_back();
    if (prefixOf(n.name) == "sbm") return true;
    if (isSmartBodyBehavior(n.name) || (n.name == "body" && n.attribute("posture"))) return true;
    for (const detail::XmlAttribute& a : n.attributes)
      if (prefixOf(a.name) == "sbm" || a.name == "xmlns:sbm") return true;
    for (int c = n.firstChild; c >= 0; c = tree[c].nextSibling)
      if (tree[c].type == detail::XmlNode::Type::Element) stack.push_back(c);
  }
  return false;
}

// FNV-1a: a generated block id that is the same for the same text on every run.
std::string textHash(std::string_view text) {
  std::uint32_t h = 2166136261u;
  for (char c : text) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", h);
  return buf;
}

class Parser {
 public:
  Parser(std::string_view text, const ParseOptions& options, detail::XmlParser xml)
      : text_(text), lines_(text), options_(options), xml_(xml) {}

  ParseResult run() {
    detail::XmlParseResult parsed = xml_(text_);
    if (!parsed.ok) {
      auto [line, col] = lines_.at(parsed.errorOffset);
      fatal(WarningType::ParsingFailure, "", "malformed XML: " + parsed.errorMessage, line, col);
      return std::move(result_);
    }
    tree_ = std::move(parsed.tree);
    int root = tree_.root;
    smartBody_ = options_.dialect == Dialect::SmartBody ||
                 (options_.dialect == Dialect::Auto && root >= 0 &&
                  (localName(tree_[root].name) == "act" || usesSmartBodyForms(tree_, root)));
    // SmartBody dialect: <act><bml>...</bml></act>.
    if (root >= 0 && localName(tree_[root].name) == "act") {
      int inner = tree_.childElement(root, "bml");
      if (inner < 0)
        for (int c = tree_[root].firstChild; c >= 0; c = tree_[c].nextSibling)
          if (isElement(c) && localName(tree_[c].name) == "bml") inner = c;
      if (inner >= 0) root = inner;
    }
    if (root < 0 || localName(tree_[root].name) != "bml") {
      auto [line, col] = root >= 0 ? place(root) : std::pair{0, 0};
      fatal(WarningType::ParsingFailure, "", "expected a <bml> element at the top", line, col);
      return std::move(result_);
    }
    Block block;
    std::tie(block.line, block.column) = place(root);
    block.id = attribute(root, "id");
    blockId_ = block.id;
    block.characterId = attribute(root, "characterId");
    // Compositions case-insensitively: Greta writes "append".
    block.composition = tree_[root].attribute("composition") ? attribute(root, "composition") : "MERGE";
    for (char& c : block.composition) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    block.smartBody = smartBody_;
    collectIds(root);
    if (block.id.empty() && smartBody_) {
      block.id = options_.generatedBlockId.empty() ? "sbm_" + textHash(text_) : options_.generatedBlockId;
      blockId_ = block.id;
      generated_.push_back("the block ('" + block.id + "')");
    } else if (block.id.empty()) {
      fatal(WarningType::ParsingFailure, "", "<bml> has no id (BML 1.0 requires one)", block.line, block.column);
      return std::move(result_);
    }
    readBlockAttributes(root, block);
    if (block.id.find_first_of(": \t\n\r") != std::string::npos) {
      fatal(WarningType::ParsingFailure, "",
            "<bml> id '" + block.id.substr(0, 40) + "' has a ':' or a space (references to other blocks use ':')",
            block.line, block.column);
      return std::move(result_);
    }
    if (block.composition != "MERGE" && block.composition != "APPEND" && block.composition != "REPLACE") {
      warn(WarningType::ParsingFailure, "",
           "composition '" + std::string(attribute(root, "composition")) +
               "' is not MERGE, APPEND or REPLACE; using MERGE",
           block.line, block.column);
      block.composition = "MERGE";
    }
    readChildren(root, false, block);
    if (tooLarge_) return std::move(result_);  // the block failed; its partial content is not scheduled
    if (!generated_.empty()) {  // one warning for the whole block
      std::string list;
      for (std::size_t k = 0; k < generated_.size(); ++k)
        list += (k == 0 ? "" : k + 1 == generated_.size() ? " and " : ", ") + generated_[k];
      warn(WarningType::ParsingFailure, "",
           "SmartBody mode: ids generated for " + list + " (BML 1.0 requires them; SmartBody's execBML adds them)",
           block.line, block.column);
      block.generatedIds = true;
    }
    result_.block = std::move(block);
    return std::move(result_);
  }

 private:
  // Where an element starts: its '<', one byte before its name.
  std::pair<int, int> place(int n) const { return lines_.at(tree_[n].offset - 1); }
  bool isElement(int n) const { return tree_[n].type == detail::XmlNode::Type::Element; }
  // The attribute's value, "" when the element has none (as pugixml's as_string()).
  const char* attribute(int n, std::string_view name) const {
    const std::string* value = tree_[n].attribute(name);
    return value ? value->c_str() : "";
  }

  void warn(WarningType type, std::string behavior, std::string message, int line, int col, bool isFatal = false) {
    result_.warnings.push_back({type, blockId_, std::move(behavior), line, col, std::move(message), isFatal});
  }
  void fatal(WarningType type, std::string behavior, std::string message, int line, int col) {
    warn(type, std::move(behavior), std::move(message), line, col, true);
  }

  // The <bml> element's other attributes: BMLA's (Block::Bmla) read, any other named.
  void readBlockAttributes(int root, Block& block) {
    for (const detail::XmlAttribute& a : tree_[root].attributes) {
      const std::string_view name = a.name;
      if (name == "xmlns" || name.substr(0, 6) == "xmlns:") continue;
      const std::string_view local = localName(name);
      const std::string ns = prefixOf(name).empty() ? std::string(kBmlNamespace) : namespaceOf(root, name, true);
      if (ns == kBmlaNamespace) {
        std::vector<std::string>* list = local == "interrupt"     ? &block.bmla.interrupt
                                         : local == "appendAfter" ? &block.bmla.appendAfter
                                         : local == "chunkAfter"  ? &block.bmla.chunkAfter
                                         : local == "onStart"     ? &block.bmla.onStart
                                                                  : nullptr;
        if (list) {
          std::string id;
          for (const char* c = a.value.c_str();; ++c) {  // "b1,b2" or "b1 b2"
            if (*c && *c != ',' && *c != ' ' && *c != '\t' && *c != '\n') {
              id += *c;
              continue;
            }
            if (!id.empty()) list->push_back(std::move(id));
            id.clear();
            if (!*c) break;
          }
        } else if (local == "preplan") {
          block.bmla.preplan = a.value == "true";
          if (!block.bmla.preplan && a.value != "false")
            warn(WarningType::ParsingFailure, "", "bmla:preplan=\"" + a.value.substr(0, 40) +
                                                      "\" is not true or false; the block starts as planned", block.line,
                 block.column);
        } else {
          warn(WarningType::CustomAttributeNotSupported, "",
               "BMLA's " + std::string(name) + " is not supported (this realizer reads interrupt, preplan, onStart, "
               "appendAfter and chunkAfter); ignored",
               block.line, block.column);
        }
        continue;
      }
      if (isBmlNamespace(ns) && (local == "id" || local == "characterId" || local == "composition")) continue;
      warn(WarningType::CustomAttributeNotSupported, "",
           "attribute '" + std::string(name) + "' of <bml> " +
               (isBmlNamespace(ns) ? std::string("is not one of id, characterId, composition") : "(" + ns + ") is not supported") +
               "; ignored",
           block.line, block.column);
    }
  }

  // Every id the block's behaviors give themselves, so that a generated one takes none of them.
  // Behaviors stand under <bml> or one <required> (readChildren goes no deeper).
  void collectIds(int n, bool inRequired = false) {
    for (int c = tree_[n].firstChild; c >= 0; c = tree_[c].nextSibling) {
      if (!isElement(c)) continue;
      if (const char* id = attribute(c, "id"); *id) usedIds_.insert(id);
      if (!inRequired && localName(tree_[c].name) == "required") collectIds(c, true);
    }
  }

  // The namespace of an element's or attribute's name, as XML scopes it: the nearest
  // xmlns / xmlns:prefix declaration on the node or an ancestor (other realizers' tools
  // declare a prefix on the behavior itself: <bmla:interrupt xmlns:bmla="...">).
  std::string namespaceOf(int node, std::string_view qualified, bool isAttribute) const {
    const std::string_view prefix = prefixOf(qualified);
    if (prefix.empty() && isAttribute) return std::string(kBmlNamespace);
    const std::string declaration = prefix.empty() ? std::string("xmlns") : "xmlns:" + std::string(prefix);
    for (int n = node; n >= 0 && isElement(n); n = tree_[n].parent)
      if (const std::string* value = tree_[n].attribute(declaration)) return value->c_str();
    return prefix.empty() ? std::string() : "undeclared prefix '" + std::string(prefix) + "'";
  }
  static bool isBmlNamespace(std::string_view ns) {
    return ns.empty() || ns == kBmlNamespace || ns == kCoreExtensionsNamespace || ns == kDraftBmlNamespace;
  }

  void readChildren(int parent, bool required, Block& block) {
    for (int n = tree_[parent].firstChild; n >= 0; n = tree_[n].nextSibling) {
      if (!isElement(n)) continue;
      if (tooLarge_) return;
      const std::string_view qualified = tree_[n].name;
      const std::string type(localName(qualified));
      auto [line, col] = place(n);
      const std::string id = attribute(n, "id");
      const std::string ns = namespaceOf(n, qualified, false);
      // Inside <required>, a behavior that cannot be realized fails the block (BML 1.0).
      const std::string failsBlock = required ? "; being required, it made the block fail" : "";
      if (prefixOf(qualified) == "sbm" && isSmartBodyBehavior(type)) {  // <sbm:event>
        readBehavior(n, type, required, block);
        continue;
      }
      if (ns == kBmlaNamespace && (type == "interrupt" || type == "activate")) {  // <bmla:interrupt target>
        readBehavior(n, type, required, block);
        continue;
      }
      if (ns == kBmltNamespace && (type == "blinkemitter" || type == "breathingemitter" || type == "audiofile")) {  // idle life, sound
        readBehavior(n, type, required, block);
        continue;
      }
      if (!isBmlNamespace(ns)) {
        warn(WarningType::CustomBehaviorNotSupported, id,
             "<" + std::string(qualified) + "> is a custom behavior (" + ns + "); it is not supported and was left out" +
                 failsBlock,
             line, col, required);
        continue;
      }
      if (type == "required") {
        if (required) {  // BML 1.0 has <required> only directly under <bml>; no recursion on nesting
          warn(WarningType::ParsingFailure, id, "<required> inside <required>; its content was left out", line, col, true);
          continue;
        }
        readChildren(n, true, block);
      } else if (type == "constraint") {
        readConstraint(n, required, block);
      } else if (type == "body" && prefixOf(qualified).empty() && tree_[n].attribute("posture")) {
        readBehavior(n, "posture", required, block);  // SmartBody <body posture="..."/>
      } else if (isCoreBehavior(type) || (prefixOf(qualified).empty() && isSmartBodyBehavior(type))) {
        readBehavior(n, type, required, block);
      } else {
        warn(WarningType::BehaviorTypeNotSupported, id,
             "<" + type + "> is not a BML 1.0 behavior; it was left out" + failsBlock, line, col, required);
      }
    }
  }

  void readBehavior(int n, const std::string& type, bool required, Block& block) {
    Behavior b;
    b.type = type;
    b.required = required;
    std::tie(b.line, b.column) = place(n);
    std::vector<std::string> unknown;  // named together in one warning, after the id is known
    std::string knownList;
    for (const detail::XmlAttribute& a : tree_[n].attributes) {
      const std::string_view name = a.name;
      if (name == "id") {
        b.id = a.value;
        continue;
      }
      if (name == "xmlns" || name.substr(0, 6) == "xmlns:") continue;
      const std::string ns = namespaceOf(n, name, true);
      if (type == "saccade" && name == "sbm:duration") {  // SmartBody's own spelling of the saccade's length
        b.attributes.push_back({"duration", a.value, b.line, b.column});
        continue;
      }
      // A reach's attributes are SmartBody's, with or without its prefix (sbm:action).
      const bool sbmReach = type == "reach" && prefixOf(name) == "sbm";
      if (!sbmReach && (!isBmlNamespace(ns) || prefixOf(name) == "sbm")) {
        warn(WarningType::CustomAttributeNotSupported, b.id,
             "attribute '" + std::string(name) + "' (" + (prefixOf(name) == "sbm" ? "SmartBody" : ns) +
                 ") is not supported and was ignored",
             b.line, b.column);
        continue;
      }
      const std::string local(localName(name));
      if (const std::string known = unknownAttribute(type, local); !known.empty()) {
        unknown.push_back("'" + local + "'");
        knownList = known;
        continue;
      }
      b.attributes.push_back({local, a.value, b.line, b.column});
    }
    if (b.id.empty() && smartBody_) {
      for (int k = ++typeCount_[type];; k = ++typeCount_[type])
        if (usedIds_.insert(type + "_" + std::to_string(k)).second) {
          b.id = type + "_" + std::to_string(k);
          break;
        }
      generated_.push_back("<" + type + "> at " + std::to_string(b.line) + ":" + std::to_string(b.column) + " ('" +
                           b.id + "')");
    }
    if (!unknown.empty()) {
      std::string names;
      for (const std::string& u : unknown) names += (names.empty() ? "" : ", ") + u;
      warn(WarningType::CustomAttributeNotSupported, b.id,
           "<" + type + "> has no attribute" + (unknown.size() > 1 ? "s " : " ") + names + " in BML 1.0 or here (it has " +
               knownList + "); ignored",
           b.line, b.column);
    }
    if (b.id.find_first_of(": \t\n\r") != std::string::npos) {
      warn(WarningType::ParsingFailure, b.id,
           "<" + type + "> id '" + b.id.substr(0, 40) + "' has a ':' or a space (sync references use ':'); it was left out",
           b.line, b.column, required);
      return;
    }
    if (b.id.empty()) {
      warn(WarningType::ParsingFailure, "",
           "<" + type + "> has no id (BML 1.0 requires one on every behavior); it was left out", b.line, b.column,
           required);
      return;
    }
    for (const Behavior& other : block.behaviors)
      if (other.id == b.id) {
        warn(WarningType::ParsingFailure, b.id, "behavior id '" + b.id + "' is used twice in the block; the second was left out",
             b.line, b.column, required);
        return;
      }
    if (block.behaviors.size() >= kMaxBehaviorsPerBlock) {
      tooLarge_ = true;
      fatal(WarningType::ParsingFailure, b.id,
            "the block has more than " + std::to_string(kMaxBehaviorsPerBlock) +
                " behaviors; split it into several blocks (the limit bounds scheduling time and memory)",
            b.line, b.column);
      return;
    }
    // BMLA's interrupt and activate act on the block they name: without one they do nothing,
    // so they are left out, and behaviors timed by them are removed (NO_SUCH_TARGET).
    if ((type == "interrupt" || type == "activate") &&
        (!b.attribute("target") || b.attribute("target")->value.empty())) {
      warn(WarningType::ParsingFailure, b.id,
           "BMLA's <" + type + "> names no target (the block to " + type + "); it was left out", b.line, b.column,
           required);
      return;
    }
    if (type == "speech") readSpeech(n, b);
    if (type == "posture" || type == "postureShift") readPostureChildren(n, b);
    if (const std::string w = detail::standardizeSpellings(b, smartBody_); !w.empty())
      warn(WarningType::CustomAttributeNotSupported, b.id, w, b.line, b.column);
    block.behaviors.push_back(std::move(b));
  }

  // Text and word marks, with character offsets into the collapsed text. Marks are BML's
  // <sync id>, SSML's <mark name> (SmartBody, Greta) and AsapRealizer's <tm id>; other
  // elements (SSML's <speak>, <prosody>, <emphasis>, ...) give their text. The walk is
  // iterative and bounded by the document, which the XML parser has already read.
  void readSpeech(int n, Behavior& b) {
    int textNode = tree_.childElement(n, "text");
    if (textNode < 0)
      for (int c = tree_[n].firstChild; c >= 0; c = tree_[c].nextSibling)
        if (isElement(c) && localName(tree_[c].name) == "text") textNode = c;
    const int source = textNode >= 0 ? textNode : n;
    std::string raw;
    // The collapsed text's length so far, kept as the text is read: a mark's offset without
    // collapsing the text again at every mark (quadratic in a line of thousands of marks).
    std::size_t collapsedLength = 0;
    bool pendingSpace = false, lastWasSpace = false;
    std::vector<int> stack;  // siblings still to visit, last first
    for (int c = tree_[source].lastChild; c >= 0; c = tree_[c].previousSibling) stack.push_back(c);
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      if (!isElement(c)) {  // text or CDATA
        for (const char* p = tree_[c].value.c_str(); *p; ++p) {  // as collapse() does
          lastWasSpace = *p == ' ' || *p == '\t' || *p == '\n' || *p == '\r';
          if (lastWasSpace) {
            pendingSpace = collapsedLength > 0;
            continue;
          }
          collapsedLength += pendingSpace ? 2 : 1;
          pendingSpace = false;
        }
        raw += tree_[c].value;
        continue;
      }
      const std::string_view kind = localName(tree_[c].name);
      const char* idAttribute = kind == "sync" || kind == "tm" ? "id" : kind == "mark" ? "name" : nullptr;
      if (!idAttribute) {
        for (int g = tree_[c].lastChild; g >= 0; g = tree_[g].previousSibling) stack.push_back(g);
        continue;
      }
      const std::string id = attribute(c, idAttribute);
      auto [line, col] = place(c);
      if (id.empty()) {
        warn(WarningType::ParsingFailure, b.id,
             "<" + std::string(kind) + "> in speech text has no " + idAttribute + "; it was ignored", line, col);
        continue;
      }
      // Offset in the collapsed text where the next word starts.
      const bool gap = collapsedLength > 0 && lastWasSpace && raw.back() != '\r';
      b.marks.push_back({id, collapsedLength + (gap ? 1 : 0)});
    }
    b.text = collapse(raw);
    // A mark after the last word (a space may follow it) is the end of the text: the
    // offset counted that space, which collapsing trims away.
    for (WordMark& m : b.marks) m.characterOffset = std::min(m.characterOffset, b.text.size());
  }

  // BML 1.0's element form of a posture: <stance type="SITTING"/> and <pose part="WHOLEBODY"
  // lexeme="..."/> children, read as the stance and lexeme attributes (an attribute given
  // on the behavior itself comes first).
  void readPostureChildren(int n, Behavior& b) {
    for (int c = tree_[n].firstChild; c >= 0; c = tree_[c].nextSibling) {
      if (!isElement(c)) continue;
      const std::string_view kind = localName(tree_[c].name);
      const char* name = kind == "stance" ? "stance" : kind == "pose" ? "lexeme" : nullptr;
      const char* value = kind == "stance" ? attribute(c, "type") : attribute(c, "lexeme");
      auto [line, col] = place(c);
      if (!name) {
        warn(WarningType::ParsingFailure, b.id, "<" + std::string(kind) + "> in <" + b.type +
                                                    ">: expected <stance type> or <pose lexeme>; it was ignored",
             line, col);
      } else if (!*value) {
        warn(WarningType::ParsingFailure, b.id,
             "<" + std::string(kind) + "> has no " + (kind == "stance" ? "type" : "lexeme") + "; it was ignored", line, col);
      } else if (!b.attribute(name)) {
        b.attributes.push_back({name, value, line, col});
      }
    }
  }

  void readConstraint(int n, bool required, Block& block) {
    for (int c = tree_[n].firstChild; c >= 0; c = tree_[c].nextSibling) {
      if (!isElement(c)) continue;
      const std::string kind(localName(tree_[c].name));
      Constraint k;
      k.id = attribute(n, "id");
      k.required = required;
      std::tie(k.line, k.column) = place(c);
      if (kind == "synchronize") k.kind = Constraint::Kind::Synchronize;
      else if (kind == "before") k.kind = Constraint::Kind::Before;
      else if (kind == "after") k.kind = Constraint::Kind::After;
      else {
        warn(WarningType::ParsingFailure, k.id, "<" + kind + "> in <constraint>: expected synchronize, before or after",
             k.line, k.column);
        continue;
      }
      if (k.kind != Constraint::Kind::Synchronize) {
        k.anchor = {attribute(c, "ref"), k.line, k.column};
        if (k.anchor.ref.empty()) {
          warn(WarningType::ParsingFailure, k.id, "<" + kind + "> needs a ref attribute; the constraint was left out", k.line,
               k.column);
          continue;
        }
      }
      for (int s = tree_[c].firstChild; s >= 0; s = tree_[s].nextSibling) {
        if (!isElement(s) || localName(tree_[s].name) != "sync") continue;
        auto [line, col] = place(s);
        if (++constraintSyncs_ > kMaxConstraintSyncsPerBlock) {
          tooLarge_ = true;
          fatal(WarningType::ParsingFailure, k.id,
                "the block's constraints have more than " + std::to_string(kMaxConstraintSyncsPerBlock) +
                    " sync references; split it into several blocks (the limit bounds scheduling time)",
                line, col);
          return;
        }
        k.syncs.push_back({attribute(s, "ref"), line, col});
      }
      block.constraints.push_back(std::move(k));
    }
  }

  std::string_view text_;
  LineIndex lines_;
  const ParseOptions& options_;
  detail::XmlParser xml_;
  detail::XmlTree tree_;
  bool smartBody_ = false;
  std::set<std::string> usedIds_;
  std::map<std::string, int> typeCount_;
  std::vector<std::string> generated_;  // what got an id, for the one warning
  ParseResult result_;
  std::string blockId_;
  std::size_t constraintSyncs_ = 0;
  bool tooLarge_ = false;
};
}  // namespace

const Attribute* Behavior::attribute(std::string_view name) const noexcept {
  for (const Attribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

std::string ParseResult::format(const std::string& source) const {
  std::string out;
  for (const Warning& w : warnings) {
    std::string where;
    if (!w.blockId.empty()) where += "block '" + w.blockId + "'";
    if (!w.behaviorId.empty()) where += std::string(where.empty() ? "" : ", ") + "behavior '" + w.behaviorId + "'";
    Diagnostic d{w.fatal ? Severity::Error : Severity::Warning, source, w.line, w.column,
                 std::string(toString(w.type)) + ": " + (where.empty() ? "" : where + ": ") + w.message};
    out += d.format() + '\n';
  }
  return out;
}

ParseResult parseBlock(std::string_view text, const ParseOptions& options) {
  return Parser(text, options, detail::parseXml).run();
}

ParseResult detail::parseBlockWith(std::string_view text, const ParseOptions& options, XmlParser xml) {
  return Parser(text, options, xml).run();
}

constexpr EnumName<Dialect> kDialectNames[] = {
    {"auto", Dialect::Auto}, {"bml", Dialect::Bml}, {"smartbody", Dialect::SmartBody}};

std::string_view toString(Dialect d) noexcept { return nameOfValue<Dialect>(d, kDialectNames, "auto"); }

std::optional<Dialect> dialectFromName(std::string_view name) noexcept {
  return valueOfName<Dialect>(name, kDialectNames);
}

}  // namespace marionette::bml
