// AnimationEventTrack: events of a clip compiled once, and the crossings of a playhead per
// frame: half-open intervals, loops (several in one step), negative speed, clamping, the
// loop point, the cap per frame. Invalid input first.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "marionette/animation/animation_events.hpp"

using namespace marionette;

namespace {

struct Crossing {
  std::string name;
  double at;
};

std::vector<Crossing> crossed(const AnimationEventTrack& track, double from, double to, WrapMode wrap = WrapMode::Loop,
                              std::uint64_t* skipped = nullptr) {
  std::vector<Crossing> out;
  const std::uint64_t s = track.forEachCrossed(from, to, wrap, [&](const AnimationEventTrack::Event& e, double at) {
    out.push_back({std::string(track.name(e)), at});
  });
  if (skipped) *skipped = s;
  return out;
}

std::vector<std::string> names(const std::vector<Crossing>& c) {
  std::vector<std::string> out;
  for (const Crossing& x : c) out.push_back(x.name);
  return out;
}

// A 1 s clip with markers a (0.25), b (0.5), c (0.75).
AnimationEventTrack abc() {
  const std::vector<ClipEvent> m = {{0.5f, "b"}, {0.25f, "a"}, {0.75f, "c"}};
  return AnimationEventTrack(1.0f, m, {}, {});
}

}  // namespace

TEST(AnimationEventTrack, InvalidMarkersAndClipsWithoutDurationGiveNoEvents) {
  const std::vector<ClipEvent> bad = {{NAN, "nan"}, {INFINITY, "inf"}, {-0.1f, "before"}, {1.5f, "after"}, {0.5f, ""}};
  EXPECT_TRUE(AnimationEventTrack(1.0f, bad, {}, {}).empty());
  const std::vector<ClipEvent> good = {{0.0f, "start"}};
  EXPECT_TRUE(AnimationEventTrack(0.0f, good, {}, {}).empty());  // a one-key clip: nothing to cross
  EXPECT_TRUE(AnimationEventTrack(NAN, good, {}, {}).empty());
  // A foot that never lifts and a contact with NaN ends: no event.
  const std::vector<ContactInterval> always = {{0.0f, 1.0f}}, broken = {{NAN, 0.5f}};
  EXPECT_TRUE(AnimationEventTrack(1.0f, {}, always, broken).empty());
  // Nothing crossed for non-finite times, a held playhead, or an empty track.
  const AnimationEventTrack t = abc();
  EXPECT_TRUE(crossed(t, NAN, 1.0).empty());
  EXPECT_TRUE(crossed(t, 0.0, INFINITY).empty());
  EXPECT_TRUE(crossed(t, 0.5, 0.5).empty());
  EXPECT_TRUE(crossed(AnimationEventTrack(), 0.0, 10.0).empty());
}

TEST(AnimationEventTrack, SortedByTimeWithEachNameStoredOnce) {
  const std::vector<ClipEvent> m = {{0.5f, "step"}, {0.1f, "step"}, {0.1f, "clap"}};
  const std::vector<ContactInterval> left = {{0.2f, 0.6f}}, right = {{0.7f, 0.1f}};
  const AnimationEventTrack t(2.0f, m, left, right);
  ASSERT_EQ(t.events().size(), 7u);
  for (std::size_t i = 1; i < t.events().size(); ++i) EXPECT_LE(t.events()[i - 1].time, t.events()[i].time);
  // 0.1 s: the markers in their given order; 0.2 s: the right foot lifts (phase 0.1);
  // 0.4 s: the left foot lands (phase 0.2).
  EXPECT_EQ(t.name(t.events()[0]), "step");
  EXPECT_EQ(t.name(t.events()[1]), "clap");
  EXPECT_EQ(t.events()[1].kind, AnimationEventKind::Marker);
  EXPECT_EQ(t.name(t.events()[2]), "right_foot_up");
  EXPECT_EQ(t.events()[2].kind, AnimationEventKind::FootUp);
  EXPECT_EQ(t.events()[2].side, FootSide::Right);
  EXPECT_EQ(t.name(t.events()[3]), "left_foot_down");
  EXPECT_FLOAT_EQ(t.events()[3].time, 0.4f);
  EXPECT_EQ(t.events()[3].kind, AnimationEventKind::FootDown);
  EXPECT_EQ(t.events()[3].side, FootSide::Left);
  EXPECT_EQ(t.name(t.events()[6]), "right_foot_down");
  EXPECT_FLOAT_EQ(t.events()[6].time, 1.4f);
  // At equal times the feet come first.
  const std::vector<ClipEvent> same = {{0.4f, "marker"}};
  const AnimationEventTrack u(2.0f, same, left, {});
  EXPECT_EQ(u.name(u.events()[0]), "left_foot_down");
  EXPECT_EQ(u.name(u.events()[1]), "marker");
  EXPECT_EQ(t.names().size(), 6u);  // step once, clap, and four foot names
}

