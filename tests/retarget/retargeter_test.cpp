// Retargeting on hand-made humanoids whose right answer is known: same bone
// lengths and directions must give the same joint positions, whatever the
// joint frames, rest shapes, scale, mirroring or spine length.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/retarget/retargeter.hpp"
#include "synthetic_humanoid.hpp"

using namespace marionette;
using namespace marionette::retarget;
using marionette::test::TestHumanoid;
using marionette::test::HumanoidSpec;
using marionette::test::makeHumanoid;

namespace {

// A pose: every joint turned from rest by a random rotation of up to `amount`
// radians, the hips moved by `hipsMove`.
std::vector<Transform> randomPose(const Skeleton& s, unsigned seed, float amount = 0.8f,
                                  glm::vec3 hipsMove = glm::vec3(0.3f, -0.1f, 0.5f)) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Transform> pose = s.restPose;
  for (Transform& t : pose) {
    const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
    t.rotation = t.rotation * glm::angleAxis(amount * u(rng), axis);
  }
  pose[0].translation += hipsMove;
  return pose;
}

std::vector<glm::vec3> positions(const Skeleton& s, const std::vector<Transform>& local) {
  std::vector<glm::mat4> model(s.jointCount());
  localToModel(s, local, model);
  std::vector<glm::vec3> p;
  for (const glm::mat4& m : model) p.push_back(glm::vec3(m[3]));
  return p;
}

// Joints that both humanoids have (same construction order but spines may differ):
// compared through the map, by canonical bone. B is A scaled by scaleB (and
// turned by turnB); the error is relative to B's size (B's scale over A's).
float worstBoneError(const TestHumanoid& a, const std::vector<glm::vec3>& pa, const TestHumanoid& b,
                     const std::vector<glm::vec3>& pb, float scaleB, const glm::quat& turnB = glm::quat(1, 0, 0, 0),
                     float sizeB = 0.0f) {
  if (sizeB <= 0.0f) sizeB = scaleB;
  float worst = 0.0f;
  for (int k = 0; k < kBoneCount; ++k) {
    const int ja = a.map.bones[static_cast<std::size_t>(k)], jb = b.map.bones[static_cast<std::size_t>(k)];
    if (ja < 0 || jb < 0) continue;
    const glm::vec3 expected = turnB * (pa[static_cast<std::size_t>(ja)] * scaleB);
    worst = std::max(worst, glm::length(pb[static_cast<std::size_t>(jb)] - expected) / sizeB);
  }
  return worst;
}

struct Retargeted {
  Retargeter r;
  std::vector<Transform> target;
};

Retargeted retargetPose(const TestHumanoid& src, const TestHumanoid& dst, const std::vector<Transform>& pose,
                 const RetargetOptions& options = {}) {
  Retargeted run{Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map, options), {}};
  run.target.resize(dst.skeleton.jointCount());
  RetargetScratch scratch = run.r.makeScratch();
  run.r.apply(pose, run.target, scratch);
  return run;
}

}  // namespace

TEST(Retargeter, IdenticalSkeletonsGiveTheSourceUpToRounding) {
  const TestHumanoid h = makeHumanoid({.rollSeed = 7});
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::vector<Transform> pose = randomPose(h.skeleton, seed);
    const Retargeted run = retargetPose(h, h, pose);
    ASSERT_TRUE(run.r.valid());
    for (std::size_t j = 0; j < pose.size(); ++j) {
      // Same rotation (q and -q are one rotation).
      EXPECT_GT(std::fabs(glm::dot(pose[j].rotation, run.target[j].rotation)), 1.0f - 1e-6f) << "joint " << j;
      EXPECT_LT(glm::length(pose[j].translation - run.target[j].translation), 1e-5f) << "joint " << j;
    }
  }
}

