#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <string>
#include <vector>

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

namespace {
std::string warningText(const Schedule& s, WarningType type, const std::string& behavior) {
  for (const auto& w : s.warnings)
    if (w.type == type && w.behaviorId == behavior) return w.message;
  return "";
}

// One repetition's stroke syncs of a head/gesture/pointing template: repetition n
// (1-based) of R, each repetition u seconds long, relative to the behavior's start.
struct Stroke {
  double start, peak, end;
};
Stroke strokeOf(int n, int reps, double u) {
  const double period = (reps * u - 0.3 * u) / reps;
  const double from = 0.1 * u + (n - 1) * period;
  return {from + period / 7, from + 2 * period / 7, from + 4 * period / 7};
}
}  // namespace

TEST(Scheduler, RepetitionsRepeatTheStrokePhaseInTimeOrder) {
  Schedule s = scheduleText("<bml id='b'><head id='nod1' lexeme='NOD' repetition='3' start='0'/>"
                            "<gesture id='g' lexeme='BEAT' start='nod1:stroke:2'/>"
                            "<gaze id='z' target='user' start='nod1:strokeEnd:1'/></bml>");
  ASSERT_TRUE(s.warnings.empty()) << s.warnings[0].message;
  const ScheduledBehavior* nod = s.find("nod1");
  ASSERT_NE(nod, nullptr);
  const std::vector<std::string> names = {"start",         "ready",    "strokeStart", "stroke",        "strokeEnd",
                                          "strokeStart:2", "stroke:2", "strokeEnd:2", "strokeStart:3", "stroke:3",
                                          "strokeEnd:3",   "relax",    "end"};
  ASSERT_EQ(nod->syncs.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(nod->syncs[k].name, names[k]);
    if (k > 0) {
      EXPECT_LT(nod->syncs[k - 1].time, nod->syncs[k].time) << names[k];
    }
  }
  EXPECT_NEAR(*nod->time("start"), 0.0, 1e-9);
  EXPECT_NEAR(*nod->time("ready"), 0.1, 1e-9);
  for (int n = 1; n <= 3; ++n) {
    const std::string suffix = n == 1 ? "" : ":" + std::to_string(n);
    const Stroke expected = strokeOf(n, 3, 1.0);
    EXPECT_NEAR(*nod->time("strokeStart" + suffix), expected.start, 1e-9) << n;
    EXPECT_NEAR(*nod->time("stroke" + suffix), expected.peak, 1e-9) << n;
    EXPECT_NEAR(*nod->time("strokeEnd" + suffix), expected.end, 1e-9) << n;
  }
  EXPECT_NEAR(*nod->time("relax"), 2.8, 1e-9);
  EXPECT_NEAR(*nod->time("end"), 3.0, 1e-9);
  EXPECT_FALSE(nod->time("stroke:4"));
  // A reference to repetition 2 gets exactly that time; ":1" is the plain name.
  EXPECT_NEAR(*s.time("g", "start"), 0.1 + 0.9 + 2 * 0.9 / 7, 1e-9);
  EXPECT_NEAR(*s.time("z", "start"), *nod->time("strokeEnd"), 1e-9);
}

TEST(Scheduler, RepetitionReferencesThatDoNotExistAreNoSuchTarget) {
  for (const char* ref : {"nod1:stroke:4", "nod1:relax:2"}) {
    Schedule s = scheduleText(std::string("<bml id='b'><head id='nod1' lexeme='NOD' repetition='3' start='0'/>"
                                          "<gesture id='g' lexeme='BEAT' start='") +
                              ref + "'/></bml>");
    SCOPED_TRACE(ref);
    EXPECT_EQ(s.find("g"), nullptr);
    EXPECT_NE(s.find("nod1"), nullptr);
    const std::string message = warningText(s, WarningType::NoSuchTarget, "g");
    EXPECT_NE(message.find("behavior 'nod1' (head) has 3 repetitions; only strokeStart, stroke and strokeEnd repeat"),
              std::string::npos)
        << message;
    EXPECT_FALSE(hasWarning(s, WarningType::ImpossibleToSchedule));  // the old "not supported yet" warning is gone
  }
  // A behavior that does not repeat at all says so.
  Schedule t = scheduleText("<bml id='b'><gaze id='z' target='user' start='0'/>"
                            "<gesture id='g' lexeme='BEAT' start='z:ready:2'/></bml>");
  EXPECT_EQ(t.find("g"), nullptr);
  EXPECT_NE(warningText(t, WarningType::NoSuchTarget, "g").find("'z' (gaze) does not repeat"), std::string::npos);
}

