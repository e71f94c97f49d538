// Reaching on real characters through their shipped profiles: RobotExpressive (playing
// Idle; its arms end at the palm joint) and Godette (VRM, no clips: the T-pose). The palm
// reaches targets in front, to the side, low, high and across, holds them until relax and is
// back in the pose by end; a target beyond the arm gives a warning and the palm on the line
// shoulder to target at about the arm's reach; extreme timings and targets (ready at the
// start, zero and tiny durations, the shoulder itself, behind the back) never jump or NaN;
// a NaN target is refused with a message. The figures are printed for docs/controllers.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

struct Case {
  const char* asset;
  const char* profile;
};
const Case kRobot{"characters/RobotExpressive.glb", "RobotExpressive.json"};
const Case kGodette{"characters/Godette_vrm_v4.vrm", "Godette_vrm_v4.json"};

glm::vec3 worldOf(const Character& c, int joint) {
  return glm::vec3(c.transformBuffer().worldMatrix() * c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)][3]);
}

// The character as it stands: its frame from the shoulders, its height, its arms' reach.
struct Body {
  std::shared_ptr<Rig> rig;
  glm::vec3 left{1, 0, 0}, up{0, 1, 0}, forward{0, 0, 1};
  glm::vec3 shoulder[2];
  float height = 0.0f, arm = 0.0f;  // arm: shoulder to elbow to palm (the palm from a probe reach)
};

Body measure(const Case& k) {
  Body b;
  b.rig = loadRigWithProfile(sharedAsset(k.asset), k.profile);
  if (!b.rig) return b;
  const RigJoints& j = b.rig->joints();
  Scene probe;
  Character* c = probe.addCharacter("probe", b.rig);
  probe.update(0.0);
  b.height = worldOf(*c, j.head).y;
  b.shoulder[0] = worldOf(*c, j.leftArm.upper);
  b.shoulder[1] = worldOf(*c, j.rightArm.upper);
  b.left = b.shoulder[0] - b.shoulder[1];
  b.left.y = 0.0f;
  b.left = glm::normalize(b.left);
  b.forward = glm::cross(b.left, b.up);
  b.arm = glm::length(worldOf(*c, j.rightArm.lower) - b.shoulder[1]);
  // The elbow to the palm, as the controller finds the palm (a reach that has not moved yet).
  BehaviorRequest r{.id = "probe", .kind = BehaviorKind::Reach, .syncs = {{"start", 10.0}, {"end", 11.0}},
                    .parameters = ReachParameters{BehaviorTarget::at(b.shoulder[1] - b.left), PointingArms::Right}};
  (void)c->addBehavior(r);
  const ReachState* st = c->behaviors().find("probe")->as<ReachState>();
  const auto models = c->transformBuffer().modelMatrices();
  if (st && st->limb[1].end >= 0)
    b.arm += glm::length(glm::vec3(models[static_cast<std::size_t>(st->limb[1].end)] * glm::vec4(st->palmInEnd[1], 1.0f)) -
                         glm::vec3(models[static_cast<std::size_t>(j.rightArm.lower)][3]));
  return b;
}

// The palm of the request's reaching arm, world space, from the transform buffer.
glm::vec3 palmWorld(const Character& c, const std::string& id) {
  const ReachState* st = c.behaviors().find(id)->as<ReachState>();
  const int side = std::max(st->side, 0);
  const glm::mat4 end = c.transformBuffer().modelMatrices()[static_cast<std::size_t>(st->limb[side].end)];
  return glm::vec3(c.transformBuffer().worldMatrix() * end * glm::vec4(st->palmInEnd[side], 1.0f));
}

glm::quat rotationOf(const glm::mat4& m) {
  return glm::normalize(glm::quat_cast(glm::mat3(glm::normalize(glm::vec3(m[0])), glm::normalize(glm::vec3(m[1])),
                                                 glm::normalize(glm::vec3(m[2])))));
}

