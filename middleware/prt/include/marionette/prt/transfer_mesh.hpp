// The geometry shadowed transfer is computed on: every triangle of a character in bind
// pose, in one vertex/index list, and the per-vertex data the visibility rays start from.
#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/asset/asset.hpp"

namespace marionette::prt {

struct TransferMesh {
  std::vector<glm::vec3> positions;     // model space, metres (but see SkinnedSpace::AsStored)
  std::vector<glm::vec3> normals;       // unit shading normals, one per position
  std::vector<std::uint32_t> indices;   // triangles
  // First vertex of each source primitive (mesh-major, primitive-minor order). Every primitive
  // of the asset has an entry; a primitive skipped for bad data has no vertices (its offset
  // equals the next one), so the entries still line up with Asset::meshes[m].primitives[p].
  std::vector<std::size_t> primitiveVertexOffset;
};

// Where bindPoseMesh puts skinned vertices.
enum class SkinnedSpace {
  // As stored: the skin's bind space. That is model space only when the skeleton's rest model
  // matrix times the inverse bind matrix is the identity for every joint. Not so for
  // RobotExpressive: its bind space is Z-up at 1/100 of model space (the root carries the x100
  // and the Z-up to Y-up turn) and its rest pose bends the limbs away from the bind pose.
  AsStored,
  // Skinned with the rest pose, as the runtime draws the character before any clip plays:
  // sum over weights of restModel[j] * inverseBind[j] * vertex, normals by the inverse
  // transpose of the blended matrix. Model space, like the rigid meshes.
  RestPose,
  // Skinned (and rigid meshes placed) with the model matrices of a pose given in
  // BindPoseOptions::poseModel, e.g. a clip's first frame: a character whose bind pose is a
  // T-pose gets the shadows of its arms on its sides when posed with the arms down.
  Posed,
};

struct BindPoseOptions {
  // RestPose by default: model space, the frame the renderer's lighting is turned into.
  SkinnedSpace skinnedSpace = SkinnedSpace::RestPose;
  std::vector<glm::mat4> poseModel;  // Posed: one model matrix per joint of the skeleton
};

// Every primitive of every mesh of an asset, in bind pose: skinned meshes as `options` say
// (default as stored, with a warning when that is not the skeleton's model space); an unskinned
// mesh attached to a joint (Mesh::joint >= 0, !skinned) transformed by that joint's rest model
// matrix (Skeleton::restModelMatrices()), normals by its inverse transpose; any other mesh as
// stored. Missing or unusable normals are computed (area-weighted face normals).
// Problems go to `diagnostics` naming the asset: a primitive with a non-finite position, or a
// mesh attached to a missing joint, is skipped (error); a triangle with an out-of-range index
// is dropped (error); a skinned vertex that RestPose cannot place (no weights, a joint past the
// skeleton) keeps its stored position (warning).
[[nodiscard]] TransferMesh bindPoseMesh(const Asset& asset, Diagnostics& diagnostics,
                                        const BindPoseOptions& options = {});

// Geometric vertex normals: the angle-weighted mean of the adjacent faces' normals (unit; a
// vertex with no non-degenerate face gets its shading normal, or +Y without one). For a convex
// mesh this normal lies in the normal cone, so no direction in its hemisphere enters the solid.
// Within a primitive, vertices at exactly the same position (UV or normal seams) are welded
// while accumulating, so they all get the same normal. Primitives are not welded to each other.
// Triangles with out-of-range indices are ignored.
[[nodiscard]] std::vector<glm::vec3> geometricVertexNormals(const TransferMesh& mesh);

// Ray-origin offset: a fraction of the bounding-box diagonal of the finite positions, so that
// it scales with the mesh (0 for a mesh without finite positions).
[[nodiscard]] float rayOriginOffset(const TransferMesh& mesh, float fraction = 1e-4f);

}  // namespace marionette::prt