TEST(Retargeter, JointFramesAndRestShapesDoNotMatter) {
  // T-pose source with plain frames; targets in A-pose and arms-down rest, with
  // randomly rolled joint frames: same bone directions, same positions.
  const TestHumanoid src = makeHumanoid({});
  for (float down : {0.0f, 45.0f, 85.0f}) {
    for (unsigned roll : {0u, 3u, 11u}) {
      const TestHumanoid dst = makeHumanoid({.armDownDegrees = down, .rollSeed = roll, .prefix = "t_"});
      for (unsigned seed = 1; seed <= 5; ++seed) {
        const std::vector<Transform> pose = randomPose(src.skeleton, seed);
        const Retargeted run = retargetPose(src, dst, pose);
        const float err = worstBoneError(src, positions(src.skeleton, pose), dst, positions(dst.skeleton, run.target), 1.0f);
        EXPECT_LT(err, 2e-5f) << "arms down " << down << " roll " << roll << " pose " << seed;
      }
    }
  }
  // And the reverse: an A-pose source onto a T-pose target.
  const TestHumanoid a = makeHumanoid({.armDownDegrees = 45.0f, .rollSeed = 5});
  const std::vector<Transform> pose = randomPose(a.skeleton, 9);
  const Retargeted run = retargetPose(a, src, pose);
  EXPECT_LT(worstBoneError(a, positions(a.skeleton, pose), src, positions(src.skeleton, run.target), 1.0f), 2e-5f);
}

TEST(Retargeter, ScaledSkeletonsScaleTheMotion) {
  const TestHumanoid src = makeHumanoid({.rollSeed = 2});
  for (float scale : {0.01f, 100.0f}) {
    const TestHumanoid dst = makeHumanoid({.scale = scale, .armDownDegrees = 30.0f, .rollSeed = 4});
    const std::vector<Transform> pose = randomPose(src.skeleton, 3);
    const Retargeted run = retargetPose(src, dst, pose);
    EXPECT_NEAR(run.r.horizontalScale(), scale, scale * 1e-5f);
    EXPECT_NEAR(run.r.verticalScale(), scale, scale * 1e-5f);
    const float err = worstBoneError(src, positions(src.skeleton, pose), dst, positions(dst.skeleton, run.target), scale);
    EXPECT_LT(err, 5e-5f) << "scale " << scale;
    // And back.
    const std::vector<Transform> big = randomPose(dst.skeleton, 4, 0.8f, glm::vec3(0.2f * scale));
    const Retargeted back = retargetPose(dst, src, big);
    EXPECT_LT(worstBoneError(dst, positions(dst.skeleton, big), src, positions(src.skeleton, back.target), 1.0f / scale,
                             glm::quat(1, 0, 0, 0), 1.0f),
              5e-5f)
        << "from scale " << scale;
  }
}

TEST(Retargeter, MirroredJointsOnEitherSide) {
  const TestHumanoid plain = makeHumanoid({.rollSeed = 8});
  const TestHumanoid mirrored = makeHumanoid({.rollSeed = 9, .mirrorLeftArm = true});
  ASSERT_LT(mirrored.skeleton.restPose[static_cast<std::size_t>(mirrored.map.joint(Bone::LeftShoulder))].scale.x, 0.0f);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const std::vector<Transform> pose = randomPose(plain.skeleton, seed);
    const Retargeted run = retargetPose(plain, mirrored, pose);
    EXPECT_LT(worstBoneError(plain, positions(plain.skeleton, pose), mirrored, positions(mirrored.skeleton, run.target), 1.0f),
              2e-5f);
    const std::vector<Transform> mpose = randomPose(mirrored.skeleton, seed + 10);
    const Retargeted back = retargetPose(mirrored, plain, mpose);
    EXPECT_LT(worstBoneError(mirrored, positions(mirrored.skeleton, mpose), plain, positions(plain.skeleton, back.target), 1.0f),
              2e-5f);
  }
}

