#include "marionette/prt/transfer_mesh.hpp"

#include "marionette/core/finite.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>

namespace marionette::prt {

namespace {


// Unit vector along v, or nullopt when v is zero or not finite.
std::optional<glm::vec3> unit(const glm::vec3& v) noexcept {
  const float len = glm::length(v);
  if (!(len > 0.0f) || !std::isfinite(len)) return std::nullopt;
  return v / len;
}

constexpr glm::vec3 kFallbackNormal{0.0f, 1.0f, 0.0f};

// Where one vertex goes: positions by `position`, normals by the inverse transpose of its
// linear part.
struct Placement {
  glm::mat4 position{1.0f};
  glm::mat3 normal{1.0f};
};

std::optional<Placement> placementOf(const glm::mat4& m) noexcept {
  const glm::mat3 linear(m);
  const float det = glm::determinant(linear);
  if (!isFinite(m) || !std::isfinite(det) || det == 0.0f) return std::nullopt;
  return Placement{m, glm::transpose(glm::inverse(linear))};
}

// The rest-pose skinning matrix of vertex v (the weight-blended palette, as linear blend
// skinning draws it), or nullopt without usable weights.
std::optional<glm::mat4> restSkin(const MeshPrimitive& prim, std::size_t v, const std::vector<glm::mat4>& palette) noexcept {
  if (v >= prim.joints.size() || v >= prim.weights.size()) return std::nullopt;
  glm::mat4 sum(0.0f);
  float total = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const float w = prim.weights[v][k];
    if (!(w > 0.0f)) continue;  // also skips NaN
    const std::size_t j = prim.joints[v][k];
    if (j >= palette.size()) return std::nullopt;
    sum += w * palette[j];
    total += w;
  }
  if (!(total > 0.0f) || !std::isfinite(total)) return std::nullopt;
  return sum / total;
}

// How far a skinning palette entry is from the identity (largest element difference).
float offIdentity(const glm::mat4& m) noexcept {
  float d = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) d = std::max(d, std::abs(m[c][r] - (c == r ? 1.0f : 0.0f)));
  return d;
}

// Says once per asset when stored skinned vertices are not where the rest pose draws them.
void warnIfBindSpaceIsNotModelSpace(const Asset& asset, const std::vector<glm::mat4>& palette, Diagnostics& diagnostics) {
  for (const Mesh& mesh : asset.meshes) {
    if (!mesh.skinned) continue;
    for (const MeshPrimitive& prim : mesh.primitives)
      for (std::size_t v = 0; v < prim.joints.size() && v < prim.weights.size(); ++v)
        for (int k = 0; k < 4; ++k) {
          const std::size_t j = prim.joints[v][k];
          if (!(prim.weights[v][k] > 0.0f) || j >= palette.size() || offIdentity(palette[j]) <= 1e-3f) continue;
          const float scale = std::cbrt(std::abs(glm::determinant(glm::mat3(palette[j]))));
          diagnostics.warning(asset.sourcePath,
                              "mesh '" + mesh.name + "' is kept in its bind space, which is not the skeleton's model "
                              "space at rest: rest model x inverse bind of joint '" + asset.skeleton.names[j] +
                              "' is not the identity (scale " + std::to_string(scale) +
                              "); SkinnedSpace::RestPose puts skinned meshes in model space");
          return;
        }
  }
}

}  // namespace