// What the reach adds to each joint's model-space rotation (against the same character not
// reaching: the idle clip turns joints too), and the largest change of it between frames.
void reachTurns(std::span<const glm::mat4> reaching, std::span<const glm::mat4> plain, std::vector<glm::quat>& out) {
  out.resize(reaching.size());
  for (std::size_t i = 0; i < reaching.size(); ++i) out[i] = rotationOf(reaching[i]) * glm::inverse(rotationOf(plain[i]));
}
float largestTurn(const std::vector<glm::quat>& a, const std::vector<glm::quat>& b) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    worst = std::max(worst, 2.0f * std::acos(std::min(1.0f, std::fabs(glm::dot(a[i], b[i])))));
  return worst;
}

struct Run {
  std::string message;
  bool realized = false;
  float meanError = 0.0f, worstError = 0.0f, drift = 0.0f, worstTurn = 0.0f, backAtEnd = 0.0f;
  float lineOff = 0.0f, palmDistance = 0.0f;  // for unreachable targets: off the shoulder line, distance
  float leastBend = 10.0f;                   // the elbow's bend while held, radians
  float elbowUp = -1.0f;  // the most the elbow rose above the line shoulder to palm (its unit offset's up part)
  int side = -1;
  bool finite = true;
};

// One reach at 60 Hz from 0 to `until`, with the idle clip (if any) under it; compared with
// the same character not reaching for where the arm ends.
Run reachFor(const Body& b, const glm::vec3& target, std::vector<BehaviorSync> syncs, double until,
             PointingArms arm = PointingArms::Nearest) {
  Run out;
  Scene scene;
  Character* c = scene.addCharacter("c", b.rig);
  Scene plain;
  Character* p = plain.addCharacter("p", b.rig);
  for (Character* x : {c, p})
    if (!b.rig->profile().idle.empty()) x->play(0, b.rig->profile().idle);
  BehaviorRequest r{.id = "r", .kind = BehaviorKind::Reach, .syncs = std::move(syncs),
                    .parameters = ReachParameters{BehaviorTarget::at(target), arm}};
  const BehaviorResult added = c->addBehavior(r);
  out.realized = added.realized;
  out.message = added.message;
  if (!added.realized) return out;
  // The entry is looked up again each frame: the timeline drops it once it has ended (a
  // reference kept across updates would dangle).
  const BehaviorTimeline::Entry* entry = c->behaviors().find("r");
  if (!entry) {
    ADD_FAILURE() << "the realized reach is not on the timeline";
    return out;
  }
  const double ready = entry->blendInEnd, relax = entry->blendOutStart, end = entry->request.end();
  int ends[2] = {-1, -1};  // each arm's end joint, for after the entry is dropped
  if (const ReachState* first = entry->as<ReachState>()) ends[0] = first->limb[0].end, ends[1] = first->limb[1].end;
  const RigJoints& j = b.rig->joints();
  std::vector<glm::quat> last, now;
  glm::vec3 held(0.0f);
  bool holding = false;
  int n = 0;
  const int frames = static_cast<int>(std::lround(until * 60.0));
  for (int f = 1; f <= frames; ++f) {
    scene.update(1.0 / 60.0);
    plain.update(1.0 / 60.0);
    const double t = f / 60.0;
    const auto models = c->transformBuffer().modelMatrices();
    for (const glm::mat4& m : models)
      out.finite &= std::isfinite(m[3].x + m[3].y + m[3].z + m[0].x + m[1].y + m[2].z + m[0].z);
    reachTurns(models, p->transformBuffer().modelMatrices(), now);
    if (!last.empty()) out.worstTurn = std::max(out.worstTurn, largestTurn(last, now));
    std::swap(last, now);
    const BehaviorTimeline::Entry* current = c->behaviors().find("r");
    const ReachState* st = current ? current->as<ReachState>() : nullptr;
    if (st) out.side = st->side;
    if (st && t > ready + 1e-9 && t < relax - 1e-9 && end > 0.0) {
      const glm::vec3 palm = palmWorld(*c, "r");
      const float err = glm::length(palm - target);
      out.meanError += err;
      out.worstError = std::max(out.worstError, err);
      ++n;
      if (!holding) held = palm, holding = true;
      out.drift = std::max(out.drift, glm::length(palm - held));
      const int side = st->side;
      const LimbIk& limb = st->limb[side];
      const glm::vec3 shoulder = worldOf(*c, limb.upper), elbow = worldOf(*c, limb.lower), wrist = worldOf(*c, limb.end);
      out.leastBend = std::min(out.leastBend, std::acos(std::clamp(glm::dot(glm::normalize(elbow - shoulder),
                                                                            glm::normalize(wrist - elbow)), -1.0f, 1.0f)));
      const glm::vec3 line = glm::normalize(palm - shoulder), across = (elbow - shoulder) - line * glm::dot(elbow - shoulder, line);
      if (glm::length(across) > 1e-6f) out.elbowUp = std::max(out.elbowUp, glm::normalize(across).y);
      const glm::vec3 d = glm::normalize(target - shoulder);
      const glm::vec3 off = (palm - shoulder) - d * glm::dot(palm - shoulder, d);
      out.lineOff = std::max(out.lineOff, glm::length(off));
      out.palmDistance = glm::length(palm - shoulder);
    }
    if (t >= end + 1.0 / 60.0 && end > 0.0) {
      const int endJoint = ends[std::max(out.side, 0)];
      out.backAtEnd = std::max(out.backAtEnd, glm::length(worldOf(*c, endJoint) - worldOf(*p, endJoint)));
    }
  }
  out.meanError = n ? out.meanError / static_cast<float>(n) : std::numeric_limits<float>::infinity();
  (void)j;
  return out;
}

