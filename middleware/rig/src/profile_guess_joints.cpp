// The body chain of a character profile: hips, spine, neck, head, eyes and jaw,
// from the VRM humanoid map, else joint names, else the shape of the skeleton.
#include "profile_guess.hpp"

#include <algorithm>

namespace marionette::profile_detail {

std::vector<std::string> spineBetween(const Tree& t, int hips, int neck) {
  std::vector<std::string> spine;
  if (!t.above(hips, neck)) return spine;
  for (int j = t.parent[neck]; j >= 0 && j != hips; j = t.parent[j]) spine.push_back(t.names[j]);
  std::reverse(spine.begin(), spine.end());
  return spine;
}

namespace {

// The VRM humanoid map, when it is complete and its chain is consistent.
bool guessFromHumanoid(const Asset& asset, const Tree& t, JointGuess& g) {
  if (!asset.hasHumanoid) return false;
  auto bone = [&](const char* key) {
    auto it = asset.humanoid.bones.find(key);
    return it == asset.humanoid.bones.end() ? -1 : t.find(it->second);
  };
  const int hips = bone("hips"), neck = bone("neck"), head = bone("head");
  if (hips < 0 || neck < 0 || head < 0 || !t.above(hips, neck) || !t.above(neck, head)) return false;
  g.hips = hips, g.neck = neck, g.head = head;
  g.hipsHow = g.neckHow = g.headHow = "VRM humanoid";
  auto below = [&](int j) { return t.above(head, j) ? j : -1; };
  if ((g.leftEye = below(bone("leftEye"))) >= 0) g.leftEyeHow = "VRM humanoid";
  if ((g.rightEye = below(bone("rightEye"))) >= 0) g.rightEyeHow = "VRM humanoid";
  if ((g.jaw = below(bone("jaw"))) >= 0) g.jawHow = "VRM humanoid";
  return true;
}

// Walking up from the neck, the joints where other branches (holding >= 2 leaves:
// arms, legs) leave the spine: the first is the chest (or the neck, where the arms
// hang from it), the next the hips.
int hipsAboveNeck(const Tree& t, int neck, int head) {
  int branchings = 0;
  int from = head >= 0 ? t.childToward(neck, head) : -1;
  for (int j = neck; t.valid(j); from = j, j = t.parent[j]) {
    const int other = t.leaves[j] - (from >= 0 ? t.leaves[from] : (j == neck ? t.leaves[j] : 0));
    if (other >= 2 && ++branchings == 2) return j;
  }
  return -1;
}

}  // namespace

JointGuess guessJoints(const Asset& asset, const Tree& t) {
  JointGuess g;
  if (guessFromHumanoid(asset, t, g)) return g;

  std::vector<int> hipsC, neckC, headC, eyeC[2], jawC;
  for (int j = 0; j < t.count(); ++j) {
    const NameParts np = parts(t.names[j], kJointNoise);
    if (np.side == 0) {
      if (np.is({"hips"}) || np.is({"hip"}) || np.is({"pelvis"})) hipsC.push_back(j);
      // "lowerneck" (CMU 3dsMax-friendly) is where the neck starts: the root-most wins below.
      if (np.is({"neck"}) || np.is({"lower", "neck"}) || np.is({"lowerneck"}) || np.is({"upper", "neck"}) ||
          np.is({"upperneck"}))
        neckC.push_back(j);
      if (np.is({"head"})) headC.push_back(j);
      if (np.is({"jaw"}) || np.is({"lower", "jaw"})) jawC.push_back(j);
    } else if (np.is({"eye"}) || np.is({"face", "eye"}) || np.is({"eye", "ball"}) || np.is({"eyeball"})) {
      eyeC[np.side > 0].push_back(j);
    }
  }
  auto underAny = [&](const std::vector<int>& tops, int j) {
    if (tops.empty()) return true;  // nothing of that name: no constraint
    return std::any_of(tops.begin(), tops.end(), [&](int a) { return t.above(a, j); });
  };
  auto shallowest = [&](const std::vector<int>& c) {
    int best = -1;
    for (int j : c)
      if (best < 0 || t.depth[j] < t.depth[best]) best = j;
    return best;
  };

  // Head: a head-named joint below a neck-named one, below a hips-named one.
  std::vector<int> heads;
  std::string rejected;
  for (int j : headC) {
    if (underAny(neckC, j) && underAny(hipsC, j)) heads.push_back(j);
    else rejected += (rejected.empty() ? "" : ", ") + inQuotes(t.names[j]);
  }
  const std::string rejectNote = rejected.empty() ? "" : "; " + rejected + " rejected: not below a neck and the hips";
  if ((g.head = shallowest(heads)) >= 0) {
    g.headHow = "name";
  } else {
    // The joint the eyes (or the jaw) hang from is the head, whatever its name.
    const int le = shallowest(eyeC[0]), re = shallowest(eyeC[1]), jaw = shallowest(jawC);
    if (le >= 0 && re >= 0 && t.parent[le] == t.parent[re] && t.parent[le] >= 0 && underAny(hipsC, t.parent[le])) {
      g.head = t.parent[le];
      g.headHow = "topology: parent of the eyes" + rejectNote;
    } else if (jaw >= 0 && t.parent[jaw] >= 0 && underAny(hipsC, t.parent[jaw])) {
      g.head = t.parent[jaw];
      g.headHow = "topology: parent of the jaw" + rejectNote;
    }
  }

  // Neck: the root-most neck-named joint above the head (CMU has Neck and Neck1);
  // else the unbranched chain above the head, up to where the arms branch off.
  if (g.head >= 0) {
    for (int j = t.parent[g.head]; j >= 0; j = t.parent[j])
      if (std::find(neckC.begin(), neckC.end(), j) != neckC.end()) g.neck = j, g.neckHow = "name";
    if (g.neck < 0 && t.parent[g.head] >= 0) {
      int j = t.parent[g.head];
      while (t.parent[j] >= 0 && t.children[t.parent[j]].size() == 1 &&
             std::find(hipsC.begin(), hipsC.end(), t.parent[j]) == hipsC.end())
        j = t.parent[j];
      if (std::find(hipsC.begin(), hipsC.end(), j) == hipsC.end())
        g.neck = j, g.neckHow = "topology: unbranched chain above the head";
    }
  } else {
    std::vector<int> necks;
    for (int j : neckC)
      if (underAny(hipsC, j)) necks.push_back(j);
    if ((g.neck = shallowest(necks)) >= 0) {
      g.neckHow = "name";
      if (t.children[g.neck].size() == 1)
        g.head = t.children[g.neck][0], g.headHow = "topology: only child of the neck" + rejectNote;
    }
  }

  // Hips: the deepest hips-named joint above the neck (Pab has Hips above Pelvis;
  // the legs branch at Pelvis); else where the legs branch off the spine.
  const int top = g.neck >= 0 ? g.neck : g.head;
  if (top >= 0) {
    for (int j = t.parent[top]; j >= 0 && g.hips < 0; j = t.parent[j])
      if (std::find(hipsC.begin(), hipsC.end(), j) != hipsC.end()) g.hips = j, g.hipsHow = "name";
    if (g.hips < 0 && g.neck >= 0 && (g.hips = hipsAboveNeck(t, g.neck, g.head)) >= 0)
      g.hipsHow = "topology: where the legs branch off below the arms";
  } else if ((g.hips = shallowest(hipsC)) >= 0) {
    g.hipsHow = "name";
  } else {
    // Nothing named: the root-most joint with a pair of legs and one odd branch.
    for (int j = 0; j < t.count(); ++j)
      if (t.oddChildOut(j, 1) >= 0 && (g.hips < 0 || t.depth[j] < t.depth[g.hips])) g.hips = j;
    if (g.hips >= 0) g.hipsHow = "topology: root-most joint with two legs and a spine";
  }

  // Neither neck nor head named: down the spine to the chest, whose odd branch is the neck.
  if (g.hips >= 0 && g.neck < 0 && g.head < 0) {
    int j = t.oddChildOut(g.hips, 1);
    while (t.valid(j) && t.children[j].size() == 1) j = t.children[j][0];
    const int neck = t.oddChildOut(j, 0);
    if (neck >= 0) {
      g.neck = neck, g.neckHow = "topology: odd branch of the chest";
      if (t.children[neck].size() == 1) g.head = t.children[neck][0], g.headHow = "topology: only child of the neck";
    }
  }
  if (g.head < 0 && !rejected.empty()) g.headHow = rejectNote.substr(2);

  // Eyes and jaw: named joints below the head.
  auto below = [&](const std::vector<int>& c) {
    std::vector<int> ok;
    for (int j : c)
      if (g.head < 0 || t.above(g.head, j)) ok.push_back(j);
    return shallowest(ok);
  };
  if ((g.leftEye = below(eyeC[0])) >= 0) g.leftEyeHow = "name";
  if ((g.rightEye = below(eyeC[1])) >= 0) g.rightEyeHow = "name";
  if ((g.jaw = below(jawC)) >= 0) g.jawHow = "name";
  return g;
}

}  // namespace marionette::profile_detail
