// A small BVH for any-hit rays: the oracle the Embree tracer is tested against, and a
// fallback. Plain and readable over fast: binned SAH build, 32-byte nodes in depth-first order,
// Moller-Trumbore triangles, single precision.
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <numeric>

#include "marionette/prt/ray_occlusion.hpp"
#include "traceable_geometry.hpp"

namespace marionette::prt {

namespace {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{std::numeric_limits<float>::lowest()};
  void grow(const glm::vec3& p) noexcept {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Box& b) noexcept {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  [[nodiscard]] float halfArea() const noexcept {
    const glm::vec3 d = glm::max(hi - lo, glm::vec3(0.0f));
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

// Interior node: count == 0, its left child follows it, `offset` is the right child.
// Leaf: `count` triangles from `offset`.
struct Node {
  glm::vec3 lo;
  std::uint32_t offset;
  glm::vec3 hi;
  std::uint32_t count;
};

// A triangle as Moller-Trumbore wants it: a corner and the two edges from it.
struct Triangle {
  glm::vec3 v0, e1, e2;
};

constexpr std::uint32_t kLeafSize = 4;   // split while more triangles than this
constexpr std::uint32_t kMaxLeaf = 16;   // ... or while SAH says a leaf is dearer
constexpr int kBins = 16;
// Past this depth splits are at the median (balanced), so the traversal stack below bounds
// the depth: kMedianDepth + log2(2^32) < kStackSize.
constexpr int kMedianDepth = 48;
constexpr int kStackSize = 96;

class BvhBuilder {
 public:
  BvhBuilder(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices) {
    const std::size_t count = indices.size() / 3;
    boxes_.resize(count);
    centroids_.resize(count);
    for (std::size_t t = 0; t < count; ++t) {
      for (int c = 0; c < 3; ++c) boxes_[t].grow(positions[indices[t * 3 + static_cast<std::size_t>(c)]]);
      centroids_[t] = 0.5f * (boxes_[t].lo + boxes_[t].hi);
    }
    order_.resize(count);
    std::iota(order_.begin(), order_.end(), 0u);
  }

  std::vector<Node> build() {
    if (!order_.empty()) split(0, static_cast<std::uint32_t>(order_.size()), 0);
    return std::move(nodes_);
  }
  // Triangle order of the leaves.
  [[nodiscard]] const std::vector<std::uint32_t>& order() const noexcept { return order_; }

 private:
  std::vector<Box> boxes_;
  std::vector<glm::vec3> centroids_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;

  void split(std::uint32_t begin, std::uint32_t end, int depth) {
    const std::size_t self = nodes_.size();
    nodes_.push_back({});
    Box bounds, centres;
    for (std::uint32_t i = begin; i < end; ++i) {
      bounds.grow(boxes_[order_[i]]);
      centres.grow(centroids_[order_[i]]);
    }
    nodes_[self].lo = bounds.lo;
    nodes_[self].hi = bounds.hi;
    const std::uint32_t count = end - begin;
    const auto makeLeaf = [&] {
      nodes_[self].offset = begin;
      nodes_[self].count = count;
    };
    const glm::vec3 extent = centres.hi - centres.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    if (count <= kLeafSize || !(extent[axis] > 0.0f)) return makeLeaf();  // all centroids coincide

    std::uint32_t mid = depth < kMedianDepth ? sahPartition(begin, end, centres, bounds) : begin;
    if (mid == end) return makeLeaf();  // SAH prefers a leaf
    if (mid == begin) {                 // no useful SAH split (or too deep): halve at the median
      mid = begin + count / 2;
      std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                       [&](std::uint32_t a, std::uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    }
    split(begin, mid, depth + 1);
    nodes_[self].offset = static_cast<std::uint32_t>(nodes_.size());
    nodes_[self].count = 0;
    split(mid, end, depth + 1);
  }

  // Partitions [begin, end) at the cheapest binned SAH plane over the three axes and returns
  // the split point; `end` when a leaf is cheaper, `begin` when no plane separates anything.
  std::uint32_t sahPartition(std::uint32_t begin, std::uint32_t end, const Box& centres, const Box& bounds) {
    float bestCost = std::numeric_limits<float>::max();
    int bestAxis = -1, bestBin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = centres.lo[axis], width = centres.hi[axis] - lo;
      if (!(width > 0.0f)) continue;
      const float scale = kBins / width;
      std::array<Box, kBins> binBox{};
      std::array<std::uint32_t, kBins> binCount{};
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = order_[i];
        const int b = std::min(kBins - 1, static_cast<int>((centroids_[t][axis] - lo) * scale));
        binBox[static_cast<std::size_t>(b)].grow(boxes_[t]);
        ++binCount[static_cast<std::size_t>(b)];
      }
      // Cost of splitting after bin b: area-weighted counts of the two sides.
      std::array<float, kBins> rightCost{};
      Box right;
      std::uint32_t rightCount = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.grow(binBox[static_cast<std::size_t>(b)]);
        rightCount += binCount[static_cast<std::size_t>(b)];
        rightCost[static_cast<std::size_t>(b - 1)] = rightCount > 0 ? right.halfArea() * static_cast<float>(rightCount) : 0.0f;
      }
      Box left;
      std::uint32_t leftCount = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        left.grow(binBox[static_cast<std::size_t>(b)]);
        leftCount += binCount[static_cast<std::size_t>(b)];
        if (leftCount == 0 || leftCount == end - begin) continue;
        const float cost = left.halfArea() * static_cast<float>(leftCount) + rightCost[static_cast<std::size_t>(b)];
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBin = b;
        }
      }
    }
    if (bestAxis < 0) return begin;
    // A leaf costs one intersection per triangle; a split one box test (taken as 1) plus its sides.
    const float leafCost = static_cast<float>(end - begin);
    const float splitCost = 1.0f + bestCost / std::max(bounds.halfArea(), FLT_MIN);
    if (end - begin <= kMaxLeaf && splitCost >= leafCost) return end;
    const float lo = centres.lo[bestAxis], scale = kBins / (centres.hi[bestAxis] - lo);
    const auto it = std::partition(order_.begin() + begin, order_.begin() + end, [&](std::uint32_t t) {
      return std::min(kBins - 1, static_cast<int>((centroids_[t][bestAxis] - lo) * scale)) <= bestBin;
    });
    return static_cast<std::uint32_t>(it - order_.begin());
  }
};