TEST(Scheduler, OneRepetitionKeepsTheSinglePhaseTiming) {
  // Absent, 1 and invalid values are one repetition: .1 .2 .3 .5 .8 1 of the duration.
  for (const char* attribute : {"", " repetition='1'", " repetition='0'", " repetition='2.5'", " repetition='-3'",
                                " repetition='x'"}) {
    SCOPED_TRACE(attribute);
    Schedule s = scheduleText(std::string("<bml id='b'><gesture id='g' lexeme='BEAT' start='1'") + attribute + "/></bml>");
    const ScheduledBehavior* g = s.find("g");
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(g->syncs.size(), 7u);
    const char* names[] = {"start", "ready", "strokeStart", "stroke", "strokeEnd", "relax", "end"};
    const double at[] = {0, .1, .2, .3, .5, .8, 1};
    for (std::size_t k = 0; k < 7; ++k) {
      EXPECT_EQ(g->syncs[k].name, names[k]);
      EXPECT_NEAR(g->syncs[k].time, 1.0 + 2.0 * at[k], 1e-9) << names[k];
    }
  }
  // A huge count is clamped, so it cannot exhaust memory.
  Schedule h = scheduleText("<bml id='b'><head id='n' lexeme='NOD' repetition='99999999999999999999999' start='0'/></bml>");
  ASSERT_NE(h.find("n"), nullptr);
  EXPECT_EQ(h.find("n")->syncs.size(), 4u + 3u * kMaxBehaviorRepetitions);
  EXPECT_NEAR(*h.time("n", "end"), 1.0 * kMaxBehaviorRepetitions, 1e-9);
}

TEST(Scheduler, RepeatedBehaviorsStretchProportionallyAndSyncAttributesNameTheFirstRepetition) {
  Schedule s = scheduleText("<bml id='b'><head id='n' lexeme='NOD' start='0' end='6' repetition='3'/></bml>");
  const ScheduledBehavior* n = s.find("n");
  ASSERT_NE(n, nullptr);
  ASSERT_EQ(n->syncs.size(), 13u);
  for (std::size_t k = 1; k < n->syncs.size(); ++k) {
    EXPECT_LT(n->syncs[k - 1].time, n->syncs[k].time) << n->syncs[k].name;
  }
  // The default length is 3 s: stretched to 6 s, every sync is twice its default.
  for (int r = 1; r <= 3; ++r) {
    const std::string suffix = r == 1 ? "" : ":" + std::to_string(r);
    const Stroke expected = strokeOf(r, 3, 1.0);
    EXPECT_NEAR(*n->time("strokeStart" + suffix), 2 * expected.start, 1e-9) << r;
    EXPECT_NEAR(*n->time("stroke" + suffix), 2 * expected.peak, 1e-9) << r;
    EXPECT_NEAR(*n->time("strokeEnd" + suffix), 2 * expected.end, 1e-9) << r;
  }
  EXPECT_NEAR(*n->time("relax"), 5.6, 1e-9);
  EXPECT_NEAR(*n->time("end"), 6.0, 1e-9);

  // stroke="..." constrains the first repetition; the later ones follow at default spacing.
  Schedule t = scheduleText("<bml id='b'><head id='n' lexeme='NOD' repetition='2' start='0' stroke='1'/></bml>");
  ASSERT_NE(t.find("n"), nullptr);
  EXPECT_NEAR(*t.time("n", "stroke"), 1.0, 1e-9);
  EXPECT_NEAR(*t.time("n", "stroke:2"), 1.0 + (strokeOf(2, 2, 1.0).peak - strokeOf(1, 2, 1.0).peak), 1e-9);
}

namespace {
// Another block "b0" with a speech s1 ending 2.5 s after this block's start.
SchedulerOptions withOtherBlock(std::vector<SyncRef>* asked = nullptr) {
  SchedulerOptions o;
  o.externalSync = [asked](const SyncRef& r) -> SchedulerOptions::ExternalSync {
    if (asked) asked->push_back(r);
    if (r.block == "b0" && r.behavior == "s1" && r.syncPoint == "end") return {2.5, {}};
    return {std::nullopt, "block 'b0' has no behavior '" + r.behavior + "'"};
  };
  return o;
}
}  // namespace

