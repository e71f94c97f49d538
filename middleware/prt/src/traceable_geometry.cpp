#include "traceable_geometry.hpp"

#include <string>

namespace marionette::prt::detail {

std::vector<std::uint32_t> traceableTriangles(const TransferMesh& mesh, Diagnostics* diagnostics, const char* tracer) {
  const std::string file = std::string(tracer) + " occlusion";
  const std::size_t n = mesh.positions.size();
  std::vector<std::uint32_t> out;
  out.reserve(mesh.indices.size() - mesh.indices.size() % 3);
  std::size_t outOfRange = 0, nonFinite = 0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    if (i[0] >= n || i[1] >= n || i[2] >= n) {
      ++outOfRange;
      continue;
    }
    if (!isFinite(mesh.positions[i[0]]) || !isFinite(mesh.positions[i[1]]) || !isFinite(mesh.positions[i[2]])) {
      ++nonFinite;
      continue;
    }
    out.insert(out.end(), i, i + 3);
  }
  if (!diagnostics) return out;
  if (mesh.indices.size() % 3 != 0)
    diagnostics->warning(file, std::to_string(mesh.indices.size()) +
                                   " indices are not a whole number of triangles; the last partial one is ignored");
  if (outOfRange > 0)
    diagnostics->error(file, std::to_string(outOfRange) + " triangle(s) index past the mesh's " + std::to_string(n) +
                                 " vertices; dropped");
  if (nonFinite > 0)
    diagnostics->error(file, std::to_string(nonFinite) + " triangle(s) have a non-finite corner position; dropped");
  if (out.empty()) diagnostics->warning(file, "the mesh has no traceable triangles; no ray will be occluded");
  return out;
}

}  // namespace marionette::prt::detail