// The character's frame: x left, y up, z forward, from the right (or left) shoulder, in arm lengths.
glm::vec3 around(const Body& b, int side, const glm::vec3& at) {
  return b.shoulder[side] + (at.x * b.left + at.y * b.up + at.z * b.forward) * b.arm;
}

void checkReaching(const Case& k) {
  MARIONETTE_REQUIRE_FILE(sharedAsset(k.asset));
  const Body b = measure(k);
  ASSERT_TRUE(b.rig) << k.asset;
  ASSERT_GT(b.arm, 0.05f * b.height) << k.asset;
  // Reachable targets (arm lengths from the right shoulder): ahead, low ahead, out to the
  // side, high, across the chest (nearer the left shoulder: the left arm takes it).
  struct Target {
    glm::vec3 at;
    int side;
  };
  const Target targets[] = {{{0.0f, -0.2f, 0.75f}, 1}, {{0.1f, -0.6f, 0.5f}, 1}, {{-0.7f, -0.1f, 0.3f}, 1},
                            {{-0.1f, 0.6f, 0.5f}, 1},  {{0.9f, -0.3f, 0.5f}, 0}};
  float sum = 0.0f, worst = 0.0f, drift = 0.0f, turn = 0.0f, back = 0.0f, bend = 10.0f;
  for (const Target& t : targets) {
    const glm::vec3 target = around(b, 1, t.at);
    const Run run = reachFor(b, target, {{"start", 0.0}, {"ready", 0.6}, {"stroke", 0.6}, {"relax", 1.6}, {"end", 2.2}}, 2.5);
    SCOPED_TRACE(std::string(k.asset) + " target " + describeTarget(BehaviorTarget::at(target)));
    ASSERT_TRUE(run.realized) << run.message;
    EXPECT_EQ(run.message, "");
    EXPECT_TRUE(run.finite);
    EXPECT_EQ(run.side, t.side);
    EXPECT_LT(run.worstError, 0.005f * b.arm);  // half a percent of the arm: under 3 mm on Godette
    EXPECT_LT(run.drift, 0.005f * b.arm);       // the target holds still: so does the palm
    EXPECT_LT(run.backAtEnd, 1e-4f * b.height);  // back in the pose by end
    if (t.at.y < 0.0f) EXPECT_LT(run.elbowUp, -0.3f) << "the elbow does not hang down";  // for the raised arm: out
    sum += run.meanError, worst = std::max(worst, run.worstError), drift = std::max(drift, run.drift);
    turn = std::max(turn, run.worstTurn), back = std::max(back, run.backAtEnd), bend = std::min(bend, run.leastBend);
  }
  EXPECT_GE(bend, 0.15f) << "the elbow straightened past its least bend";
  EXPECT_LT(turn, 0.12f) << "a joint turned more than 7 degrees in one frame at 60 Hz";
  std::printf("%s: arm %.3f m; palm error mean %.2f mm, worst %.2f mm; hold drift %.2f mm; back at end %.4f mm; "
              "least elbow bend %.1f deg; largest joint turn per frame %.2f deg (60 Hz)\n",
              k.asset, static_cast<double>(b.arm), static_cast<double>(sum / 5.0f * 1000.0f),
              static_cast<double>(worst * 1000.0f), static_cast<double>(drift * 1000.0f), static_cast<double>(back * 1000.0f),
              static_cast<double>(glm::degrees(bend)), static_cast<double>(glm::degrees(turn)));
}