TEST(Scheduler, ReferencesToOtherBlocksUseTheResolver) {
  std::vector<SyncRef> asked;
  const SchedulerOptions o = withOtherBlock(&asked);
  Schedule s = scheduleText("<bml id='b1'><head id='h' lexeme='NOD' start='b0:s1:end+0.5'/>"
                            "<head id='k' lexeme='NOD' start='b1:h:end'/></bml>",
                            o);
  ASSERT_TRUE(s.warnings.empty()) << s.warnings[0].message;
  EXPECT_NEAR(*s.time("h", "start"), 3.0, 1e-9);  // the offset is added once, by the scheduler
  EXPECT_NEAR(*s.time("k", "start"), 4.0, 1e-9);  // this block's own id: resolved here, as before
  ASSERT_FALSE(asked.empty());
  for (const SyncRef& r : asked) {
    EXPECT_EQ(r.block, "b0");
    EXPECT_NEAR(r.offset, 0.5, 1e-9);
  }

  // <synchronize> and <after> go through the same resolution.
  Schedule c = scheduleText("<bml id='b1'><gesture id='g' lexeme='BEAT'/><head id='n' lexeme='NOD'/>"
                            "<constraint id='c1'><synchronize><sync ref='g:stroke'/><sync ref='b0:s1:end'/></synchronize></constraint>"
                            "<constraint id='c2'><after ref='b0:s1:end+1'><sync ref='n:start'/></after></constraint></bml>",
                            o);
  ASSERT_TRUE(c.warnings.empty()) << c.warnings[0].message;
  EXPECT_NEAR(*c.time("g", "stroke"), 2.5, 1e-9);
  EXPECT_NEAR(*c.time("g", "start"), 2.5 - 0.3 * 2.0, 1e-9);
  EXPECT_NEAR(*c.time("n", "start"), 3.5, 1e-9);
}

TEST(Scheduler, UnresolvableOtherBlockReferencesAreReported) {
  // The resolver's problem is passed on.
  Schedule s = scheduleText("<bml id='b1'><head id='h' lexeme='NOD' start='b0:ghost:end'/></bml>", withOtherBlock());
  EXPECT_EQ(s.find("h"), nullptr);
  const std::string message = warningText(s, WarningType::NoSuchTarget, "h");
  EXPECT_NE(message.find("block 'b0' has no behavior 'ghost'"), std::string::npos) << message;
  // In a constraint, the sync is left out with the same warning.
  Schedule c = scheduleText("<bml id='b1'><head id='h' lexeme='NOD'/><constraint id='c1'><synchronize>"
                            "<sync ref='h:start'/><sync ref='b0:ghost:end'/></synchronize></constraint></bml>",
                            withOtherBlock());
  EXPECT_NE(c.find("h"), nullptr);
  EXPECT_NE(warningText(c, WarningType::NoSuchTarget, "c1").find("no behavior 'ghost'"), std::string::npos);
  // Without a resolver there is nothing to ask.
  Schedule n = scheduleText("<bml id='b1'><head id='h' lexeme='NOD' start='b0:s1:end'/></bml>");
  EXPECT_EQ(n.find("h"), nullptr);
  EXPECT_NE(warningText(n, WarningType::NoSuchTarget, "h").find("block 'b0'"), std::string::npos);
  // A time before this block's start cannot be met.
  Schedule e = scheduleText("<bml id='b1'><head id='h' lexeme='NOD' start='b0:s1:end-3'/></bml>", withOtherBlock());
  EXPECT_EQ(e.find("h"), nullptr);
  EXPECT_TRUE(hasWarning(e, WarningType::ImpossibleToSchedule, "h"));
  EXPECT_FALSE(hasWarning(e, WarningType::NoSuchTarget, "h"));
}

