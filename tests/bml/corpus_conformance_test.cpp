// Runs every file of ../shared/bml-corpus/openbmlparser (the BML 1.0 reference
// parser's test blocks) and checks what its header comment states:
//   "Required timing:" / "Expected timing:" relations such as
//       h1:start = h2:start-2 = 4      g2:end = 4      speech1:start < 10
//       h1:start = g1:end, > 4         (", > 4" continues from the last term)
//   "Realization: ... should be removed and a warning should be generated"
//   "Expected execution: Warning: ... should be omitted"
//   "Error: X not found"
// Statements that cannot be checked as written (typos, or a header that
// disagrees with its own XML) are listed in kDivergences with the reason;
// nothing is skipped silently.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include "marionette/bml/scheduler.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {

const std::string kDir = ::marionette::test::sharedDir() + "/bml-corpus/openbmlparser";

// file -> why a statement of its header is not checked as written.
const std::map<std::string, std::string> kDivergences = {
    {"testbeatandnod.xml",
     "header says beat1:end = 5 and uses 'nod' for nod1, but the XML has end=\"7\"; checked: beat1 3..7, nod1:start = beat1:strokeEnd"},
    {"testspeech_gesturestart.xml", "header relation 'g1:stroke = speech1:this' names no sync point the XML defines"},
    {"testspeech_syncatstartandtobeat.xml", "header misspells the speech id ('welcom' for 'welkom')"},
    {"testspeech_syncatstart.xml", "header names 'speech1' but the speech's id is 'welkom'; checked: welkom:start = 0"},
    {"testnod_absolute.xml",
     "header says start = 2, end = 0 but the XML (and the header's own constraints) say start=\"0\" end=\"2\"; checked: 0 and 2"},
    {"testnod2x_absolute.xml",
     "header's 'nod1:end = 3' contradicts its own constraint list (c2 nod2:start,3); checked: nod1:start = 1, nod2:start = 3"},
    {"testoffsetchainreversed.xml", "header's 'h2:end = 6' is h2:start in its own constraint list; checked: h2:start = 6"},
    {"testoffsetchainneg.xml",
     "header's 'h2:end = h1:end' contradicts its own constraint list (h2:start = h1:end); checked: the constraint list"},
    {"testoffsetgaze.xml", "header's 'gaze1:ready = speech1:ready' (speech has no ready) is 'speech1:start = gaze1:ready' in its constraint list"},
    {"testoffsetgaze2.xml", "as testoffsetgaze.xml"},
    {"testspeech_nodtimedtosync_capitalization.xml",
     "header uses speech1/nod1/syncstart1; the XML's ids are the capitalized ones it tests"},
    {"testspeech_unknownsync.xml",
     "header relates nod1:start to speech1:unknown, a sync point the speech does not define: nod1 is removed with NO_SUCH_TARGET"},
};

// For the files above: what the XML (or the header's own constraint list) implies.
const std::map<std::string, std::vector<std::string>> kCheckedInstead = {
    {"testspeech_syncatstart.xml", {"welkom:start = 0"}},
    {"testnod_absolute.xml", {"nod1:start = 0", "nod1:end = 2"}},
    {"testnod2x_absolute.xml", {"nod1:start = 1", "nod2:start = 3"}},
    {"testoffsetchainreversed.xml", {"h1:start = 4", "h2:start = 6", "h3:start = 8", "h4:start = 10"}},
    {"testoffsetchainneg.xml",
     {"speech1:start = 0", "h1:start = speech1:s1 > 0", "h2:start = h1:end", "h3:start = h2:end", "h4:start = h3:end"}},
    {"testoffsetgaze.xml", {"speech1:start > 2", "gaze1:start = 2", "speech1:start = gaze1:ready"}},
    {"testoffsetgaze2.xml", {"speech1:start > 2", "gaze1:start = 2", "speech1:start = gaze1:ready"}},
    {"testspeech_syncatstartandtobeat.xml", {"welkom:start = 0", "g1:start = welkom:deicticheart1", "g1:end = welkom:deicticheart1+2"}},
    {"testspeech_gesturestart.xml", {"g1:start = 0"}},
    {"testspeech_nodtimedtosync_capitalization.xml",
     {"speech1WithCapitalizedStuff:start = 6", "speech1WithCapitalizedStuff:syncStart_1 = nod1WithCapitalizedStuff:start",
      "nod1WithCapitalizedStuff:end = 9"}},
};