void checkUnreachable(const Case& k) {
  MARIONETTE_REQUIRE_FILE(sharedAsset(k.asset));
  const Body b = measure(k);
  ASSERT_TRUE(b.rig) << k.asset;
  const glm::vec3 target = around(b, 1, {-1.2f, 0.3f, 2.5f});  // three arm lengths out
  const Run run = reachFor(b, target, {{"start", 0.0}, {"ready", 0.6}, {"relax", 1.6}, {"end", 2.2}}, 2.5);
  ASSERT_TRUE(run.realized) << run.message;
  EXPECT_NE(run.message.find("reach 'r': the target is "), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("m from the right shoulder but the arm reaches"), std::string::npos) << run.message;
  EXPECT_NE(run.message.find("does not lean or step"), std::string::npos) << run.message;
  EXPECT_TRUE(run.finite);
  EXPECT_LT(run.lineOff, 0.01f * b.arm) << k.asset << ": the palm left the line shoulder to target";
  EXPECT_GT(run.palmDistance, 0.93f * b.arm) << k.asset;
  EXPECT_LT(run.palmDistance, 1.0f * b.arm) << k.asset;
  EXPECT_GE(run.leastBend, 0.15f) << k.asset << ": locked straight";
  EXPECT_LT(run.backAtEnd, 1e-4f * b.height);
  std::printf("%s: unreachable target: palm %.1f mm off the shoulder line, at %.3f of the arm's length; elbow bend %.1f deg\n",
              k.asset, static_cast<double>(run.lineOff * 1000.0f), static_cast<double>(run.palmDistance / b.arm),
              static_cast<double>(glm::degrees(run.leastBend)));
}

