// PegGroups: the groups of sync points (pegs) that a block's equalities tie together, each with
// its offset in the group (a union-find). Private to the scheduler's files.
#pragma once
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace marionette::bml::detail {

// Times closer than this are equal (seconds).
inline constexpr double kEpsilon = 1e-6;

// Union-find over pegs with offsets: time(x) = time(root(x)) + offset(x).
class PegGroups {
 public:
  int add() {
    parent_.push_back(static_cast<int>(parent_.size()));
    offset_.push_back(0.0);
    return parent_.back();
  }
  [[nodiscard]] std::size_t size() const noexcept { return parent_.size(); }
  std::pair<int, double> find(int x) {
    double off = 0.0;
    int r = x;
    while (parent_[r] != r) {
      off += offset_[r];
      r = parent_[r];
    }
    // Path compression keeping offsets exact.
    double rest = off;
    for (int y = x; parent_[y] != y;) {
      const int next = parent_[y];
      const double o = offset_[y];
      parent_[y] = r;
      offset_[y] = rest;
      rest -= o;
      y = next;
    }
    return {r, off};
  }
  // Requires time(a) + da == time(b) + db. False on a contradiction.
  bool unite(int a, double da, int b, double db) {
    auto [ra, oa] = find(a);
    auto [rb, ob] = find(b);
    // time(ra) + oa + da == time(rb) + ob + db
    if (ra == rb) return std::fabs((oa + da) - (ob + db)) < kEpsilon;
    parent_[rb] = ra;
    offset_[rb] = (oa + da) - (ob + db);
    return true;
  }

 private:
  std::vector<int> parent_;
  std::vector<double> offset_;
};

}  // namespace marionette::bml::detail