TEST(AnimationEventTrack, FramesCrossEachEventOnceWhateverTheirCuts) {
  const AnimationEventTrack t = abc();
  // Frames ending exactly on events (0.25 s steps), odd steps, and tiny ones: 3 loops.
  for (const double dt : {0.25, 0.125, 1.0 / 60.0, 0.3, 0.07, 1e-3}) {
    std::vector<Crossing> all;
    double time = 0.0;
    while (time < 3.0 - 1e-12) {
      const double next = std::min(time + dt, 3.0);
      for (const Crossing& c : crossed(t, time, next)) all.push_back(c);
      time = next;
    }
    ASSERT_EQ(all.size(), 9u) << "dt " << dt;
    for (std::size_t i = 0; i < all.size(); ++i) {
      EXPECT_EQ(all[i].name, std::string(1, static_cast<char>('a' + i % 3))) << "dt " << dt;
      EXPECT_NEAR(all[i].at, static_cast<double>(i / 3) + 0.25 * static_cast<double>(i % 3 + 1), 1e-12);
    }
  }
  // Half-open: an event at the start is crossed, one at the end is not.
  EXPECT_EQ(names(crossed(t, 0.25, 0.5)), std::vector<std::string>{"a"});
  EXPECT_EQ(names(crossed(t, 0.5, 0.75)), std::vector<std::string>{"b"});
}

TEST(AnimationEventTrack, SeveralLoopsInOneStepInOrder) {
  const AnimationEventTrack t = abc();
  const std::vector<Crossing> c = crossed(t, 0.3, 3.6);  // b c | a b c | a b c | a b
  EXPECT_EQ(names(c), (std::vector<std::string>{"b", "c", "a", "b", "c", "a", "b", "c", "a", "b"}));
  for (std::size_t i = 1; i < c.size(); ++i) EXPECT_GT(c[i].at, c[i - 1].at);
  EXPECT_DOUBLE_EQ(c.back().at, 3.5);
  // Far from zero (10^7 s of play) and below it.
  EXPECT_EQ(crossed(t, 1e7, 1e7 + 2.0).size(), 6u);
  EXPECT_EQ(names(crossed(t, -1.0, 0.0)), (std::vector<std::string>{"a", "b", "c"}));
}