struct Term {
  bool number = false;
  double value = 0.0;
  std::string behavior, sync;
  double offset = 0.0;
};

std::optional<Term> parseTerm(std::string s) {
  s = std::regex_replace(s, std::regex("^\\s+|\\s+$|;$"), "");
  if (s.empty()) return std::nullopt;
  std::smatch m;
  if (std::regex_match(s, m, std::regex(R"(([-+]?[0-9.]+))"))) return Term{true, std::stod(m[1]), {}, {}, 0.0};
  if (std::regex_match(s, m, std::regex(R"(([A-Za-z_]\w*):([A-Za-z_]\w*(?:-[A-Za-z_]\w*)*)\s*([-+]\s*[0-9.]+)?)"))) {
    Term t;
    t.behavior = m[1];
    t.sync = m[2];
    if (m[3].matched) t.offset = std::stod(std::regex_replace(m[3].str(), std::regex("\\s"), ""));
    return t;
  }
  return std::nullopt;
}

std::optional<double> evaluate(const Schedule& s, const Term& t) {
  if (t.number) return t.value;
  auto v = s.time(t.behavior, t.sync);
  if (!v) return std::nullopt;
  return *v + t.offset;
}

// Header sections: name -> lines.
std::map<std::string, std::vector<std::string>> headerSections(const std::string& text) {
  std::map<std::string, std::vector<std::string>> out;
  const auto a = text.find("<!--"), b = text.find("-->");
  if (a == std::string::npos || b == std::string::npos) return out;
  std::istringstream in(text.substr(a + 4, b - a - 4));
  std::string line, current;
  while (std::getline(in, line)) {
    std::smatch m;
    if ((std::regex_match(line, m, std::regex(R"(\s*([A-Z][A-Za-z ]+):\s*(.*))")) && m[1].str().find(' ') == std::string::npos) ||
        std::regex_match(line, m, std::regex(R"(\s*((?:Required|Expected) (?:timing|behavior|execution)|Realization|Error|Warning):\s*(.*))"))) {
      current = m[1];
      if (!m[2].str().empty()) out[current].push_back(m[2]);
      continue;
    }
    if (!current.empty() && line.find_first_not_of(" \t\r") != std::string::npos) out[current].push_back(line);
  }
  return out;
}

// Checks one timing line; returns a failure message or "".
std::string checkRelation(const Schedule& s, const std::string& line) {
  if (std::regex_match(line, std::regex(R"(\s*(none|-)\s*)"))) return "";
  // Split into terms and operators: a op b op c, where ", op" continues from the last term.
  std::vector<std::string> terms;
  std::vector<std::string> ops;
  std::string rest = std::regex_replace(line, std::regex(R"(,\s*([<>=]))"), " $1");
  std::regex op(R"(\s*(<=|>=|=|<|>)\s*)");
  std::sregex_token_iterator it(rest.begin(), rest.end(), op, {-1, 1}), end;
  for (int i = 0; it != end; ++it, ++i) (i % 2 == 0 ? terms : ops).push_back(*it);
  if (terms.size() < 2 || ops.size() != terms.size() - 1) return "cannot read the statement '" + line + "'";
  for (std::size_t i = 0; i < ops.size(); ++i) {
    auto ta = parseTerm(terms[i]), tb = parseTerm(terms[i + 1]);
    if (!ta || !tb) return "cannot read a term of '" + line + "'";
    auto a = evaluate(s, *ta), b = evaluate(s, *tb);
    if (!a || !b) return "'" + line + "': '" + (!a ? terms[i] : terms[i + 1]) + "' is not in the schedule";
    const double tol = 1e-3;
    bool ok = ops[i] == "=" ? std::fabs(*a - *b) < tol
              : ops[i] == "<" ? *a < *b - 1e-9
              : ops[i] == ">" ? *a > *b + 1e-9
              : ops[i] == "<=" ? *a <= *b + tol
                               : *a >= *b - tol;
    if (!ok) {
      std::ostringstream msg;
      msg << "'" << line << "': " << terms[i] << " = " << *a << ", " << terms[i + 1] << " = " << *b;
      return msg.str();
    }
  }
  return "";
}

std::string describe(const Schedule& s) {
  std::ostringstream out;
  for (const auto& b : s.behaviors) {
    out << "  " << b.id << ":";
    for (const auto& sync : b.syncs) out << " " << sync.name << "=" << sync.time;
    out << "\n";
  }
  for (const auto& w : s.warnings) out << "  warning " << toString(w.type) << " " << w.behaviorId << ": " << w.message << "\n";
  return out.str();
}