TEST(Scheduler, DefaultDurationComesFromTheCharacter) {
  SchedulerOptions o;
  o.defaultDuration = [](const Behavior& b) -> std::optional<double> {
    const Attribute* lexeme = b.attribute("lexeme");
    if (b.type == "speech") return 10.0;  // must be ignored
    if (!lexeme) return 3.2;              // the gaze
    if (lexeme->value == "BEAT") return 3.2;
    if (lexeme->value == "NAN") return std::numeric_limits<double>::quiet_NaN();
    if (lexeme->value == "NEGATIVE") return -1.0;
    if (lexeme->value == "ZERO") return 0.0;
    if (lexeme->value == "INF") return std::numeric_limits<double>::infinity();
    return std::nullopt;
  };
  Schedule s = scheduleText("<bml id='b'><gesture id='g' lexeme='BEAT' start='0'/>"
                            "<gesture id='g2' lexeme='BEAT' start='0' repetition='2'/>"
                            "<gaze id='z' target='user' start='0'/>"
                            "<speech id='s' start='0'><text>Hello world</text></speech></bml>",
                            o);
  ASSERT_TRUE(s.warnings.empty()) << s.warnings[0].message;
  EXPECT_NEAR(*s.time("g", "end"), 3.2, 1e-9);
  EXPECT_NEAR(*s.time("g", "stroke"), 0.3 * 3.2, 1e-9);
  EXPECT_NEAR(*s.time("g2", "end"), 6.4, 1e-9);
  EXPECT_NEAR(*s.time("g2", "stroke:2"), strokeOf(2, 2, 3.2).peak, 1e-9);
  EXPECT_NEAR(*s.time("z", "ready"), 0.25 * 3.2, 1e-9);
  EXPECT_NEAR(*s.time("s", "end"), 11 * SchedulerOptions{}.speechSecondsPerCharacter, 1e-9);
  // Unusable answers keep the built-in 2 s.
  for (const char* lexeme : {"OTHER", "NAN", "NEGATIVE", "ZERO", "INF"}) {
    Schedule d = scheduleText(std::string("<bml id='b'><gesture id='g' lexeme='") + lexeme + "' start='0'/></bml>", o);
    EXPECT_NEAR(*d.time("g", "end"), 2.0, 1e-9) << lexeme;
  }
}

TEST(Scheduler, BlocksOverTheSizeLimitsFailAtOnceNamingTheLimit) {
  // Ten megabytes of behaviors, of constraint syncs, or of repetitions: the block
  // fails at once with the limit named, instead of scheduling for hours.
  std::string many = "<bml id='b'>";
  for (int i = 0; many.size() < 10u << 20; ++i) many += "<head id='h" + std::to_string(i) + "' lexeme='NOD'/>";
  many += "</bml>";
  Schedule m = scheduleText(many);
  EXPECT_TRUE(m.failed);
  EXPECT_NE(warningText(m, WarningType::ParsingFailure, "h1000").find("more than 1000 behaviors"), std::string::npos);
  std::string syncs = "<bml id='b'><head id='h' lexeme='NOD'/><constraint id='c'><synchronize>";
  while (syncs.size() < 10u << 20) syncs += "<sync ref='h:start'/>";
  syncs += "</synchronize></constraint></bml>";
  Schedule c = scheduleText(syncs);
  EXPECT_TRUE(c.failed);
  EXPECT_NE(warningText(c, WarningType::ParsingFailure, "c").find("more than 1000 sync references"), std::string::npos);
  std::string reps = "<bml id='b'>";
  for (int i = 0; i < 100; ++i) reps += "<head id='h" + std::to_string(i) + "' lexeme='NOD' repetition='100'/>";
  reps += "</bml>";
  Schedule r = scheduleText(reps);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(warningText(r, WarningType::ImpossibleToSchedule, "h65").find("more than 20000 sync points"), std::string::npos);
}

// A behavior whose own attribute ties its end to another behavior's end waits
// for that behavior to be timed, instead of pinning the shared end with its own
// default length (found with the demo's greeting: the gaze's 2 s default pinned
// the tilt's end before the tilt's start was known, and the tilt was removed).
TEST(Scheduler, ReferringBehaviorWaitsForTheOneItRefersTo) {
  Schedule s = scheduleText(
      "<bml id='b'><gaze id='look' target='x' start='0' end='tilt:end'/>"
      "<head id='nod' lexeme='NOD' start='0.5'/><head id='tilt' lexeme='TILT' start='nod:end+0.2'/></bml>");
  ASSERT_TRUE(s.warnings.empty()) << s.warnings[0].message;
  EXPECT_NEAR(*s.time("tilt", "start"), 1.7, 1e-9);
  EXPECT_NEAR(*s.time("tilt", "end"), 2.7, 1e-9);      // its own 1 s
  EXPECT_NEAR(*s.time("look", "end"), 2.7, 1e-9);      // stretched to it
  EXPECT_NEAR(*s.time("look", "ready"), 0.675, 1e-9);  // proportions kept
}