TransferMesh bindPoseMesh(const Asset& asset, Diagnostics& diagnostics, const BindPoseOptions& options) {
  const std::string& file = asset.sourcePath;
  TransferMesh out;
  const bool posed = options.skinnedSpace == SkinnedSpace::Posed;
  const bool skinToRest = options.skinnedSpace == SkinnedSpace::RestPose || posed;

  // The rest pose only when a mesh needs it; restModelMatrices() trusts the skeleton.
  bool anyRigid = false, anySkinned = false;
  for (const Mesh& mesh : asset.meshes) {
    anyRigid = anyRigid || (!mesh.skinned && mesh.joint >= 0);
    anySkinned = anySkinned || mesh.skinned;
  }
  std::vector<glm::mat4> rest, palette;  // palette[j] = rest[j] * inverseBind[j]
  bool restKnown = false;                // false: the skeleton is invalid (reported once)
  if (anyRigid || anySkinned) {
    if (const std::string problem = asset.skeleton.validate(); problem.empty()) {
      restKnown = true;
      rest = asset.skeleton.restModelMatrices();
      if (posed && options.poseModel.size() == rest.size()) {
        rest = options.poseModel;
      } else if (posed) {
        diagnostics.error(file, "the pose for the transfer mesh has " + std::to_string(options.poseModel.size()) +
                                    " joint matrices but the skeleton has " + std::to_string(rest.size()) +
                                    " joints; the rest pose is used");
      }
      for (std::size_t j = 0; j < rest.size(); ++j) palette.push_back(rest[j] * asset.skeleton.inverseBind[j]);
    } else if (anyRigid || skinToRest) {
      diagnostics.error(file, "meshes need the skeleton's rest pose, but the skeleton is invalid: " + problem);
    }
  }
  if (anySkinned && !skinToRest) warnIfBindSpaceIsNotModelSpace(asset, palette, diagnostics);

  for (const Mesh& mesh : asset.meshes) {
    const std::string meshWhere = "mesh '" + mesh.name + "'";
    std::optional<Placement> rigid;
    bool skipMesh = false;
    if (!mesh.skinned && mesh.joint >= 0) {
      const auto j = static_cast<std::size_t>(mesh.joint);
      if (j >= rest.size()) {
        if (restKnown)
          diagnostics.error(file, meshWhere + " is attached to joint " + std::to_string(mesh.joint) + " but the skeleton has " +
                                      std::to_string(rest.size()) + " joints; mesh skipped");
        skipMesh = true;
      } else if (rigid = placementOf(rest[j]); !rigid) {
        diagnostics.error(file, meshWhere + " follows joint '" + asset.skeleton.names[j] +
                                    "', whose rest model matrix is singular or not finite; mesh skipped");
        skipMesh = true;
      }
    }
    const bool skinned = mesh.skinned && skinToRest && !palette.empty();

    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const MeshPrimitive& prim = mesh.primitives[p];
      out.primitiveVertexOffset.push_back(out.positions.size());
      if (skipMesh) continue;
      const std::string where = meshWhere + " primitive " + std::to_string(p);
      const std::size_t count = prim.positions.size();
      const std::size_t base = out.positions.size();
      if (base + count > std::numeric_limits<std::uint32_t>::max()) {
        diagnostics.error(file, where + ": more than 2^32 vertices in all; primitive skipped");
        continue;
      }

      // Positions and the file's normals, placed in model space.
      const bool haveNormals = prim.normals.size() == count;
      std::vector<glm::vec3> positions(count), placedNormals(haveNormals ? count : 0);
      std::size_t badPosition = count, unplaced = 0;
      for (std::size_t v = 0; v < count && badPosition == count; ++v) {
        std::optional<Placement> place = rigid;
        if (skinned) {
          if (auto m = restSkin(prim, v, palette)) place = placementOf(*m);
          if (!place) ++unplaced;
        }
        positions[v] = place ? glm::vec3(place->position * glm::vec4(prim.positions[v], 1.0f)) : prim.positions[v];
        if (haveNormals) placedNormals[v] = place ? place->normal * prim.normals[v] : prim.normals[v];
        if (!isFinite(positions[v])) badPosition = v;
      }
      if (badPosition != count) {
        diagnostics.error(file, where + " vertex " + std::to_string(badPosition) +
                                    " has a non-finite position; primitive skipped");
        continue;
      }
      if (unplaced > 0)
        diagnostics.warning(file, where + ": " + std::to_string(unplaced) +
                                      " vertex(es) without usable skin weights kept where stored");

      // Triangles: whole ones, with every index in range.
      std::vector<std::uint32_t> indices;
      indices.reserve(prim.indices.size());
      if (prim.indices.size() % 3 != 0)
        diagnostics.warning(file, where + " has " + std::to_string(prim.indices.size()) +
                                      " indices, not a whole number of triangles; the last partial one is dropped");
      std::size_t outOfRange = 0;
      for (std::size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
        const std::uint32_t a = prim.indices[t], b = prim.indices[t + 1], c = prim.indices[t + 2];
        if (a >= count || b >= count || c >= count) {
          ++outOfRange;
          continue;
        }
        indices.insert(indices.end(), {a, b, c});
      }
      if (outOfRange > 0)
        diagnostics.error(file, where + ": " + std::to_string(outOfRange) + " triangle(s) index past its " +
                                    std::to_string(count) + " vertices; dropped");

      // Shading normals: the file's where usable, else area-weighted face normals (the
      // unnormalized cross product is twice the area times the unit normal).
      std::vector<glm::vec3> normals(count, glm::vec3(0.0f));
      std::vector<std::uint8_t> missing(count, 1);
      if (!prim.normals.empty() && !haveNormals)
        diagnostics.warning(file, where + " has " + std::to_string(prim.normals.size()) + " normals for " +
                                      std::to_string(count) + " positions; normals computed from the faces");
      std::size_t unusable = 0;
      if (haveNormals)
        for (std::size_t v = 0; v < count; ++v) {
          if (auto u = unit(placedNormals[v])) {
            normals[v] = *u;
            missing[v] = 0;
          } else {
            ++unusable;
          }
        }
      if (unusable > 0)
        diagnostics.warning(file, where + ": " + std::to_string(unusable) +
                                      " normal(s) zero or not finite; computed from the faces");
      if (std::find(missing.begin(), missing.end(), 1) != missing.end()) {
        std::vector<glm::vec3> sum(count, glm::vec3(0.0f));
        for (std::size_t t = 0; t < indices.size(); t += 3) {
          const std::uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
          const glm::vec3 n = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
          sum[a] += n;
          sum[b] += n;
          sum[c] += n;
        }
        for (std::size_t v = 0; v < count; ++v)
          if (missing[v]) normals[v] = unit(sum[v]).value_or(kFallbackNormal);
      }

      for (std::uint32_t& i : indices) i += static_cast<std::uint32_t>(base);
      out.positions.insert(out.positions.end(), positions.begin(), positions.end());
      out.normals.insert(out.normals.end(), normals.begin(), normals.end());
      out.indices.insert(out.indices.end(), indices.begin(), indices.end());
    }
  }
  if (out.indices.empty()) diagnostics.warning(file, "the asset has no triangles to compute transfer on");
  return out;
}