// Slightly inclusive barycentric bounds: a ray through a shared edge hits both triangles
// rather than slipping between them (an occlusion query only needs one).
constexpr float kEdgeSlack = 1e-6f;

bool hits(const Triangle& tri, const glm::vec3& origin, const glm::vec3& dir, float tnear, float tfar) noexcept {
  const glm::vec3 p = glm::cross(dir, tri.e2);
  const float det = glm::dot(tri.e1, p);
  if (det == 0.0f) return false;  // parallel to the plane (or a degenerate triangle)
  const float inv = 1.0f / det;
  const glm::vec3 s = origin - tri.v0;
  const float u = glm::dot(s, p) * inv;
  if (!(u >= -kEdgeSlack && u <= 1.0f + kEdgeSlack)) return false;
  const glm::vec3 q = glm::cross(s, tri.e1);
  const float v = glm::dot(dir, q) * inv;
  if (!(v >= -kEdgeSlack && u + v <= 1.0f + kEdgeSlack)) return false;
  const float t = glm::dot(tri.e2, q) * inv;
  return t >= tnear && t <= tfar;
}

// Widening of the box exit distance for the rounding in the slab test (Ize, "Robust BVH Ray
// Traversal", 2013: 1 + 2 gamma(3)), so a ray grazing a box is not culled.
constexpr float kSlabWiden = 1.0f + 2.0f * (3.0f * FLT_EPSILON * 0.5f) / (1.0f - 3.0f * FLT_EPSILON * 0.5f);

class BvhOcclusion final : public OcclusionTracer {
 public:
  BvhOcclusion(const TransferMesh& mesh, const std::vector<std::uint32_t>& indices) {
    BvhBuilder builder(mesh.positions, indices);
    nodes_ = builder.build();
    triangles_.reserve(builder.order().size());
    for (std::uint32_t t : builder.order()) {
      const glm::vec3 a = mesh.positions[indices[t * 3]], b = mesh.positions[indices[t * 3 + 1]],
                      c = mesh.positions[indices[t * 3 + 2]];
      triangles_.push_back({a, b - a, c - a});
    }
  }

  void occluded(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded) const noexcept override {
    const std::size_t n = std::min(rays.size(), occluded.size());
    for (std::size_t i = 0; i < n; ++i) {
      float tnear = 0.0f;
      occluded[i] = detail::traceable(rays[i], tnear) && anyHit(rays[i].origin, rays[i].direction, tnear, rays[i].tfar);
    }
  }
  const char* name() const noexcept override { return "bvh"; }

 private:
  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;

  bool anyHit(const glm::vec3& origin, const glm::vec3& dir, float tnear, float tfar) const noexcept {
    if (nodes_.empty()) return false;
    // 1/0 would make 0 * inf = NaN in the slab test; the largest float keeps it a number.
    glm::vec3 inv;
    for (int a = 0; a < 3; ++a) inv[a] = std::clamp(1.0f / dir[a], -FLT_MAX, FLT_MAX);
    std::array<std::uint32_t, kStackSize> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      const glm::vec3 t0 = (node.lo - origin) * inv, t1 = (node.hi - origin) * inv;
      const glm::vec3 tmin = glm::min(t0, t1), tmax = glm::max(t0, t1);
      const float enter = std::max({tnear, tmin.x, tmin.y, tmin.z});
      const float exit = std::min({tfar, tmax.x, tmax.y, tmax.z}) * kSlabWiden;
      if (!(enter <= exit)) continue;
      if (node.count > 0) {
        for (std::uint32_t t = node.offset; t < node.offset + node.count; ++t)
          if (hits(triangles_[t], origin, dir, tnear, tfar)) return true;
      } else {
        const auto self = static_cast<std::uint32_t>(&node - nodes_.data());
        stack[top++] = node.offset;
        stack[top++] = self + 1;
      }
    }
    return false;
  }
};

}  // namespace

std::unique_ptr<OcclusionTracer> makeBvhOcclusion(const TransferMesh& mesh, Diagnostics& diagnostics) {
  return std::make_unique<BvhOcclusion>(mesh, detail::traceableTriangles(mesh, &diagnostics, "bvh"));
}

std::unique_ptr<OcclusionTracer> makeBvhOcclusion(const TransferMesh& mesh) {
  return std::make_unique<BvhOcclusion>(mesh, detail::traceableTriangles(mesh, nullptr, "bvh"));
}

}  // namespace marionette::prt