TEST(AnimationEventTrack, BackwardsCrossesInReverseWithTheSameHalfOpenRule) {
  const AnimationEventTrack t = abc();
  const std::vector<Crossing> c = crossed(t, 2.6, 0.4);  // b a | c b a | c b
  EXPECT_EQ(names(c), (std::vector<std::string>{"b", "a", "c", "b", "a", "c", "b"}));
  for (std::size_t i = 1; i < c.size(); ++i) EXPECT_LT(c[i].at, c[i - 1].at);
  // (to, from]: the start is crossed, the end is not.
  EXPECT_EQ(names(crossed(t, 0.5, 0.25)), std::vector<std::string>{"b"});
  // Forward to an event, then back: it is crossed once (leaving it), then again only
  // when the playhead passes it anew.
  EXPECT_TRUE(crossed(t, 0.4, 0.5).empty());
  EXPECT_EQ(names(crossed(t, 0.5, 0.45)), std::vector<std::string>{"b"});
  EXPECT_TRUE(crossed(t, 0.45, 0.5).empty());
  // Frames of negative speed cover the time once, each event once.
  std::vector<Crossing> all;
  for (double time = 3.0; time > 1e-12; time -= 0.125)
    for (const Crossing& x : crossed(t, time, time - 0.125)) all.push_back(x);
  EXPECT_EQ(all.size(), 9u);
}

TEST(AnimationEventTrack, TheLoopPointIsCrossedOncePerLoop) {
  const std::vector<ClipEvent> m = {{1.0f, "end"}, {0.0f, "start"}, {0.5f, "mid"}};
  const AnimationEventTrack t(1.0f, m, {}, {});
  // The end and the start are one instant of a loop: the end first (it closes the cycle before).
  EXPECT_EQ(names(crossed(t, 0.0, 2.0)), (std::vector<std::string>{"end", "start", "mid", "end", "start", "mid"}));
  EXPECT_EQ(names(crossed(t, 0.9, 1.1)), (std::vector<std::string>{"end", "start"}));
  EXPECT_EQ(names(crossed(t, 1.1, 0.9)), (std::vector<std::string>{"start", "end"}));
  EXPECT_TRUE(crossed(t, 0.9, 1.0).empty());
}

TEST(AnimationEventTrack, ClampCrossesTheEndsItArrivesAt) {
  const std::vector<ClipEvent> m = {{1.0f, "end"}, {0.0f, "start"}, {0.5f, "mid"}};
  const AnimationEventTrack t(1.0f, m, {}, {});
  EXPECT_EQ(names(crossed(t, 0.0, 0.6, WrapMode::Clamp)), (std::vector<std::string>{"start", "mid"}));
  EXPECT_EQ(names(crossed(t, 0.6, 5.0, WrapMode::Clamp)), std::vector<std::string>{"end"});  // arrives at the end
  EXPECT_TRUE(crossed(t, 1.0, 1.0, WrapMode::Clamp).empty());                                // held there
  EXPECT_TRUE(crossed(t, 1.0, 9.0, WrapMode::Clamp).empty());                                // still held
  EXPECT_EQ(names(crossed(t, 1.0, -3.0, WrapMode::Clamp)), (std::vector<std::string>{"end", "mid", "start"}));
}

TEST(AnimationEventTrack, AtMostSixtyFourPassesPerStep) {
  const AnimationEventTrack t = abc();
  std::uint64_t skipped = 0;
  const std::vector<Crossing> c = crossed(t, 0.0, 3600.0, WrapMode::Loop, &skipped);
  EXPECT_EQ(c.size(), 3u * AnimationEventTrack::kMaxPassesPerFrame);
  EXPECT_EQ(skipped, 3600u - AnimationEventTrack::kMaxPassesPerFrame);  // 3600 cycles touched
  EXPECT_DOUBLE_EQ(c.front().at, 0.25);  // the first passes, in order
  EXPECT_EQ(crossed(t, 0.0, 64.0, WrapMode::Loop, &skipped).size(), 192u);
  EXPECT_EQ(skipped, 0u);
  // Backwards too: the first pass touches cycle 0 only at its start (no event there), then
  // 63 whole passes.
  EXPECT_EQ(crossed(t, 0.0, -1000.0, WrapMode::Loop, &skipped).size(), 3u * (AnimationEventTrack::kMaxPassesPerFrame - 1));
  EXPECT_EQ(skipped, 1001u - AnimationEventTrack::kMaxPassesPerFrame);
}