// Timings that can be met are met (issue 24, 2): when only the untimed sync points before the
// first timed one would fall before the block's start, the preparation is compressed into
// [0, first] keeping its proportions, instead of the behavior being removed.
TEST(Scheduler, APreparationThatWouldStartBeforeTheBlockIsShortenedNotDropped) {
  // The standard form with a stroke near 0: a nod's default preparation is 0.3 s.
  Schedule nod = scheduleText("<bml id='b'><head id='h' lexeme='NOD' stroke='0.1'/></bml>");
  EXPECT_TRUE(nod.warnings.empty()) << nod.warnings.front().message;
  ASSERT_NE(nod.find("h"), nullptr);
  EXPECT_DOUBLE_EQ(*nod.time("h", "start"), 0.0);
  EXPECT_NEAR(*nod.time("h", "ready"), 0.1 / 3, 1e-9);      // 0.1 of 0.3 of the preparation
  EXPECT_NEAR(*nod.time("h", "strokeStart"), 0.2 / 3, 1e-9);
  EXPECT_DOUBLE_EQ(*nod.time("h", "stroke"), 0.1);
  EXPECT_NEAR(*nod.time("h", "strokeEnd"), 0.3, 1e-9);      // after the stroke: the default spacing
  // stroke="0" relax="2": the preparation takes no time; the rest stretches between the two.
  Schedule beat = scheduleText("<bml id='b'><gesture id='g' lexeme='BEAT' stroke='0' relax='2'/></bml>");
  EXPECT_TRUE(beat.warnings.empty());
  ASSERT_NE(beat.find("g"), nullptr);
  EXPECT_DOUBLE_EQ(*beat.time("g", "start"), 0.0);
  EXPECT_DOUBLE_EQ(*beat.time("g", "ready"), 0.0);
  EXPECT_DOUBLE_EQ(*beat.time("g", "relax"), 2.0);
  EXPECT_GT(*beat.time("g", "end"), 2.0);
  // ready="0" relax="0", and a gaze with only its relax given.
  Schedule still = scheduleText("<bml id='b'><gesture id='g' lexeme='BEAT' ready='0' relax='0'/>"
                                "<gaze id='z' target='x' relax='0.5'/></bml>");
  EXPECT_TRUE(still.warnings.empty());
  ASSERT_EQ(still.behaviors.size(), 2u);
  EXPECT_DOUBLE_EQ(*still.time("g", "start"), 0.0);
  EXPECT_NEAR(*still.time("z", "ready"), 0.5 / 3, 1e-9);
  // A behavior timed by another's sync point near 0 is shortened the same way.
  Schedule chained = scheduleText("<bml id='b'><gaze id='z' target='x' start='0' end='1'/>"
                                  "<head id='h' lexeme='NOD' stroke='z:start+0.05'/></bml>");
  EXPECT_TRUE(chained.warnings.empty());
  EXPECT_DOUBLE_EQ(*chained.time("h", "start"), 0.0);
  // What truly contradicts still goes: a timed sync point before the block, or out of order.
  Schedule before = scheduleText("<bml id='b'><head id='h' lexeme='NOD' stroke='-0.1'/></bml>");
  EXPECT_EQ(before.find("h"), nullptr);
  EXPECT_TRUE(hasWarning(before, WarningType::ImpossibleToSchedule, "h"));
  Schedule backwards = scheduleText("<bml id='b'><gesture id='g' lexeme='BEAT' stroke='1' ready='2'/></bml>");
  EXPECT_EQ(backwards.find("g"), nullptr);
  // Speech keeps its own timing: it is placed, never compressed.
  Schedule speech = scheduleText("<bml id='b'><speech id='s'><text>Hello <sync id='m'/>there.</text></speech>"
                                 "<head id='h' lexeme='NOD' stroke='s:m'/></bml>");
  EXPECT_TRUE(speech.warnings.empty());
  EXPECT_GE(*speech.time("h", "start"), 0.0);
  EXPECT_DOUBLE_EQ(*speech.time("h", "stroke"), *speech.time("s", "m"));
}