void checkExtremes(const Case& k) {
  MARIONETTE_REQUIRE_FILE(sharedAsset(k.asset));
  const Body b = measure(k);
  ASSERT_TRUE(b.rig) << k.asset;
  const glm::vec3 ahead = around(b, 1, {0.0f, -0.2f, 0.7f});
  struct Timing {
    std::vector<BehaviorSync> syncs;
    const char* note;  // what the message says, "" for none
  };
  const Timing timings[] = {
      {{{"start", 0.0}, {"ready", 0.0}, {"relax", 1.0}, {"end", 1.5}}, "it arrives at 0.25 s"},
      {{{"start", 0.0}, {"ready", 0.5}, {"relax", 1.0}, {"end", 1.0}}, "it leaves at 0.75 s"},
      {{{"start", 0.0}, {"ready", 0.0}, {"relax", 0.0}, {"end", 0.0}}, "the hand does not move"},
      {{{"start", 0.0}, {"ready", 0.01}, {"relax", 0.01}, {"end", 0.02}}, "only part of the way"},
      {{{"start", 0.2}, {"ready", 0.2}, {"relax", 0.2}, {"end", 0.2}}, "the hand does not move"},
  };
  // A smoothstep over T seconds turns a joint by a half-turn at most 1.5 pi / (60 T) per
  // frame at 60 Hz; a quarter more for the idle clip under it. The hand takes at least
  // ReachSettings::minMoveSeconds (0.25 s).
  auto fastest = [](float seconds) { return 1.25f * 1.5f * 3.1416f / (seconds * 60.0f); };
  float turn = 0.0f;
  for (const Timing& t : timings) {
    const Run run = reachFor(b, ahead, t.syncs, 2.0);
    SCOPED_TRACE(std::string(k.asset) + ": " + t.note);
    ASSERT_TRUE(run.realized) << run.message;
    EXPECT_NE(run.message.find(t.note), std::string::npos) << run.message;
    EXPECT_TRUE(run.finite);
    EXPECT_LT(run.worstTurn, fastest(0.25f));
    EXPECT_LT(run.backAtEnd, 1e-4f * b.height);
    turn = std::max(turn, run.worstTurn);
  }
  // Targets at the shoulder itself, behind the back, straight down, far behind and across.
  const glm::vec3 odd[] = {b.shoulder[1], around(b, 1, {0.0f, 0.0f, -0.6f}), around(b, 1, {0.0f, -0.9f, 0.0f}),
                           around(b, 1, {2.0f, 0.0f, -5.0f}), b.shoulder[1] + 1e-5f * b.left};
  for (const glm::vec3& target : odd) {
    const Run run = reachFor(b, target, {{"start", 0.0}, {"ready", 0.5}, {"relax", 1.0}, {"end", 1.5}}, 2.0, PointingArms::Right);
    SCOPED_TRACE(std::string(k.asset) + ": target " + describeTarget(BehaviorTarget::at(target)));
    ASSERT_TRUE(run.realized) << run.message;
    EXPECT_TRUE(run.finite);
    EXPECT_LT(run.worstTurn, fastest(0.5f));  // half a second to get there, from hanging to folded
    EXPECT_LT(run.backAtEnd, 1e-4f * b.height);
    EXPECT_GE(run.leastBend, 0.15f);
    turn = std::max(turn, run.worstTurn);
  }
  std::printf("%s: extreme timings and targets: largest joint turn per frame %.2f deg (60 Hz)\n", k.asset,
              static_cast<double>(glm::degrees(turn)));
  // Not finite: refused, naming the behavior and the target; nothing moves.
  for (const float bad : {std::nanf(""), std::numeric_limits<float>::infinity()}) {
    const Run run = reachFor(b, {bad, 1.0f, 0.5f}, {{"start", 0.0}, {"end", 1.0}}, 0.1);
    EXPECT_FALSE(run.realized);
    EXPECT_NE(run.message.find("reach target"), std::string::npos) << run.message;
    EXPECT_NE(run.message.find("is not finite"), std::string::npos) << run.message;
  }
}

}  // namespace

TEST(ReachOnRealCharacters, RobotExpressiveReachesHoldsAndReturns) { checkReaching(kRobot); }
TEST(ReachOnRealCharacters, GodetteReachesHoldsAndReturns) { checkReaching(kGodette); }
TEST(ReachOnRealCharacters, RobotExpressiveStopsShortOfAnUnreachableTargetWithAWarning) { checkUnreachable(kRobot); }
TEST(ReachOnRealCharacters, GodetteStopsShortOfAnUnreachableTargetWithAWarning) { checkUnreachable(kGodette); }
TEST(ReachOnRealCharacters, RobotExpressiveNeverJumpsAtExtremeTimingsAndTargets) { checkExtremes(kRobot); }
TEST(ReachOnRealCharacters, GodetteNeverJumpsAtExtremeTimingsAndTargets) { checkExtremes(kGodette); }