TEST(Retargeter, FacingIsAlignedAboutUp) {
  const TestHumanoid src = makeHumanoid({.rollSeed = 1});
  const TestHumanoid dst = makeHumanoid({.rollSeed = 6, .facingDegrees = 180.0f});
  const std::vector<Transform> pose = randomPose(src.skeleton, 5);
  const Retargeted run = retargetPose(src, dst, pose);
  const glm::quat turn = glm::angleAxis(glm::radians(180.0f), glm::vec3(0, 1, 0));
  EXPECT_LT(worstBoneError(src, positions(src.skeleton, pose), dst, positions(dst.skeleton, run.target), 1.0f, turn), 2e-5f);
  // Without alignment the character walks backwards: far off.
  RetargetOptions o;
  o.alignFacing = false;
  const Retargeted raw = retargetPose(src, dst, pose, o);
  EXPECT_GT(worstBoneError(src, positions(src.skeleton, pose), dst, positions(dst.skeleton, raw.target), 1.0f, turn), 0.1f);
}

TEST(Retargeter, ZeroLengthBonesGiveNoNaN) {
  const TestHumanoid src = makeHumanoid({.rollSeed = 3, .zeroLengthToes = true});
  const TestHumanoid dst = makeHumanoid({.armDownDegrees = 45.0f, .rollSeed = 4, .zeroLengthToes = true});
  const std::vector<Transform> pose = randomPose(src.skeleton, 2);
  const Retargeted run = retargetPose(src, dst, pose);
  for (const Transform& t : run.target) {
    ASSERT_TRUE(std::isfinite(t.rotation.w + t.rotation.x + t.rotation.y + t.rotation.z));
    ASSERT_TRUE(std::isfinite(t.translation.x + t.translation.y + t.translation.z));
  }
  EXPECT_LT(worstBoneError(src, positions(src.skeleton, pose), dst, positions(dst.skeleton, run.target), 1.0f), 2e-5f);
  // A whole skeleton of zero-length bones: rest pose, finite.
  TestHumanoid dot = makeHumanoid({.scale = 0.0f});
  const Retargeted flat = retargetPose(src, dot, pose);
  for (const Transform& t : flat.target) ASSERT_TRUE(std::isfinite(t.rotation.w + t.translation.x));
}

