// Assimp importer: the skeleton. The nodes that are mesh bones or animation
// targets, with their ancestors, become joints (parents before children); FBX
// helper nodes are folded into the joint below them; bone offset matrices give
// the inverse binds.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "assimp_conversion.hpp"
#include "marionette/core/text.hpp"

namespace marionette::assimp_detail {
namespace {

// Nodes Assimp's FBX reader inserts for pivots and geometric offsets. With
// AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS off they should not appear; if some do,
// they are folded into the real node below them instead of becoming joints.
constexpr std::string_view kFbxHelperTag = "_$AssimpFbx$_";

// Scaling every length by s turns an affine matrix M into S*M*S^-1: only the
// translation column changes.
glm::mat4 scaleLengths(glm::mat4 m, float s) {
  m[3] = glm::vec4(glm::vec3(m[3]) * s, m[3][3]);
  return m;
}

bool isFbxHelper(const aiNode& node) {
  return std::string_view(node.mName.C_Str()).find(kFbxHelperTag) != std::string_view::npos;
}

using NameSet = std::unordered_set<std::string>;
using NodeSet = std::unordered_set<const aiNode*>;
using BoneBinds = std::unordered_map<std::string, glm::mat4>;  // bone name -> offset matrix (file units)

NameSet wantedJointNames(const aiScene& scene) {
  NameSet names;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
    for (unsigned b = 0; b < scene.mMeshes[m]->mNumBones; ++b) names.insert(str(scene.mMeshes[m]->mBones[b]->mName));
  for (unsigned a = 0; a < scene.mNumAnimations; ++a)
    for (unsigned c = 0; c < scene.mAnimations[a]->mNumChannels; ++c)
      names.insert(str(scene.mAnimations[a]->mChannels[c]->mNodeName));
  return names;
}

// Keeps `node` when it is wanted or has a wanted descendant; returns whether it did.
bool keepWanted(const aiNode& node, const NameSet& wanted, NodeSet& kept) {
  bool keep = wanted.count(str(node.mName)) > 0;
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (keepWanted(*node.mChildren[i], wanted, kept)) keep = true;
  if (keep) kept.insert(&node);
  return keep;
}

void keepAll(const aiNode& node, NodeSet& kept) {
  kept.insert(&node);
  for (unsigned i = 0; i < node.mNumChildren; ++i) keepAll(*node.mChildren[i], kept);
}

// BVH "End Site" nodes (Assimp names them "EndSite_<joint>") carry no channels and
// no bones, so they are not wanted and the skeleton has exactly the file's ROOT and
// JOINT entries.
NodeSet chooseJointNodes(const aiScene& scene) {
  const NameSet wanted = wantedJointNames(scene);
  const aiNode& root = *scene.mRootNode;
  NodeSet kept;
  keepWanted(root, wanted, kept);
  // The root is a joint only when it is a bone or animated itself; otherwise it
  // is the space the skeleton lives in (Skeleton::rootTransform).
  if (!wanted.count(str(root.mName))) kept.erase(&root);
  if (kept.empty()) {
    // A static model: its node tree is the skeleton.
    if (root.mNumChildren == 0) kept.insert(&root);
    for (unsigned i = 0; i < root.mNumChildren; ++i) keepAll(*root.mChildren[i], kept);
  }
  return kept;
}

bool nearlyEqual(const glm::mat4& a, const glm::mat4& b) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(a[c][r] - b[c][r]) > 1e-4f * std::max(1.0f, std::abs(a[c][r]))) return false;
  return true;
}

BoneBinds collectBoneBinds(Importing& im) {
  BoneBinds binds;
  std::vector<std::string> conflicting;
  for (unsigned m = 0; m < im.scene.mNumMeshes; ++m) {
    const aiMesh& mesh = *im.scene.mMeshes[m];
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      const glm::mat4 offset = toGlm(bone.mOffsetMatrix);
      auto [it, inserted] = binds.emplace(str(bone.mName), offset);
      if (!inserted && !nearlyEqual(it->second, offset) &&
          std::find(conflicting.begin(), conflicting.end(), it->first) == conflicting.end())
        conflicting.push_back(it->first);
    }
  }
  if (!conflicting.empty())
    im.warning("bones " + quotedNameList(conflicting) +
               " have different bind matrices in different meshes; the first mesh's are used");
  return binds;
}

int addJoint(Importing& im, const aiNode& node, int parent, const glm::mat4& local, const glm::mat4& folded,
             const BoneBinds& binds, std::vector<std::string>& duplicates) {
  Skeleton& skeleton = im.asset.skeleton;
  std::string name = str(node.mName);
  auto bind = name.empty() ? binds.end() : binds.find(name);
  if (name.empty()) name = "joint_" + std::to_string(skeleton.jointCount());
  Transform rest = decompose(local);
  rest.translation *= im.scale;
  const bool skinned = bind != binds.end();
  const glm::mat4 inverseBind = skinned ? scaleLengths(bind->second, im.scale) : glm::mat4(1.0f);
  const int index = skeleton.addJoint(name, parent, rest, inverseBind, skinned);
  im.jointOfNode[&node] = index;
  if (!im.jointOfName.emplace(name, index).second) duplicates.push_back(name);
  im.foldedHelpers.push_back(folded);
  return index;
}

// Depth-first, so parents come before children. `folded` carries the transforms
// of FBX helper nodes directly above `node`.
void addJointTree(Importing& im, const aiNode& node, int parent, const glm::mat4& folded, const NodeSet& kept,
                  const BoneBinds& binds, std::vector<std::string>& duplicates) {
  if (!kept.count(&node)) return;
  const glm::mat4 local = folded * toGlm(node.mTransformation);
  int self = parent;
  glm::mat4 passDown(1.0f);
  if (isFbxHelper(node))
    passDown = local;
  else
    self = addJoint(im, node, parent, local, folded, binds, duplicates);
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    addJointTree(im, *node.mChildren[i], self, passDown, kept, binds, duplicates);
}

}  // namespace

void buildSkeleton(Importing& im) {
  const NodeSet kept = chooseJointNodes(im.scene);
  const BoneBinds binds = collectBoneBinds(im);
  const aiNode& root = *im.scene.mRootNode;
  std::vector<std::string> duplicates;
  if (kept.count(&root)) {
    addJointTree(im, root, -1, glm::mat4(1.0f), kept, binds, duplicates);
  } else {
    im.asset.skeleton.rootTransform = scaleLengths(toGlm(root.mTransformation), im.scale);
    for (unsigned i = 0; i < root.mNumChildren; ++i)
      addJointTree(im, *root.mChildren[i], -1, glm::mat4(1.0f), kept, binds, duplicates);
  }
  if (!duplicates.empty())
    im.warning("joint names " + quotedNameList(duplicates) +
               " occur more than once; bones and animation channels bind to the first of each");
}

}  // namespace marionette::assimp_detail
