// A hand-made humanoid skeleton whose rest layout (joint positions) and joint
// frames are chosen separately, with its joint map: for retargeting tests where
// the answer is known. Two skeletons with the same bone lengths and the same
// bone directions in a pose must put every joint at the same place, whatever
// their joint axes, bone roll, mirrored frames or rest shapes (T / A pose).
#pragma once
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "marionette/rig/joint_map.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::test {

struct HumanoidSpec {
  int spineJoints = 3;            // 2 to 5
  float scale = 1.0f;             // every length
  float armDownDegrees = 0.0f;    // 0: T-pose; 45: A-pose; 85: arms down
  unsigned rollSeed = 0;          // nonzero: every joint frame turned by a random rotation (bone roll, joint axes)
  bool mirrorLeftArm = false;     // the left clavicle's frame mirrored (scale -1 on X), its subtree in mirrored frames
  bool zeroLengthToes = false;    // toes at the foot's position
  float facingDegrees = 0.0f;     // rest facing: rotation of the whole skeleton about +Y (0: faces +Z)
  std::string prefix = "";        // joint name prefix (skeletons with different names)
};

struct TestHumanoid {
  Skeleton skeleton;
  retarget::JointMap map;
  std::vector<glm::vec3> layout;  // rest model positions
};

// Joint frames: model rotation Rm and, for a mirrored subtree, the mirror M =
// diag(-1,1,1) on the right: model linear part = Rm * M. Locals are
// inverse(parent) * joint, which for a mirrored parent conjugates by M.
inline TestHumanoid makeHumanoid(const HumanoidSpec& spec) {
  TestHumanoid h;
  std::mt19937 rng(spec.rollSeed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto roll = [&]() {
    if (spec.rollSeed == 0) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
    glm::vec3 axis(u(rng), u(rng), u(rng));
    if (glm::length(axis) < 1e-3f) axis = glm::vec3(0.0f, 1.0f, 0.0f);
    return glm::angleAxis(2.5f * u(rng), glm::normalize(axis));
  };
  const float s = spec.scale;
  const glm::quat face = glm::angleAxis(glm::radians(spec.facingDegrees), glm::vec3(0.0f, 1.0f, 0.0f));
  struct Frame {
    glm::vec3 p;
    glm::quat r;
    bool mirrored;
  };
  std::vector<Frame> frames;
  auto add = [&](const std::string& name, int parent, glm::vec3 pos, bool mirrored = false) {
    pos = face * (pos * s);
    const glm::quat r = roll();
    Transform local;
    if (parent < 0) {
      local.translation = pos;
      local.rotation = r;
    } else {
      const Frame& pf = frames[static_cast<std::size_t>(parent)];
      const glm::vec3 m(-1.0f, 1.0f, 1.0f);
      glm::vec3 t = glm::conjugate(pf.r) * (pos - pf.p);
      glm::quat q = glm::conjugate(pf.r) * r;
      if (pf.mirrored) {  // M * v, and M q M (vector part's y, z negated)
        t *= m;
        q = glm::quat(q.w, q.x, -q.y, -q.z);
      }
      local.translation = t;
      local.rotation = q;
      if (mirrored && !pf.mirrored) local.scale = m;
    }
    frames.push_back({pos, r, mirrored});
    h.layout.push_back(pos);
    return h.skeleton.addJoint(spec.prefix + name, parent, local);
  };
  using retarget::Bone;
  using retarget::Chain;
  auto setBone = [&](Bone b, int j) { h.map.bones[static_cast<std::size_t>(b)] = j; };

  const int hips = add("pelvis", -1, {0.0f, 1.0f, 0.0f});
  setBone(Bone::Hips, hips);
  int parent = hips;
  const float spineLength = 0.45f;
  for (int k = 0; k < spec.spineJoints; ++k) {
    const float y = 1.0f + 0.05f + spineLength * static_cast<float>(k) / static_cast<float>(spec.spineJoints);
    parent = add("spine" + std::to_string(k), parent, {0.0f, y, 0.01f * static_cast<float>(k)});
    h.map.chains[static_cast<std::size_t>(Chain::Spine)].push_back(parent);
  }
  const int chest = parent;
  const int neck = add("neck", chest, {0.0f, 1.52f, 0.0f});
  h.map.chains[static_cast<std::size_t>(Chain::Neck)].push_back(neck);
  setBone(Bone::Head, add("head", neck, {0.0f, 1.62f, 0.02f}));

  const float down = glm::radians(spec.armDownDegrees);
  for (int side = 0; side < 2; ++side) {
    const float x = side == 0 ? 1.0f : -1.0f;  // left is +X for a character facing +Z
    const bool mirror = side == 0 && spec.mirrorLeftArm;
    const std::string n = side == 0 ? "L_" : "R_";
    const glm::vec3 shoulder(0.18f * x, 1.45f, 0.0f);
    // The arm hangs from the shoulder at `down` below horizontal.
    auto arm = [&](float along) { return shoulder + along * glm::vec3(x * std::cos(down), -std::sin(down), 0.0f); };
    const int clav = add(n + "clavicle", chest, {0.04f * x, 1.45f, 0.02f}, mirror);
    const int upper = add(n + "upperarm", clav, arm(0.0f), mirror);
    const int lower = add(n + "forearm", upper, arm(0.28f), mirror);
    const int hand = add(n + "hand", lower, arm(0.53f), mirror);
    const int finger = add(n + "middle1", hand, arm(0.62f), mirror);
    const int finger2 = add(n + "middle2", finger, arm(0.66f), mirror);
    setBone(side == 0 ? Bone::LeftShoulder : Bone::RightShoulder, clav);
    setBone(side == 0 ? Bone::LeftUpperArm : Bone::RightUpperArm, upper);
    setBone(side == 0 ? Bone::LeftLowerArm : Bone::RightLowerArm, lower);
    setBone(side == 0 ? Bone::LeftHand : Bone::RightHand, hand);
    h.map.chains[static_cast<std::size_t>(side == 0 ? Chain::LeftMiddle : Chain::RightMiddle)] = {finger, finger2};

    const int thigh = add(n + "thigh", hips, {0.1f * x, 0.95f, 0.0f});
    const int shin = add(n + "shin", thigh, {0.1f * x, 0.52f, 0.01f});
    const int foot = add(n + "foot", shin, {0.1f * x, 0.08f, -0.02f});
    const int toe = add(n + "toe", foot, spec.zeroLengthToes ? glm::vec3(0.1f * x, 0.08f, -0.02f)
                                                              : glm::vec3(0.1f * x, 0.02f, 0.12f));
    setBone(side == 0 ? Bone::LeftUpperLeg : Bone::RightUpperLeg, thigh);
    setBone(side == 0 ? Bone::LeftLowerLeg : Bone::RightLowerLeg, shin);
    setBone(side == 0 ? Bone::LeftFoot : Bone::RightFoot, foot);
    setBone(side == 0 ? Bone::LeftToes : Bone::RightToes, toe);
  }
  auto model = h.skeleton.restModelMatrices();
  for (std::size_t i = 0; i < model.size(); ++i) {
    h.skeleton.inverseBind[i] = glm::inverse(model[i]);
    h.skeleton.skinned[i] = 1;
  }
  return h;
}

}  // namespace marionette::test