namespace {

// Exact-position key: the float bits, with -0 folded into +0 so that both weld.
struct PositionKey {
  std::uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const noexcept {
    std::uint64_t h = k.x;
    h = h * 0x9E3779B97F4A7C15ull ^ k.y;
    h = h * 0x9E3779B97F4A7C15ull ^ k.z;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
PositionKey keyOf(const glm::vec3& p) noexcept {
  return {std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
          std::bit_cast<std::uint32_t>(p.z + 0.0f)};
}

// Angle between the edges from a corner (atan2 stays accurate near 0 and pi, unlike acos).
float cornerAngle(const glm::vec3& e0, const glm::vec3& e1) noexcept {
  return std::atan2(glm::length(glm::cross(e0, e1)), glm::dot(e0, e1));
}

}  // namespace

std::vector<glm::vec3> geometricVertexNormals(const TransferMesh& mesh) {
  const std::size_t n = mesh.positions.size();

  // Each vertex accumulates into the first vertex of its primitive at the same position.
  std::vector<std::size_t> bounds{0, n};
  for (std::size_t o : mesh.primitiveVertexOffset) bounds.push_back(std::min(o, n));
  std::sort(bounds.begin(), bounds.end());
  bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
  std::vector<std::size_t> representative(n);
  std::unordered_map<PositionKey, std::size_t, PositionKeyHash> first;
  for (std::size_t r = 0; r + 1 < bounds.size(); ++r) {
    first.clear();
    for (std::size_t v = bounds[r]; v < bounds[r + 1]; ++v)
      representative[v] = first.try_emplace(keyOf(mesh.positions[v]), v).first->second;
  }

  std::vector<glm::vec3> sum(n, glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    if (i[0] >= n || i[1] >= n || i[2] >= n) continue;
    const glm::vec3 p[3] = {mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]};
    const auto face = unit(glm::cross(p[1] - p[0], p[2] - p[0]));
    if (!face) continue;  // degenerate (or non-finite) face: no direction to contribute
    for (int c = 0; c < 3; ++c) {
      const float angle = cornerAngle(p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]);
      if (std::isfinite(angle)) sum[representative[i[c]]] += angle * *face;
    }
  }

  std::vector<glm::vec3> out(n);
  const bool haveShading = mesh.normals.size() == n;
  for (std::size_t v = 0; v < n; ++v) {
    if (auto u = unit(sum[representative[v]]))
      out[v] = *u;
    else
      out[v] = haveShading ? unit(mesh.normals[v]).value_or(kFallbackNormal) : kFallbackNormal;
  }
  return out;
}

float rayOriginOffset(const TransferMesh& mesh, float fraction) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  bool any = false;
  for (const glm::vec3& p : mesh.positions)
    if (isFinite(p)) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      any = true;
    }
  return any ? fraction * glm::length(hi - lo) : 0.0f;
}

}  // namespace marionette::prt