TEST(Retargeter, MissingJointsOnEitherSideAreNamed) {
  const TestHumanoid full = makeHumanoid({});
  TestHumanoid partial = makeHumanoid({.rollSeed = 2, .prefix = "p_"});
  const int leftHand = partial.map.joint(Bone::LeftHand);
  partial.map.bones[static_cast<std::size_t>(Bone::LeftHand)] = -1;
  partial.map.chains[static_cast<std::size_t>(Chain::LeftMiddle)].clear();
  partial.map.chains[static_cast<std::size_t>(Chain::Neck)].clear();

  const std::vector<Transform> pose = randomPose(full.skeleton, 4);
  const Retargeted run = retargetPose(full, partial, pose);
  auto noted = [&](const Retargeter& r, const std::string& what) {
    for (const std::string& n : r.notes())
      if (n.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(noted(run.r, "unmapped in target: leftHand (source joint 'L_hand'")) << "notes: " << run.r.notes().size();
  EXPECT_TRUE(noted(run.r, "unmapped in target: chain neck"));
  // The unmapped hand keeps its rest local rotation; the mapped forearm follows.
  EXPECT_GT(std::fabs(glm::dot(run.target[static_cast<std::size_t>(leftHand)].rotation,
                               partial.skeleton.restPose[static_cast<std::size_t>(leftHand)].rotation)),
            1.0f - 1e-6f);
  // The reverse: the target has joints the source does not drive.
  const std::vector<Transform> ppose = randomPose(partial.skeleton, 5);
  const Retargeted back = retargetPose(partial, full, ppose);
  EXPECT_TRUE(noted(back.r, "unmapped in source: leftHand (target joint 'L_hand' keeps its rest rotation)"));
  EXPECT_TRUE(noted(back.r, "source joints outside the joint map"));
  const int fullHand = full.map.joint(Bone::LeftHand);
  EXPECT_GT(std::fabs(glm::dot(back.target[static_cast<std::size_t>(fullHand)].rotation,
                               full.skeleton.restPose[static_cast<std::size_t>(fullHand)].rotation)),
            1.0f - 1e-6f);
}

TEST(Retargeter, SpinesOfTwoToFiveJoints) {
  // A spine bent evenly by 40 degrees forward and 30 sideways in total: the top of
  // the spine, the head, and the hands land near the source's whatever the counts.
  for (int ns = 2; ns <= 5; ++ns) {
    const TestHumanoid src = makeHumanoid({.spineJoints = ns, .rollSeed = 1});
    std::vector<Transform> pose = src.skeleton.restPose;
    for (int j : src.map.chain(Chain::Spine))
      pose[static_cast<std::size_t>(j)].rotation =
          pose[static_cast<std::size_t>(j)].rotation * glm::angleAxis(glm::radians(40.0f) / static_cast<float>(ns), glm::vec3(1, 0, 0)) *
          glm::angleAxis(glm::radians(30.0f) / static_cast<float>(ns), glm::vec3(0, 0, 1));
    const std::vector<glm::vec3> ps = positions(src.skeleton, pose);
    for (int nt = 2; nt <= 5; ++nt) {
      const TestHumanoid dst = makeHumanoid({.spineJoints = nt, .rollSeed = 2, .prefix = "t_"});
      const Retargeted run = retargetPose(src, dst, pose);
      const float err = worstBoneError(src, ps, dst, positions(dst.skeleton, run.target), 1.0f);
      // A few segments cannot draw another count's curve exactly: within 7 % of
      // the spine's length (0.45) at the hands, a quarter of the error of a spine left at rest.
      EXPECT_LT(err, 0.07f * 0.45f) << ns << " onto " << nt << " spine joints";
      RetargetOptions rigid;
      TestHumanoid unmapped = dst;
      unmapped.map.chains[static_cast<std::size_t>(Chain::Spine)].clear();
      const Retargeted still = retargetPose(src, unmapped, pose, rigid);
      EXPECT_LT(err, 0.25f * worstBoneError(src, ps, dst, positions(dst.skeleton, still.target), 1.0f));
      if (ns == nt) {
        EXPECT_LT(err, 2e-5f);
      }
      if (ns != nt) {
        bool noted = false;
        for (const std::string& n : run.r.notes()) noted |= n.find("chain spine:") != std::string::npos;
        EXPECT_TRUE(noted);
      }
    }
  }
}

TEST(Retargeter, BadInputGivesRestPoseNeverNaN) {
  const TestHumanoid src = makeHumanoid({});
  const TestHumanoid dst = makeHumanoid({.rollSeed = 3});
  Retargeter r = Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map);
  std::vector<Transform> target(dst.skeleton.jointCount());
  // NaN and zero rotations in the source.
  std::vector<Transform> pose = randomPose(src.skeleton, 1);
  pose[3].rotation = glm::quat(NAN, 0, 0, 0);
  pose[5].rotation = glm::quat(0, 0, 0, 0);
  pose[0].translation.x = INFINITY;
  RetargetScratch scratch = r.makeScratch();
  r.apply(pose, target, scratch);
  for (const Transform& t : target) {
    ASSERT_TRUE(std::isfinite(t.rotation.w + t.rotation.x + t.rotation.y + t.rotation.z));
    ASSERT_TRUE(std::isfinite(t.translation.x + t.translation.y + t.translation.z));
  }
  // A short source span: rest.
  std::vector<Transform> tooShort(3);
  r.apply(tooShort, target, scratch);
  for (std::size_t j = 0; j < target.size(); ++j)
    EXPECT_EQ(target[j].rotation, dst.skeleton.restPose[j].rotation);
  // A map naming joints outside the skeleton: an invalid binding with a note.
  JointMap broken = src.map;
  broken.bones[0] = 999;
  Retargeter bad = Retargeter::bind(src.skeleton, broken, dst.skeleton, dst.map);
  EXPECT_FALSE(bad.valid());
  ASSERT_FALSE(bad.notes().empty());
  EXPECT_NE(bad.notes().front().find("outside its skeleton"), std::string::npos);
  RetargetScratch badScratch = bad.makeScratch();
  bad.apply(randomPose(src.skeleton, 2), target, badScratch);
  for (std::size_t j = 0; j < target.size(); ++j) EXPECT_EQ(target[j].rotation, dst.skeleton.restPose[j].rotation);
}

TEST(Retargeter, WholeClipEqualsPerFrame) {
  const TestHumanoid src = makeHumanoid({.rollSeed = 1});
  const TestHumanoid dst = makeHumanoid({.scale = 1.3f, .armDownDegrees = 45.0f, .rollSeed = 2});
  Clip clip;
  clip.name = "wave";
  for (int j = 0; j < static_cast<int>(src.skeleton.jointCount()); ++j) {
    JointTrack t;
    t.joint = j;
    for (int k = 0; k <= 10; ++k) {
      t.rotation.times.push_back(0.1f * static_cast<float>(k));
      t.rotation.values.push_back(src.skeleton.restPose[static_cast<std::size_t>(j)].rotation *
                                  glm::angleAxis(0.05f * static_cast<float>(k * (j % 5)), glm::vec3(0, 0, 1)));
    }
    if (j == 0) {
      t.translation.times = t.rotation.times;
      for (float time : t.translation.times) t.translation.values.push_back(glm::vec3(0.0f, 1.0f, time));
    }
    clip.tracks.push_back(t);
  }
  clip.updateDuration();
  const Retargeter r = Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map);
  const Clip out = r.retargetClip(clip);
  ASSERT_TRUE(out.validate(dst.skeleton.jointCount()).empty()) << out.validate(dst.skeleton.jointCount());
  EXPECT_FLOAT_EQ(out.duration, clip.duration);
  std::vector<Transform> s(src.skeleton.jointCount()), a(dst.skeleton.jointCount()), b(dst.skeleton.jointCount());
  RetargetScratch scratch = r.makeScratch();
  for (float time : {0.0f, 0.3f, 0.7f, 1.0f}) {
    sampleClip(clip, time, src.skeleton.restPose, s);
    r.apply(s, a, scratch);
    sampleClip(out, time, dst.skeleton.restPose, b);
    const std::vector<glm::vec3> pa = positions(dst.skeleton, a), pb = positions(dst.skeleton, b);
    for (std::size_t j = 0; j < pa.size(); ++j) EXPECT_LT(glm::length(pa[j] - pb[j]), 1e-5f) << "t " << time << " joint " << j;
  }
}

namespace {

// A source whose left foot stands still at (0.1, 0.08, 0.15) while the hips move
// forward 0.3 m in 0.6 s, then lifts and swings forward (authored by IK on the source).
std::vector<std::vector<Transform>> plantedFootMotion(const TestHumanoid& h, int frames, float dt) {
  const LimbIk leg = makeLimbIk(h.skeleton, {h.map.joint(Bone::LeftUpperLeg), h.map.joint(Bone::LeftLowerLeg),
                                             h.map.joint(Bone::LeftFoot)});
  std::vector<std::vector<Transform>> out;
  for (int f = 0; f < frames; ++f) {
    const float t = static_cast<float>(f) * dt;
    std::vector<Transform> pose = h.skeleton.restPose;
    pose[0].translation.z += 0.5f * t;
    pose[0].translation.y -= 0.05f;  // knees bent a little: the foot is reachable
    glm::vec3 goal(0.1f, 0.08f, 0.15f);
    if (t > 0.6f) {
      const float u = std::min(1.0f, (t - 0.6f) / 0.15f);
      goal.y += 0.3f * u * u * (3.0f - 2.0f * u);
      goal.z += 1.0f * (t - 0.6f);
    }
    solveTwoBoneIk(h.skeleton, pose, leg, goal, goal + glm::vec3(0.0f, 0.5f, 1.0f), 1.0f, {0.0f});
    out.push_back(pose);
  }
  return out;
}

}  // namespace

