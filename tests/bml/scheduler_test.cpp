#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "marionette/bml/scheduler.hpp"

using namespace marionette::bml;

namespace {
bool hasWarning(const Schedule& s, WarningType type, const std::string& behavior = "") {
  for (const auto& w : s.warnings)
    if (w.type == type && (behavior.empty() || w.behaviorId == behavior)) return true;
  return false;
}
}  // namespace

TEST(Scheduler, ContradictionsAreImpossibleToSchedule) {
  Schedule s = scheduleText("<bml id='b'><head id='a' lexeme='NOD' start='c:start+1'/>"
                            "<head id='c' lexeme='NOD' start='a:start+1'/></bml>");
  EXPECT_FALSE(s.failed);
  // The behavior whose constraint closes the cycle goes; the other, timed only
  // relative to it, cannot be timed as asked and goes too. Each with a warning.
  EXPECT_TRUE(hasWarning(s, WarningType::ImpossibleToSchedule, "c"));
  EXPECT_TRUE(hasWarning(s, WarningType::NoSuchTarget, "a"));
  EXPECT_TRUE(s.behaviors.empty());
}

TEST(Scheduler, EndBeforeStartRemovesTheBehaviorWithAWarning) {
  Schedule s = scheduleText("<bml id='b'><head id='n' lexeme='NOD' start='2' end='0'/><gaze id='g' target='x'/></bml>");
  EXPECT_EQ(s.find("n"), nullptr);
  EXPECT_NE(s.find("g"), nullptr);
  EXPECT_TRUE(hasWarning(s, WarningType::ImpossibleToSchedule, "n"));
  EXPECT_FALSE(s.failed);
}

TEST(Scheduler, RequiredFailureFailsTheBlock) {
  Schedule s = scheduleText("<bml id='b'><required><head id='n' lexeme='NOD' start='2' end='0'/></required></bml>");
  EXPECT_TRUE(s.failed);
  bool fatal = false;
  for (const auto& w : s.warnings) fatal |= w.fatal;
  EXPECT_TRUE(fatal);
}

TEST(Scheduler, UnknownTargetsAreNoSuchTarget) {
  Schedule s = scheduleText("<bml id='b'><head id='n' lexeme='NOD' start='ghost:end'/></bml>");
  EXPECT_TRUE(hasWarning(s, WarningType::NoSuchTarget, "n"));
  EXPECT_EQ(s.find("n"), nullptr);
  Schedule t = scheduleText("<bml id='b'><head id='n' lexeme='NOD' start='other:x:end'/></bml>");
  EXPECT_TRUE(hasWarning(t, WarningType::NoSuchTarget, "n"));
  Schedule u = scheduleText("<bml id='b'><head id='n' lexeme='NOD' start='n:start+'/></bml>");
  EXPECT_TRUE(hasWarning(u, WarningType::ParsingFailure, "n"));
}

TEST(Scheduler, TwoAnchorsStretchAStretchableBehavior) {
  Schedule s = scheduleText("<bml id='b'><gesture id='g' lexeme='BEAT' start='1' end='5'/></bml>");
  ASSERT_NE(s.find("g"), nullptr);
  EXPECT_DOUBLE_EQ(*s.time("g", "start"), 1.0);
  EXPECT_DOUBLE_EQ(*s.time("g", "end"), 5.0);
  EXPECT_NEAR(*s.time("g", "stroke"), 1.0 + 0.3 * 4.0, 1e-9);  // proportional inside
  // Speech does not stretch: an end it cannot reach removes it.
  Schedule t = scheduleText("<bml id='b'><speech id='s' end='0.1'><text>Welcome ladies and gentlemen!</text></speech></bml>");
  EXPECT_EQ(t.find("s"), nullptr);
  EXPECT_TRUE(hasWarning(t, WarningType::ImpossibleToSchedule, "s"));
}

TEST(Scheduler, FreeGroupsStartAtZeroAndAfterMovesThem) {
  Schedule s = scheduleText("<bml id='b'><head id='h' lexeme='NOD' start='g:start-1'/><gesture id='g' lexeme='BEAT'/></bml>");
  EXPECT_DOUBLE_EQ(*s.time("h", "start"), 0.0);
  EXPECT_DOUBLE_EQ(*s.time("g", "start"), 1.0);
  Schedule t = scheduleText(
      "<bml id='b'><head id='h' lexeme='NOD' start='3'/><gesture id='g' lexeme='BEAT'/>"
      "<constraint><after ref='h:end'><sync ref='g:start'/></after></constraint></bml>");
  EXPECT_GE(*t.time("g", "start"), *t.time("h", "end") - 1e-9);
  // An anchored behavior that violates before/after is kept, with a warning.
  Schedule u = scheduleText(
      "<bml id='b'><head id='h' lexeme='NOD' start='3'/><gesture id='g' lexeme='BEAT' start='0'/>"
      "<constraint><after ref='h:end'><sync ref='g:start'/></after></constraint></bml>");
  EXPECT_TRUE(hasWarning(u, WarningType::ImpossibleToSchedule));
  EXPECT_NE(u.find("g"), nullptr);
}

TEST(Scheduler, DeepNestingAndHugeBlocksFailCleanlyAndQuickly) {
  std::string deep = "<bml id='b'>";
  for (int i = 0; i < 100000; ++i) deep += "<required>";
  for (int i = 0; i < 100000; ++i) deep += "</required>";
  deep += "</bml>";
  Schedule s = scheduleText(deep);  // must not overflow the stack
  EXPECT_TRUE(hasWarning(s, WarningType::ParsingFailure));

  std::string huge = "<bml id='b'><speech id='s'><text>";
  while (huge.size() < 10u << 20) huge += "and so on and so forth ";
  huge += "</text></speech><head id='h' lexeme='NOD' start='s:end'/></bml>";
  const auto start = std::chrono::steady_clock::now();
  Schedule h = scheduleText(huge);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_NE(h.find("h"), nullptr);
  EXPECT_GT(*h.time("h", "start"), 1000.0);  // ten megabytes of speech take a while
  EXPECT_LT(seconds, 30.0);                   // a bound against runaway work, not a speed goal
}

TEST(Scheduler, RigidSpeechIsPlacedBeforeStretchingWhatDependsOnIt) {
  // A gaze anchored at 0 whose end follows the speech: the speech must not be
  // pushed before the block start by the gaze's default length; the gaze stretches.
  Schedule s = scheduleText(
      "<bml id='b'><speech id='s1'><text>Hello there, <sync id='w1'/>nice to see you again.</text></speech>"
      "<gaze id='z1' target='user' start='0' end='s1:end+0.5'/><gesture id='g1' lexeme='BEAT' stroke='s1:w1'/></bml>");
  ASSERT_TRUE(s.warnings.empty()) << s.warnings[0].message;
  EXPECT_DOUBLE_EQ(*s.time("s1", "start"), 0.0);
  EXPECT_DOUBLE_EQ(*s.time("z1", "start"), 0.0);
  EXPECT_NEAR(*s.time("z1", "end"), *s.time("s1", "end") + 0.5, 1e-9);
  EXPECT_NEAR(*s.time("g1", "stroke"), *s.time("s1", "w1"), 1e-9);
}