// Issue 45's three schedules, from the BML 1.0 text ("Behavior ... referring to a behavior
// that is not in the block ... NO_SUCH_TARGET: the behavior is removed"; a sync point may
// coincide with another when the constraints allow it).
TEST(Scheduler, ASpeechTimedByAnInterruptThatWasLeftOutIsRemoved) {
  // An interrupt that names no block does nothing: it is left out, and the speech timed by
  // its end has nothing to start from.
  Schedule s = scheduleText(
      "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' xmlns:bmla='http://www.asap-project.org/bmla' id='b1'>"
      "<bmla:interrupt id='int1'/><speech id='s1' start='int1:end'><text>Hello.</text></speech></bml>");
  EXPECT_EQ(s.find("int1"), nullptr);
  EXPECT_EQ(s.find("s1"), nullptr);
  EXPECT_TRUE(hasWarning(s, WarningType::ParsingFailure, "int1"));
  EXPECT_TRUE(hasWarning(s, WarningType::NoSuchTarget, "s1"));
  // A prefix declared in no scope: the element is a custom behavior, left out with the same result.
  Schedule undeclared = scheduleText(
      "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' id='b1'>"
      "<bmla:interrupt id='int1' target='x'/><speech id='s1' start='int1:end'><text>Hello.</text></speech></bml>");
  EXPECT_EQ(undeclared.find("s1"), nullptr);
  EXPECT_TRUE(hasWarning(undeclared, WarningType::NoSuchTarget, "s1"));
}

TEST(Scheduler, ANamespaceDeclaredOnTheBehaviorItselfIsInScope) {
  // XML scopes xmlns:prefix to the element that declares it: AsapRealizer's tools write
  // <bmla:interrupt xmlns:bmla="..."> inside a block that does not declare bmla.
  Schedule s = scheduleText(
      "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' id='b1'>"
      "<bmla:interrupt xmlns:bmla='http://www.asap-project.org/bmla' id='int1' target='x' start='0.5'/>"
      "<speech id='s1' start='int1:end'><text>Hello.</text></speech></bml>");
  ASSERT_NE(s.find("int1"), nullptr);
  ASSERT_NE(s.find("s1"), nullptr);
  EXPECT_NEAR(*s.find("s1")->time("start"), 0.5, 1e-9);
  EXPECT_FALSE(hasWarning(s, WarningType::CustomBehaviorNotSupported));
  // A sibling outside that element does not see the declaration.
  Schedule sibling = scheduleText(
      "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' id='b1'>"
      "<bmla:interrupt xmlns:bmla='http://www.asap-project.org/bmla' id='int1' target='x'/>"
      "<bmla:activate id='act1' target='y'/></bml>");
  EXPECT_NE(sibling.find("int1"), nullptr);
  EXPECT_EQ(sibling.find("act1"), nullptr);
  EXPECT_TRUE(hasWarning(sibling, WarningType::CustomBehaviorNotSupported, "act1"));
}

TEST(Scheduler, APostureReadyAndRelaxedAtZeroIsMet) {
  // start = ready = relax = 0 satisfies start <= ready <= relax <= end: nothing is moved
  // before the block's start, in either the BML 1.0 or the SmartBody form.
  for (const char* text : {"<bml id='b2'><posture id='p1' stance='STANDING' ready='0' relax='0'/></bml>",
                           "<bml id='b2' xmlns:sbm='http://ict.usc.edu'><body id='p1' posture='Idle' ready='0' relax='0'/>"
                           "<gesture id='g' lexeme='BEAT' start='p1:relax'/></bml>"}) {
    Schedule s = scheduleText(text);
    const ScheduledBehavior* p = s.find("p1");
    ASSERT_NE(p, nullptr) << text;
    EXPECT_FALSE(hasWarning(s, WarningType::ImpossibleToSchedule)) << text;
    EXPECT_NEAR(*p->time("start"), 0.0, 1e-9) << text;
    EXPECT_NEAR(*p->time("ready"), 0.0, 1e-9) << text;
    EXPECT_NEAR(*p->time("relax"), 0.0, 1e-9) << text;
    EXPECT_GE(*p->time("end"), 0.0) << text;
  }
}