TEST(RetargeterIk, HeldFootDoesNotSlideWhereProportionsDiffer) {
  const TestHumanoid src = makeHumanoid({});
  const TestHumanoid dst = makeHumanoid({.armDownDegrees = 45.0f, .rollSeed = 5, .prefix = "t_"});
  const float dt = 1.0f / 60.0f;
  const auto motion = plantedFootMotion(src, 60, dt);
  // The stride does not follow the legs (a stride scale of 0.7): without IK the
  // planted foot slides backward under the character.
  RetargetOptions plain;
  plain.horizontalScale = 0.7f;
  RetargetOptions held = plain;
  held.ik.feet = true;
  const Retargeter a = Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map, plain);
  const Retargeter b = Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map, held);
  const int foot = dst.map.joint(Bone::LeftFoot);
  std::vector<Transform> ta(dst.skeleton.jointCount()), tb(dst.skeleton.jointCount());
  std::vector<glm::mat4> ma(ta.size()), mb(tb.size());
  glm::vec3 startA{0.0f}, startB{0.0f}, previousA{0.0f}, previousB{0.0f};
  float slideA = 0.0f, slideB = 0.0f, worstStepA = 0.0f, worstStepB = 0.0f, worstTurn = 0.0f;
  RetargetScratch scratch = b.makeScratch(), scratchA = a.makeScratch();
  for (std::size_t f = 0; f < motion.size(); ++f) {
    a.apply(motion[f], ta, scratchA);
    b.apply(motion[f], tb, scratch, f == 0 ? 0.0f : dt);
    localToModel(dst.skeleton, ta, ma);
    localToModel(dst.skeleton, tb, mb);
    const glm::vec3 pa(ma[static_cast<std::size_t>(foot)][3]), pb(mb[static_cast<std::size_t>(foot)][3]);
    if (f == 0) startA = previousA = pa, startB = previousB = pb;
    const float t = static_cast<float>(f) * dt;
    if (t < 0.55f) {  // in contact
      slideA = std::max(slideA, glm::length(glm::vec2(pa.x - startA.x, pa.z - startA.z)));
      slideB = std::max(slideB, glm::length(glm::vec2(pb.x - startB.x, pb.z - startB.z)));
    }
    worstStepA = std::max(worstStepA, glm::length(pa - previousA));
    worstStepB = std::max(worstStepB, glm::length(pb - previousB));
    previousA = pa, previousB = pb;
    // The foot keeps the motion's orientation.
    const glm::mat3 ra = glm::mat3(ma[static_cast<std::size_t>(foot)]), rb = glm::mat3(mb[static_cast<std::size_t>(foot)]);
    for (int c = 0; c < 3; ++c) worstTurn = std::max(worstTurn, glm::length(ra[c] - rb[c]));
  }
  EXPECT_GT(slideA, 0.05f);
  EXPECT_LT(slideB, 1e-3f) << "slide without IK " << slideA;
  EXPECT_LT(worstTurn, 1e-3f);
  // Release eases out: no frame steps much more than the motion's own fastest.
  EXPECT_LT(worstStepB, 1.25f * worstStepA);
}

TEST(RetargeterIk, UnusableLimbsAreNotedAndSkipped) {
  const TestHumanoid src = makeHumanoid({});
  TestHumanoid dst = makeHumanoid({.rollSeed = 2});
  dst.map.bones[static_cast<std::size_t>(Bone::RightLowerArm)] = -1;
  RetargetOptions o;
  o.ik.feet = o.ik.hands = true;
  const Retargeter r = Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map, o);
  bool noted = false;
  for (const std::string& n : r.notes()) noted |= n.find("ik: the right arm is not mapped on both sides") != std::string::npos;
  EXPECT_TRUE(noted);
  std::vector<Transform> out(dst.skeleton.jointCount());
  RetargetScratch scratch = r.makeScratch();
  for (int f = 0; f < 10; ++f) {
    r.apply(randomPose(src.skeleton, static_cast<unsigned>(f)), out, scratch, 1.0f / 30.0f);
    for (const Transform& t : out) ASSERT_TRUE(std::isfinite(t.rotation.w + t.rotation.x + t.translation.y));
  }
}