class Corpus : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(Corpus, FileDoesWhatItsHeaderStates) {
  const std::string name = GetParam();
  const std::string path = kDir + "/" + name;
  MARIONETTE_REQUIRE_FILE(path);
  const std::string text = test::readFile(path);
  const Schedule s = scheduleText(text);
  const auto sections = headerSections(text);
  const bool diverges = kDivergences.count(name) > 0;
  SCOPED_TRACE(name + "\n" + describe(s));

  if (name == "testinvalidxml.xml") {
    EXPECT_TRUE(s.failed);
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_EQ(s.warnings[0].type, WarningType::ParsingFailure);
    return;
  }
  ASSERT_FALSE(s.failed) << "block failed";

  // Removal expectations.
  std::string realization;
  for (const char* key : {"Realization", "Expected execution", "Warning"})
    if (sections.count(key))
      for (const auto& l : sections.at(key)) realization += l + " ";
  std::smatch m;
  if (std::regex_search(realization, m, std::regex(R"(for (\w+), behaviou?r should be removed)")) ||
      std::regex_search(realization, m, std::regex(R"((\w+) should be (removed|omitted))"))) {
    const std::string removed = m[1];
    EXPECT_EQ(s.find(removed), nullptr) << removed << " should have been removed";
    bool warned = false;
    for (const auto& w : s.warnings) warned |= w.behaviorId == removed;
    EXPECT_TRUE(warned) << "no warning names " << removed;
    return;  // the timing lines describe the requested (impossible) timing
  }
  for (const char* key : {"Error", "Expected timing", "Expected behavior"})
    if (sections.count(key))
      for (const auto& l : sections.at(key))
        if (std::regex_search(l, m, std::regex(R"((?:Error: )?(\w+) not found)"))) {
          bool warned = false;
          for (const auto& w : s.warnings) warned |= w.type == WarningType::NoSuchTarget && w.message.find(m[1].str()) != std::string::npos;
          EXPECT_TRUE(warned) << "expected a NO_SUCH_TARGET warning naming " << m[1];
          return;
        }

  int checked = 0, statements = 0;
  for (const char* key : {"Required timing", "Expected timing"}) {
    if (!sections.count(key)) continue;
    for (const std::string& line : sections.at(key)) {
      if (!std::regex_match(line, std::regex(R"(\s*(none|-)\s*)"))) ++statements;
      const std::string problem = checkRelation(s, line);
      if (problem.empty()) {
        ++checked;
        continue;
      }
      if (diverges) continue;  // recorded in kDivergences, checked below
      ADD_FAILURE() << problem;
    }
  }
  if (auto it = kCheckedInstead.find(name); it != kCheckedInstead.end())
    for (const std::string& line : it->second) {
      const std::string problem = checkRelation(s, line);
      EXPECT_TRUE(problem.empty()) << problem;
    }
  if (name == "testspeech_unknownsync.xml") {
    EXPECT_EQ(s.find("nod1"), nullptr);
    bool warned = false;
    for (const auto& w : s.warnings) warned |= w.type == WarningType::NoSuchTarget && w.behaviorId == "nod1";
    EXPECT_TRUE(warned);
  }
  if (name == "testbeatandnod.xml") {  // what the XML says (see kDivergences)
    EXPECT_NEAR(*s.time("beat1", "start"), 3.0, 1e-6);
    EXPECT_NEAR(*s.time("beat1", "end"), 7.0, 1e-6);
    EXPECT_NEAR(*s.time("nod1", "start"), *s.time("beat1", "strokeEnd"), 1e-6);
  }
  // A header with timing statements had at least one of them checked (or its divergence recorded).
  if (statements > 0 && !diverges) {
    EXPECT_GT(checked, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(OpenBmlParser, Corpus, ::testing::ValuesIn([] {
                           std::vector<std::string> files;
                           if (std::filesystem::exists(kDir))
                             for (const auto& e : std::filesystem::directory_iterator(kDir))
                               if (e.path().extension() == ".xml") files.push_back(e.path().filename().string());
                           std::sort(files.begin(), files.end());
                           if (files.empty()) files.push_back("MISSING-bml-corpus");  // fails loudly in the test
                           return files;
                         }()),
                         [](const auto& test) {
                           std::string n = test.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });
