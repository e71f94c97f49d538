// What the character profile tests share: synthetic assets (joint lists, placed bodies, the
// robot), profile files written to a temporary folder, and lookups in notes and diagnostics.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "marionette/rig/character_profile.hpp"
#include "marionette/rig/rig.hpp"


namespace marionette::profile_test {

using Joints = std::vector<std::pair<std::string, std::string>>;  // name, parent name ("" for a root)

inline Asset makeAsset(const Joints& joints, std::vector<std::string> morphs = {}, const std::vector<std::string>& clips = {}) {
  Asset a;
  a.sourcePath = "synthetic.glb";
  for (const auto& [name, parent] : joints) a.skeleton.addJoint(name, a.skeleton.findJoint(parent), Transform{});
  a.morphTargets = std::move(morphs);
  for (const auto& c : clips) {
    Clip clip;
    clip.name = c;
    a.clips.push_back(clip);
  }
  return a;
}

// Hips with two legs, a spine of `spine` joints, a chest with two arms, neck, head.
inline Joints body(const std::string& hips, const std::vector<std::string>& spine, const std::string& neck,
            const std::string& head, const std::string& left, const std::string& right) {
  Joints j = {{hips, ""}, {left + "UpLeg", hips}, {left + "Leg", left + "UpLeg"}, {right + "UpLeg", hips},
              {right + "Leg", right + "UpLeg"}};
  std::string parent = hips;
  for (const auto& s : spine) j.emplace_back(s, parent), parent = s;
  j.insert(j.end(), {{left + "Arm", parent}, {left + "Hand", left + "Arm"}, {right + "Arm", parent},
                     {right + "Hand", right + "Arm"}, {neck, parent}, {head, neck}});
  return j;
}

inline bool hasNote(const CharacterProfile& p, const std::string& text) {
  return std::any_of(p.notes.begin(), p.notes.end(), [&](const std::string& n) { return n.find(text) != std::string::npos; });
}
inline std::string notes(const CharacterProfile& p) {
  std::string out;
  for (const auto& n : p.notes) out += n + '\n';
  return out;
}

// A profile file in a fresh temporary folder, removed with the object.
class TempProfile {
 public:
  explicit TempProfile(const std::string& text, const std::string& name = "profile.json") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("marionette_profile_" + std::string(info->test_suite_name()) + "_" + info->name());
    std::filesystem::create_directories(dir_);
    path_ = (dir_ / name).string();
    write(text);
  }
  ~TempProfile() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  void write(const std::string& text) const { std::ofstream(path_, std::ios::binary) << text; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::filesystem::path dir_;
  std::string path_;
};

inline const Diagnostic* findDiag(const Diagnostics& d, const std::string& text) {
  for (const auto& i : d.items)
    if (i.message.find(text) != std::string::npos) return &i;
  return nullptr;
}

// A small Mixamo-like character with morphs and clips, used by the loader tests.
inline Asset robot() {
  return makeAsset(body("Hips", {"Spine", "Chest"}, "Neck", "Head", "Left", "Right"), {"Smile", "Angry", "Blink"},
                   {"Idle", "Walking", "Running", "Wave"});
}

// Joints with their offsets from the parent, for the tests that need a rest pose.
struct PlacedJoint {
  std::string name, parent;
  glm::vec3 offset;
};
inline Asset makePlacedAsset(const std::vector<PlacedJoint>& joints) {
  Asset a;
  a.sourcePath = "placed.glb";
  for (const auto& j : joints) {
    Transform t;
    t.translation = j.offset;
    a.skeleton.addJoint(j.name, a.skeleton.findJoint(j.parent), t);
  }
  return a;
}

// A standing body facing +Z (toes ahead of the ankles), +Y up, its left at +X,
// with the limb joints named `L...` / `R...` + part: UpLeg, Leg, Foot, ToeBase,
// Shoulder, Arm, ForeArm, Hand. `leftX` is where the names called "L" go: +1 on
// the character's left, -1 (mislabelled) on its right.
inline std::vector<PlacedJoint> placedBody(const std::string& l, const std::string& r, float leftX = 1.0f) {
  std::vector<PlacedJoint> j = {{"Hips", "", {0, 1.0f, 0}},
                                {"Spine", "Hips", {0, 0.2f, 0}},
                                {"Chest", "Spine", {0, 0.2f, 0}},
                                {"Neck", "Chest", {0, 0.2f, 0}},
                                {"Head", "Neck", {0, 0.1f, 0}}};
  for (const auto& [side, x] : {std::pair{l, leftX}, std::pair{r, -leftX}}) {
    j.insert(j.end(), {{side + "UpLeg", "Hips", {0.1f * x, 0, 0}},
                       {side + "Leg", side + "UpLeg", {0, -0.45f, 0}},
                       {side + "Foot", side + "Leg", {0, -0.45f, 0}},
                       {side + "ToeBase", side + "Foot", {0, -0.08f, 0.12f}},
                       {side + "Shoulder", "Chest", {0.05f * x, 0.15f, 0}},
                       {side + "Arm", side + "Shoulder", {0.12f * x, 0, 0}},
                       {side + "ForeArm", side + "Arm", {0.28f * x, 0, 0}},
                       {side + "Hand", side + "ForeArm", {0.25f * x, 0, 0}}});
  }
  return j;
}

inline void expectLimb(const Limb& l, const std::string& upper, const std::string& lower, const std::string& end,
                const CharacterProfile& p) {
  EXPECT_EQ(l.upper, upper) << notes(p);
  EXPECT_EQ(l.lower, lower) << notes(p);
  EXPECT_EQ(l.end, end) << notes(p);
}

}  // namespace marionette::profile_test
