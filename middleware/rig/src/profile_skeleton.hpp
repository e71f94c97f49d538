// Internal to the character-profile code: joint names read as words (side,
// part, convention noise dropped) and the skeleton as a tree with the shape
// measures the guesses use. Shared by the body-chain and the limb guesses.
#pragma once
#include <algorithm>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/skeleton/skeleton.hpp"

namespace marionette::profile_detail {

inline bool isUpper(char c) { return c >= 'A' && c <= 'Z'; }
inline bool isLower(char c) { return c >= 'a' && c <= 'z'; }
inline bool isDigit(char c) { return c >= '0' && c <= '9'; }
// Bytes of UTF-8 sequences count as letters: they belong to a word, never split one.
inline bool isWordByte(char c) { return isUpper(c) || isLower(c) || isDigit(c) || static_cast<unsigned char>(c) >= 0x80; }
inline char lower(char c) { return isUpper(c) ? static_cast<char>(c - 'A' + 'a') : c; }

// Lower-case words of a name: split at separators, at camelCase humps ("LeftEye",
// "LHip" -> l, hip) and between letters and digits ("Spine1", "Bip01").
inline std::vector<std::string> words(std::string_view name) {
  std::vector<std::string> out;
  std::string cur;
  auto flush = [&] {
    if (!cur.empty()) out.push_back(std::move(cur));
    cur.clear();
  };
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (!isWordByte(c)) {
      flush();
      continue;
    }
    if (!cur.empty()) {
      const char p = name[i - 1];
      const bool hump = isUpper(c) && (isLower(p) || (isUpper(p) && i + 1 < name.size() && isLower(name[i + 1])));
      if (hump || isDigit(c) != isDigit(p)) flush();
    }
    cur += lower(c);
  }
  flush();
  return out;
}

// A name reduced to what identifies a body part or an expression: the side it
// names (-1 left, +1 right, 0 none) and the words left after dropping side words,
// numbers and the `noise` of naming conventions (rig prefixes and the like).
struct NameParts {
  int side = 0;
  std::vector<std::string> core;
  [[nodiscard]] std::string key() const {
    std::string k;
    for (const auto& w : core) k += w;
    return k;
  }
  [[nodiscard]] bool is(std::initializer_list<std::string_view> ws) const {
    return std::equal(core.begin(), core.end(), ws.begin(), ws.end());
  }
};

inline NameParts parts(std::string_view name, const std::set<std::string_view>& noise) {
  NameParts np;
  bool left = false, right = false;
  for (auto& w : words(name)) {
    if (w == "l" || w == "left") left = true;
    else if (w == "r" || w == "right") right = true;
    else if (!isDigit(w[0]) && !noise.count(w)) np.core.push_back(std::move(w));
  }
  np.side = left == right ? 0 : (left ? -1 : 1);
  if (left && right) np.core.insert(np.core.begin(), "?");  // "LeftRight..." is no part we know
  return np;
}

// Prefixes and suffixes of the rig conventions (mixamorig:, J_Bip_C_, B_, _Armature,
// Bip01, CC_Base_, ValveBiped., DEF-/ORG-/MCH-) that say nothing about the part.
inline const std::set<std::string_view> kJointNoise = {"mixamorig", "j",   "bip",  "adj",  "c",     "armature",
                                                "def",       "org", "mch",  "b",    "bone",  "jnt",
                                                "joint",     "cc",  "base", "valve", "biped", "sk"};

// The skeleton as a tree. Tolerates malformed input (sizes that differ, a parent
// that is not before its child): such a joint is treated as a root.
struct Tree {
  std::vector<std::string> names;
  std::vector<int> parent;
  std::vector<std::vector<int>> children;
  std::vector<int> depth, leaves, size, height;

  explicit Tree(const Skeleton& s) {
    const std::size_t n = std::min(s.names.size(), s.parents.size());
    names.assign(s.names.begin(), s.names.begin() + static_cast<std::ptrdiff_t>(n));
    parent.resize(n, -1);
    children.resize(n);
    depth.resize(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const int p = s.parents[i];
      if (p >= 0 && static_cast<std::size_t>(p) < i) {
        parent[i] = p;
        children[p].push_back(static_cast<int>(i));
        depth[i] = depth[p] + 1;
      }
    }
    leaves.assign(n, 0);
    size.assign(n, 1);
    height.assign(n, 0);
    for (std::size_t k = n; k-- > 0;) {  // children come after their parent
      if (children[k].empty()) leaves[k] = 1;
      if (const int p = parent[k]; p >= 0) {
        leaves[p] += leaves[k];
        size[p] += size[k];
        height[p] = std::max(height[p], height[k] + 1);
      }
    }
  }
  [[nodiscard]] int count() const { return static_cast<int>(parent.size()); }
  [[nodiscard]] bool valid(int j) const { return j >= 0 && j < count(); }
  // True when `a` is a proper ancestor of `d`.
  [[nodiscard]] bool above(int a, int d) const {
    if (!valid(a) || !valid(d)) return false;
    for (int p = parent[d]; p >= 0; p = parent[p])
      if (p == a) return true;
    return false;
  }
  [[nodiscard]] std::string name(int j) const { return valid(j) ? names[j] : std::string(); }
  [[nodiscard]] int find(const std::string& n) const {
    for (int j = 0; j < count(); ++j)
      if (names[j] == n) return j;
    return -1;
  }
  // The child of `a` on the way down to its descendant `d`.
  [[nodiscard]] int childToward(int a, int d) const {
    for (int j = d; valid(j); j = parent[j])
      if (parent[j] == a) return j;
    return -1;
  }
  // Among >= 3 children where the others form mirror pairs (same shape: two legs,
  // two arms), the one child whose shape is unique (the spine, the neck); else -1.
  [[nodiscard]] int oddChildOut(int j, int minPairHeight) const {
    if (!valid(j) || children[j].size() < 3) return -1;
    auto same = [&](int a, int b) { return size[a] == size[b] && height[a] == height[b] && leaves[a] == leaves[b]; };
    int odd = -1;
    bool pairFound = false;
    for (int c : children[j]) {
      int twins = 0;
      for (int o : children[j]) twins += o != c && same(o, c);
      if (twins == 0) {
        if (odd >= 0) return -1;  // two unique shapes: no telling which is the spine
        odd = c;
      } else if (height[c] >= minPairHeight) {
        pairFound = true;
      }
    }
    return pairFound ? odd : -1;
  }
};

inline std::string inQuotes(const std::string& s) { return "'" + s + "'"; }
inline std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + inQuotes(s);
  return out;
}

// Field-tagged notes: the loader keeps those of the fields it guesses.
using Notes = std::vector<std::pair<std::string, std::string>>;

}  // namespace marionette::profile_detail
