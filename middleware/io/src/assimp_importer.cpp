// Imports FBX, COLLADA, BVH, MD5, X (and whatever else Assimp reads) into an Asset.
//
// What comes out:
//  - Skeleton: the nodes that are mesh bones or animation targets, plus all their
//    ancestors below the scene root, depth-first (parents before children). A file
//    with neither (a static model) gets its whole node tree, so every import has a
//    skeleton. The scene root's transform becomes Skeleton::rootTransform unless the
//    root is itself a joint (BVH puts the hips there).
//  - Lengths: FBX is converted to metres from its UnitScaleFactor (centimetres per
//    unit); other formats keep their numbers. ImportOptions::extraScale multiplies both.
//  - One Clip per aiAnimation, in seconds, starting at 0.
//  - One Mesh per node that carries meshes, one primitive per aiMesh (Assimp has
//    already split them by material).
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "file_extension.hpp"
#include "isolated_call.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/limits.hpp"
#include "marionette/core/text.hpp"
#include "marionette/io/import.hpp"
#include "model_folder.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;

// Nodes Assimp's FBX reader inserts for pivots and geometric offsets. With
// AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS off they should not appear; if some do,
// they are folded into the real node below them instead of becoming joints.
constexpr std::string_view kFbxHelperTag = "_$AssimpFbx$_";
// What Assimp's own tools assume when a file gives no tick rate.
constexpr double kDefaultTicksPerSecond = 25.0;

// ---------------------------------------------------------------- small helpers

glm::mat4 toGlm(const aiMatrix4x4& m) {
  // aiMatrix4x4 is row-major (a1..a4 is the first row); glm::mat4 takes columns.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4,
                   m.c4, m.d4);
}
glm::vec3 toGlm(const aiVector3D& v) { return {v.x, v.y, v.z}; }
glm::quat toGlm(const aiQuaternion& q) { return glm::quat(q.w, q.x, q.y, q.z); }


// Scaling every length by s turns an affine matrix M into S*M*S^-1: only the
// translation column changes.
glm::mat4 scaleLengths(glm::mat4 m, float s) {
  m[3] = glm::vec4(glm::vec3(m[3]) * s, m[3][3]);
  return m;
}

std::string str(const aiString& s) { return std::string(s.C_Str()); }

using detail::lowerExtension;

bool isFbxHelper(const aiNode& node) {
  return std::string_view(node.mName.C_Str()).find(kFbxHelperTag) != std::string_view::npos;
}

// ---------------------------------------------------------------- before reading

// The first `count` whitespace-separated words of a text file, skipping '#' comments.
std::vector<std::string> firstWords(const std::string& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  std::vector<std::string> words;
  for (std::size_t i = 0; i < head.size() && words.size() < count;) {
    if (head[i] == '#') {
      while (i < head.size() && head[i] != '\n') ++i;
    } else if (space(head[i])) {
      ++i;
    } else {
      const std::size_t start = i;
      while (i < head.size() && !space(head[i]) && head[i] != '#') ++i;
      words.push_back(head.substr(start, i - start));
    }
  }
  return words;
}

// A non-negative decimal count (saturating), or nothing if `word` is not one.
std::optional<std::uint64_t> parseCount(const std::string& word) {
  if (word.empty() || !std::all_of(word.begin(), word.end(), [](unsigned char c) { return std::isdigit(c); }))
    return std::nullopt;
  if (word.size() > 18) return std::numeric_limits<std::uint64_t>::max();
  return std::stoull(word);
}

// Assimp's OFF reader allocates (and zero-fills) as many vertices as the header
// declares before it notices that the file is short, so a 300-byte file declaring
// 10^11 vertices costs gigabytes and minutes. Refuse counts the file cannot hold.
bool checkOffCounts(const std::string& path, std::uintmax_t size, Diagnostics& diag) {
  const std::vector<std::string> words = firstWords(path, 4);
  std::size_t first = 0;  // a header-less OFF starts with the counts
  if (!words.empty() && words[0].size() >= 3 && words[0].compare(words[0].size() - 3, 3, "OFF") == 0) {
    // [ST][C][N][4][n]OFF: the 'n' variant puts a dimension before the counts.
    first = words[0].find('n') != std::string::npos ? 2 : 1;
  }
  if (words.size() < first + 2) return true;  // Assimp reports a broken header itself
  const auto vertices = parseCount(words[first]), faces = parseCount(words[first + 1]);
  if (!vertices || !faces) return true;
  // Every vertex and every face needs at least two bytes ("0\n").
  const std::uint64_t room = size / 2;
  if (*vertices <= room && *faces <= room) return true;
  diag.error(path, "OFF header declares " + words[first] + " vertices and " + words[first + 1] +
                       " faces, more than a file of " + std::to_string(size) + " bytes can hold");
  return false;
}

bool checkFile(const std::string& path, Diagnostics& diag) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    diag.error(path, "cannot read the file: " + ec.message());
    return false;
  }
  if (size > limits::kMaxModelFileBytes) {
    diag.error(path, "file is " + std::to_string(size >> 20) +
                         " MiB; model files over 512 MiB are refused (limits::kMaxModelFileBytes)");
    return false;
  }
  if (lowerExtension(path) == ".off") return checkOffCounts(path, size, diag);
  return true;
}

unsigned postProcessFlags(bool meshes) {
  unsigned flags = aiProcess_ValidateDataStructure;
  if (meshes)
    flags |= aiProcess_Triangulate | aiProcess_LimitBoneWeights | aiProcess_JoinIdenticalVertices |
             aiProcess_GenSmoothNormals;
  return flags;
}

void configure(Assimp::Importer& importer) {
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  // BVH (and a lone MD5 animation) would otherwise get a generated stick-figure
  // mesh that we would import as real geometry.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
  // A bone without weights is still a skin joint with a real inverse bind.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_REMOVE_EMPTY_BONES, false);
  importer.SetPropertyInteger(AI_CONFIG_PP_LBW_MAX_WEIGHTS, 4);
}

const aiScene* readScene(Assimp::Importer& importer, const std::string& path, bool meshes, Diagnostics& diag) {
  // Post-processing is a second step: a motion-only file has no meshes, and the
  // validator rejects that unless the scene is flagged incomplete first.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene) {
    diag.error(path, std::string("Assimp could not read the file: ") + importer.GetErrorString());
    return nullptr;
  }
  if (scene->mNumMeshes == 0) {
    // The importer owns this scene; flagging it is how Assimp marks skeleton- or
    // animation-only data (some readers, e.g. FBX, set the flag themselves).
    const_cast<aiScene*>(scene)->mFlags |= AI_SCENE_FLAGS_INCOMPLETE;
  }
  scene = importer.ApplyPostProcessing(postProcessFlags(meshes));
  if (!scene) {
    diag.error(path, std::string("Assimp rejected the file's contents: ") + importer.GetErrorString());
    return nullptr;
  }
  if (!scene->mRootNode) {
    diag.error(path, "Assimp returned a scene without a root node");
    return nullptr;
  }
  if (scene->mFlags & AI_SCENE_FLAGS_VALIDATION_WARNING)
    diag.warning(path, "Assimp's validator reported minor problems in the file's data");
  return scene;
}

// ---------------------------------------------------------------- conversion state

struct Importing {
  const aiScene& scene;
  const std::string& path;
  const ImportOptions& options;
  Diagnostics& diag;
  Asset asset;
  float scale = 1.0f;  // applied to every length
  std::unordered_map<const aiNode*, int> jointOfNode;
  std::unordered_map<std::string, int> jointOfName;  // the first joint with each name
  std::vector<glm::mat4> foldedHelpers;             // per joint: FBX helper transforms above it

  void error(std::string message) { diag.error(path, std::move(message)); }
  void warning(std::string message) { diag.warning(path, std::move(message)); }
  void note(std::string message) { diag.items.push_back({Severity::Note, path, 0, 0, std::move(message)}); }
};

std::optional<double> metadataNumber(const aiMetadata* meta, const std::string& key) {
  if (!meta) return std::nullopt;
  float f = 0.0f;
  double d = 0.0;
  std::int32_t i = 0;
  if (meta->Get(key, f)) return f;
  if (meta->Get(key, d)) return d;
  if (meta->Get(key, i)) return i;
  return std::nullopt;
}

bool isFbx(const Importing& im) {
  if (lowerExtension(im.path) == ".fbx") return true;
  aiString format;
  return im.scene.mMetaData && im.scene.mMetaData->Get("SourceAsset_Format", format) &&
         std::string_view(format.C_Str()).find("FBX") != std::string_view::npos;
}

// Metres per file unit. Assimp leaves FBX lengths in the file's unit, which the
// file states as UnitScaleFactor = centimetres per unit.
float fileUnitScale(Importing& im) {
  if (!isFbx(im)) return 1.0f;
  const std::optional<double> cm = metadataNumber(im.scene.mMetaData, "UnitScaleFactor");
  if (!cm) {
    im.warning("FBX file states no UnitScaleFactor; assuming centimetres");
    return 0.01f;
  }
  if (!std::isfinite(*cm) || *cm <= 0.0) {
    im.warning("FBX UnitScaleFactor " + std::to_string(*cm) + " is not a positive number; assuming centimetres");
    return 0.01f;
  }
  return static_cast<float>(*cm / 100.0);
}

// ---------------------------------------------------------------- skeleton

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

// ---------------------------------------------------------------- clips

template <class T>
struct TimedValue {
  double time;  // seconds, clip-local
  T value;
};

struct KeyIssues {
  std::size_t unsorted = 0;             // tracks whose keys had to be sorted
  std::size_t conflictingDuplicates = 0;  // same time, different value (the last was kept)
  std::size_t zeroRotations = 0;          // zero-length quaternions replaced by identity
};

// Keys must have strictly increasing times: sort when needed and keep the last
// key of each time. Duplicates with identical values are routine (resampled
// exports) and not reported.
template <class T>
Track<T> makeTrack(std::vector<TimedValue<T>>& keys, KeyIssues& issues) {
  auto earlier = [](const TimedValue<T>& a, const TimedValue<T>& b) { return a.time < b.time; };
  if (!std::is_sorted(keys.begin(), keys.end(), earlier)) {
    ++issues.unsorted;
    std::stable_sort(keys.begin(), keys.end(), earlier);
  }
  Track<T> track;  // Assimp 5.2 keys carry no interpolation mode: linear
  for (const TimedValue<T>& k : keys) {
    const float t = static_cast<float>(k.time);
    if (!track.times.empty() && t <= track.times.back()) {
      if (!(track.values.back() == k.value)) ++issues.conflictingDuplicates;
      track.values.back() = k.value;
      continue;
    }
    track.times.push_back(t);
    track.values.push_back(k.value);
  }
  return track;
}

struct ChannelContext {
  std::string where;  // "clip 'walk', joint 'Hips'"
  double ticksPerSecond;
  double startTicks;      // the clip's earliest key, moved to time 0
  glm::mat4 folded;       // FBX helper transforms above the joint (usually identity)
};

template <class Key, class T, class Convert>
std::optional<std::vector<TimedValue<T>>> readKeys(Importing& im, const Key* keys, unsigned count,
                                                    const ChannelContext& cc, const char* what,
                                                    Convert convert) {
  std::vector<TimedValue<T>> out;
  out.reserve(count);
  for (unsigned k = 0; k < count; ++k) {
    const double seconds = (keys[k].mTime - cc.startTicks) / cc.ticksPerSecond;
    const T value = convert(keys[k].mValue);
    if (!std::isfinite(seconds) || !std::isfinite(static_cast<float>(seconds)) || !isFinite(value)) {
      im.error(cc.where + ": " + what + " key " + std::to_string(k) + " has a non-finite time or value");
      return std::nullopt;
    }
    out.push_back({seconds, value});
  }
  return out;
}

bool allOnes(const Track<glm::vec3>& track) {
  return std::all_of(track.values.begin(), track.values.end(),
                     [](const glm::vec3& v) { return v == glm::vec3(1.0f); });
}

std::optional<JointTrack> convertChannel(Importing& im, const aiNodeAnim& channel, int joint,
                                         const ChannelContext& cc, KeyIssues& issues) {
  // A folded helper H above the joint makes its local transform H * TRS(t); with
  // H = T_h R_h S_h that is a TRS again (exactly when S_h is uniform).
  const Transform helper = decompose(cc.folded);
  const float scale = im.scale;
  auto translation = [&](const aiVector3D& v) { return glm::vec3(cc.folded * glm::vec4(toGlm(v), 1.0f)) * scale; };
  auto rotation = [&](const aiQuaternion& q) {
    const glm::quat raw = toGlm(q);
    if (!isFinite(raw)) return raw;  // reported as non-finite by readKeys
    if (raw.w == 0.0f && raw.x == 0.0f && raw.y == 0.0f && raw.z == 0.0f) ++issues.zeroRotations;
    return safeNormalize(helper.rotation * safeNormalize(raw));
  };
  auto scaling = [&](const aiVector3D& v) { return helper.scale * toGlm(v); };

  auto t = readKeys<aiVectorKey, glm::vec3>(im, channel.mPositionKeys, channel.mNumPositionKeys, cc, "translation",
                                            translation);
  auto r = readKeys<aiQuatKey, glm::quat>(im, channel.mRotationKeys, channel.mNumRotationKeys, cc, "rotation",
                                          rotation);
  auto s = readKeys<aiVectorKey, glm::vec3>(im, channel.mScalingKeys, channel.mNumScalingKeys, cc, "scale",
                                            scaling);
  if (!t || !r || !s) return std::nullopt;
  JointTrack track;
  track.joint = joint;
  track.translation = makeTrack(*t, issues);
  track.rotation = makeTrack(*r, issues);
  track.scale = makeTrack(*s, issues);
  // Scale tracks that never leave 1 (BVH, most FBX) only cost memory and sampling time.
  if (allOnes(track.scale)) track.scale = {};
  return track;
}

std::string uniqueClipName(const Importing& im, const aiAnimation& anim, std::size_t index,
                           std::set<std::string>& used) {
  std::string base = str(anim.mName);
  if (base.empty())
    base = im.scene.mNumAnimations == 1 ? fs::path(im.path).stem().string() : "animation_" + std::to_string(index);
  if (base.empty()) base = "animation_" + std::to_string(index);
  return claimUniqueName(base, used);
}

double ticksPerSecond(Importing& im, const aiAnimation& anim, const std::string& clip) {
  const double tps = anim.mTicksPerSecond;
  if (std::isfinite(tps) && tps > 0.0) return tps;
  im.warning("clip '" + clip + "' states " + std::to_string(tps) + " ticks per second; assuming " +
             std::to_string(static_cast<int>(kDefaultTicksPerSecond)));
  return kDefaultTicksPerSecond;
}

// The channels that drive a joint, sorted by joint index (one per joint).
std::vector<std::pair<int, const aiNodeAnim*>> boundChannels(Importing& im, const aiAnimation& anim,
                                                             const std::string& clip) {
  std::vector<std::pair<int, const aiNodeAnim*>> bound;
  std::vector<std::string> unbound, repeated;
  std::vector<std::uint8_t> seen(im.asset.skeleton.jointCount(), 0);
  for (unsigned c = 0; c < anim.mNumChannels; ++c) {
    const aiNodeAnim* channel = anim.mChannels[c];
    auto it = im.jointOfName.find(str(channel->mNodeName));
    if (it == im.jointOfName.end()) {
      unbound.push_back(str(channel->mNodeName));
    } else if (seen[it->second]) {
      repeated.push_back(it->first);
    } else {
      seen[it->second] = 1;
      bound.emplace_back(it->second, channel);
    }
  }
  if (!unbound.empty())
    im.warning("clip '" + clip + "': channels for " + quotedNameList(unbound) + " match no joint and were dropped");
  if (!repeated.empty())
    im.warning("clip '" + clip + "': joints " + quotedNameList(repeated) + " have several channels; the first is used");
  std::sort(bound.begin(), bound.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return bound;
}

double earliestKey(const std::vector<std::pair<int, const aiNodeAnim*>>& channels) {
  double first = std::numeric_limits<double>::infinity();
  auto scan = [&first](const auto* keys, unsigned count) {
    for (unsigned k = 0; k < count; ++k)
      if (std::isfinite(keys[k].mTime)) first = std::min(first, keys[k].mTime);
  };
  for (const auto& [joint, channel] : channels) {
    scan(channel->mPositionKeys, channel->mNumPositionKeys);
    scan(channel->mRotationKeys, channel->mNumRotationKeys);
    scan(channel->mScalingKeys, channel->mNumScalingKeys);
  }
  return std::isfinite(first) ? first : 0.0;
}

void reportKeyIssues(Importing& im, const std::string& clip, const KeyIssues& issues) {
  if (issues.unsorted)
    im.warning("clip '" + clip + "': " + std::to_string(issues.unsorted) +
               " tracks had keys out of time order; sorted");
  if (issues.conflictingDuplicates)
    im.warning("clip '" + clip + "': " + std::to_string(issues.conflictingDuplicates) +
               " keys share a time with a different value; the last of each was kept");
  if (issues.zeroRotations)
    im.warning("clip '" + clip + "': " + std::to_string(issues.zeroRotations) +
               " zero-length rotation keys were replaced by the identity");
}

void convertAnimation(Importing& im, const aiAnimation& anim, std::size_t index, std::set<std::string>& usedNames) {
  Clip clip;
  clip.name = uniqueClipName(im, anim, index, usedNames);
  if (anim.mNumMorphMeshChannels || anim.mNumMeshChannels)
    im.warning("clip '" + clip.name + "': " + std::to_string(anim.mNumMorphMeshChannels + anim.mNumMeshChannels) +
               " morph / mesh animation channels are not supported and were skipped");
  const auto channels = boundChannels(im, anim, clip.name);
  ChannelContext cc{{}, ticksPerSecond(im, anim, clip.name), earliestKey(channels), glm::mat4(1.0f)};
  // Clips start at 0: FBX takes and COLLADA animations often begin later (at the
  // take's start frame); the offset is reported as a note.
  if (cc.startTicks != 0.0)
    im.note("clip '" + clip.name + "' starts at " + std::to_string(cc.startTicks / cc.ticksPerSecond) +
            " s; its keys were shifted to start at 0");
  KeyIssues issues;
  for (const auto& [joint, channel] : channels) {
    cc.where = "clip '" + clip.name + "', joint '" + im.asset.skeleton.names[joint] + "'";
    cc.folded = im.foldedHelpers[joint];
    std::optional<JointTrack> track = convertChannel(im, *channel, joint, cc, issues);
    if (!track) return;  // the error is reported
    if (!track->translation.empty() || !track->rotation.empty() || !track->scale.empty())
      clip.tracks.push_back(std::move(*track));
  }
  reportKeyIssues(im, clip.name, issues);
  clip.updateDuration();
  im.asset.clips.push_back(std::move(clip));
}

void convertAnimations(Importing& im) {
  std::set<std::string> used;
  for (unsigned a = 0; a < im.scene.mNumAnimations; ++a) convertAnimation(im, *im.scene.mAnimations[a], a, used);
}

// ---------------------------------------------------------------- materials

std::string texturePath(Importing& im, const std::string& raw) {
  if (raw.empty()) return {};
  const auto [texture, index] = im.scene.GetEmbeddedTextureAndIndex(raw.c_str());
  if (texture) return "embedded:" + std::to_string(index);
  if (raw[0] == '*') {
    im.warning("texture '" + raw + "' refers to an embedded texture the file does not have");
    return {};
  }
  std::string portable = raw;
  std::replace(portable.begin(), portable.end(), '\\', '/');
  const fs::path written = fs::path(portable).lexically_normal();
  const fs::path folder = fs::path(im.path).parent_path();
  // Exporters often store the absolute path on the artist's machine ("D:/art/x.png"),
  // which is not absolute here; the texture then usually sits beside the asset.
  const bool windowsAbsolute = portable.size() > 2 && std::isalpha(static_cast<unsigned char>(portable[0])) &&
                               portable[1] == ':' && portable[2] == '/';
  const bool anywhere = im.options.allowFilesOutsideModelFolder;
  auto outside = [&] {
    im.warning("texture '" + raw +
               "' is outside the model's folder: no texture (ImportOptions::allowFilesOutsideModelFolder allows it)");
    return std::string();
  };
  if (!written.is_absolute() && !windowsAbsolute) {
    const fs::path file = (folder / written).lexically_normal();
    return anywhere || io_detail::insideFolder(file, folder) ? file.string() : outside();
  }
  std::error_code ec;
  const bool allowed = anywhere || io_detail::insideFolder(written, folder);
  if (allowed && !windowsAbsolute && fs::exists(written, ec)) return written.string();
  const fs::path beside = folder / written.filename();
  if (fs::exists(beside, ec)) return beside.string();
  return allowed ? written.string() : outside();
}

void convertMaterials(Importing& im) {
  for (unsigned i = 0; i < im.scene.mNumMaterials; ++i) {
    const aiMaterial& source = *im.scene.mMaterials[i];
    Material material;
    aiString name;
    if (source.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) material.name = str(name);
    aiColor4D color(1.0f, 1.0f, 1.0f, 1.0f);
    if (source.Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
        source.Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) {
      material.baseColor = {color.r, color.g, color.b, color.a};
      float opacity = 1.0f;
      if (source.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) material.baseColor.a *= opacity;
    }
    if (!isFinite(material.baseColor)) {
      im.error("material '" + material.name + "' has a non-finite colour");
      return;
    }
    aiString texture;
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      if (source.GetTextureCount(type) > 0 && source.GetTexture(type, 0, &texture) == AI_SUCCESS) {
        material.baseColorTexture = texturePath(im, str(texture));
        break;
      }
    }
    im.asset.materials.push_back(std::move(material));
  }
}

// ---------------------------------------------------------------- meshes

bool readVertices(Importing& im, const aiMesh& mesh, const std::string& where, MeshPrimitive& p) {
  const unsigned n = mesh.mNumVertices;
  p.positions.resize(n);
  for (unsigned v = 0; v < n; ++v) {
    p.positions[v] = toGlm(mesh.mVertices[v]) * im.scale;
    if (!isFinite(p.positions[v])) {
      im.error(where + ": vertex " + std::to_string(v) + " has a non-finite position");
      return false;
    }
  }
  if (mesh.HasNormals()) {
    // Assimp writes NaN normals for degenerate triangles it had to generate normals
    // for; such a vertex gets an arbitrary unit normal rather than failing the file.
    std::size_t replaced = 0;
    p.normals.resize(n);
    for (unsigned v = 0; v < n; ++v) {
      p.normals[v] = toGlm(mesh.mNormals[v]);
      if (!isFinite(p.normals[v])) {
        p.normals[v] = {0.0f, 1.0f, 0.0f};
        ++replaced;
      }
    }
    if (replaced) im.warning(where + ": " + std::to_string(replaced) + " non-finite normals replaced by +Y");
  }
  if (mesh.HasTextureCoords(0)) {
    p.uvs.resize(n);
    for (unsigned v = 0; v < n; ++v) {
      // Assimp puts the texture origin bottom-left; glTF (and Marionette's assets)
      // top-left.
      p.uvs[v] = {mesh.mTextureCoords[0][v].x, 1.0f - mesh.mTextureCoords[0][v].y};
      if (!isFinite(p.uvs[v])) {
        im.error(where + ": vertex " + std::to_string(v) + " has a non-finite texture coordinate");
        return false;
      }
    }
  }
  return true;
}

bool readTriangles(Importing& im, const aiMesh& mesh, const std::string& where, MeshPrimitive& p) {
  std::size_t skipped = 0;
  p.indices.reserve(std::size_t{mesh.mNumFaces} * 3);
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) {  // points and lines survive triangulation
      ++skipped;
      continue;
    }
    for (unsigned k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= mesh.mNumVertices) {
        im.error(where + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(face.mIndices[k]) +
                 " of " + std::to_string(mesh.mNumVertices));
        return false;
      }
      p.indices.push_back(face.mIndices[k]);
    }
  }
  if (skipped)
    im.warning(where + ": " + std::to_string(skipped) + " point / line faces skipped (only triangles are kept)");
  return true;
}

struct Influences {
  std::array<int, 4> joint{};
  std::array<float, 4> weight{};
  void add(int j, float w) {
    auto smallest = std::min_element(weight.begin(), weight.end());
    if (w <= *smallest) return;
    joint[static_cast<std::size_t>(smallest - weight.begin())] = j;
    *smallest = w;
  }
};

bool readSkin(Importing& im, const aiMesh& mesh, int nodeJoint, const std::string& where, MeshPrimitive& p) {
  std::vector<Influences> influences(mesh.mNumVertices);
  std::vector<std::string> unbound;
  for (unsigned b = 0; b < mesh.mNumBones; ++b) {
    const aiBone& bone = *mesh.mBones[b];
    auto it = im.jointOfName.find(str(bone.mName));
    if (it == im.jointOfName.end()) {
      unbound.push_back(str(bone.mName));
      continue;
    }
    for (unsigned w = 0; w < bone.mNumWeights; ++w) {
      const aiVertexWeight& vw = bone.mWeights[w];
      if (vw.mVertexId >= mesh.mNumVertices || !isFinite(vw.mWeight)) {
        im.error(where + ": bone '" + it->first + "' has an invalid weight (vertex " + std::to_string(vw.mVertexId) +
                 ", weight " + std::to_string(vw.mWeight) + ")");
        return false;
      }
      if (vw.mWeight > 0.0f) influences[vw.mVertexId].add(it->second, vw.mWeight);
    }
  }
  if (!unbound.empty())
    im.warning(where + ": bones " + quotedNameList(unbound) + " match no node; their weights were dropped");
  p.joints.resize(mesh.mNumVertices);
  p.weights.resize(mesh.mNumVertices);
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    Influences& in = influences[v];
    float sum = in.weight[0] + in.weight[1] + in.weight[2] + in.weight[3];
    if (!(sum > 0.0f)) {  // unweighted: follows the mesh's own node
      in = Influences{};
      in.joint[0] = nodeJoint;
      in.weight[0] = sum = 1.0f;
    }
    p.joints[v] = glm::u16vec4(in.joint[0], in.joint[1], in.joint[2], in.joint[3]);
    p.weights[v] = glm::vec4(in.weight[0], in.weight[1], in.weight[2], in.weight[3]) / sum;
  }
  return true;
}

int internMorphTarget(Asset& asset, Mesh& mesh, const std::string& name) {
  auto global = std::find(asset.morphTargets.begin(), asset.morphTargets.end(), name);
  const int index = static_cast<int>(global - asset.morphTargets.begin());
  if (global == asset.morphTargets.end()) asset.morphTargets.push_back(name);
  auto local = std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), index);
  if (local == mesh.morphTargets.end()) {
    mesh.morphTargets.push_back(index);
    return static_cast<int>(mesh.morphTargets.size()) - 1;
  }
  return static_cast<int>(local - mesh.morphTargets.begin());
}

void readMorphTargets(Importing& im, const aiMesh& source, const std::string& where, Mesh& mesh, MeshPrimitive& p) {
  for (unsigned k = 0; k < source.mNumAnimMeshes; ++k) {
    const aiAnimMesh& target = *source.mAnimMeshes[k];
    if (target.mNumVertices != source.mNumVertices) {
      im.warning(where + ": morph target " + std::to_string(k) + " has a different vertex count; skipped");
      continue;
    }
    std::string name = str(target.mName);
    if (name.empty()) name = str(source.mName) + "_morph_" + std::to_string(k);
    const std::size_t slot = static_cast<std::size_t>(internMorphTarget(im.asset, mesh, name));
    if (p.morphTargets.size() <= slot) p.morphTargets.resize(slot + 1);
    MorphTargetDelta& delta = p.morphTargets[slot];
    delta = {};
    for (unsigned v = 0; target.mVertices && v < source.mNumVertices; ++v)
      delta.positions.push_back((toGlm(target.mVertices[v]) - toGlm(source.mVertices[v])) * im.scale);
    for (unsigned v = 0; target.mNormals && source.mNormals && v < source.mNumVertices; ++v)
      delta.normals.push_back(toGlm(target.mNormals[v]) - toGlm(source.mNormals[v]));
    const bool ok = std::all_of(delta.positions.begin(), delta.positions.end(), [](auto d) { return isFinite(d); }) &&
                    std::all_of(delta.normals.begin(), delta.normals.end(), [](auto d) { return isFinite(d); });
    if (!ok) im.error(where + ": morph target '" + name + "' has non-finite values");
  }
}

bool convertPrimitive(Importing& im, const aiMesh& source, bool skinned, int nodeJoint, Mesh& mesh) {
  const std::string where = "mesh '" + mesh.name + "' (" + (source.mName.length ? str(source.mName) : "unnamed") + ")";
  MeshPrimitive p;
  if (!readVertices(im, source, where, p) || !readTriangles(im, source, where, p)) return false;
  if (p.indices.empty()) {
    im.warning(where + ": no triangles; skipped");
    return true;
  }
  if (skinned && !readSkin(im, source, nodeJoint, where, p)) return false;
  readMorphTargets(im, source, where, mesh, p);
  p.material = source.mMaterialIndex < im.asset.materials.size() ? static_cast<int>(source.mMaterialIndex) : -1;
  mesh.primitives.push_back(std::move(p));
  return true;
}

// Vertices stay in the mesh's own space: a node transform on an unskinned mesh is
// not applied (the skeleton has the node; a renderer can attach the mesh to it).
bool convertNodeMeshes(Importing& im, const aiNode& node) {
  Mesh mesh;
  mesh.name = str(node.mName);
  if (mesh.name.empty() && node.mMeshes[0] < im.scene.mNumMeshes)
    mesh.name = str(im.scene.mMeshes[node.mMeshes[0]]->mName);
  if (mesh.name.empty()) mesh.name = "mesh_" + std::to_string(im.asset.meshes.size());
  for (unsigned i = 0; i < node.mNumMeshes; ++i)
    if (node.mMeshes[i] < im.scene.mNumMeshes && im.scene.mMeshes[node.mMeshes[i]]->HasBones()) mesh.skinned = true;
  auto joint = im.jointOfNode.find(&node);
  const int nodeJoint = joint != im.jointOfNode.end() ? joint->second : 0;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] >= im.scene.mNumMeshes) {
      im.error("node '" + mesh.name + "' refers to mesh " + std::to_string(node.mMeshes[i]) + " of " +
               std::to_string(im.scene.mNumMeshes));
      return false;
    }
    if (!convertPrimitive(im, *im.scene.mMeshes[node.mMeshes[i]], mesh.skinned, nodeJoint, mesh)) return false;
  }
  // Every primitive lists the mesh's morph targets in the same order.
  for (MeshPrimitive& p : mesh.primitives) p.morphTargets.resize(mesh.morphTargets.size());
  if (!mesh.primitives.empty()) im.asset.meshes.push_back(std::move(mesh));
  return true;
}

bool convertMeshTree(Importing& im, const aiNode& node) {
  if (node.mNumMeshes > 0 && !convertNodeMeshes(im, node)) return false;
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (!convertMeshTree(im, *node.mChildren[i])) return false;
  return true;
}

void convertMeshes(Importing& im) {
  if (im.asset.skeleton.jointCount() > limits::kMaxJoints) {
    im.error("skeleton has " + std::to_string(im.asset.skeleton.jointCount()) +
             " joints, more than the 65535 a skeleton may have (limits::kMaxJoints)");
    return;
  }
  convertMaterials(im);
  convertMeshTree(im, *im.scene.mRootNode);
}

// ---------------------------------------------------------------- whole asset

void validate(Importing& im) {
  const Skeleton& skeleton = im.asset.skeleton;
  if (std::string e = skeleton.validate(); !e.empty()) im.error("skeleton: " + e);
  if (!isFinite(skeleton.rootTransform)) im.error("the scene root's transform is not finite");
  for (const Clip& clip : im.asset.clips)
    if (std::string e = clip.validate(skeleton.jointCount()); !e.empty()) im.error(e);
}

void convertScene(Importing& im) {
  im.asset.sourcePath = im.path;
  im.asset.unitScale = fileUnitScale(im) * im.options.extraScale;
  im.scale = im.asset.unitScale;
  buildSkeleton(im);
  if (!im.diag.ok()) return;
  if (im.options.loadAnimations) convertAnimations(im);
  if (im.options.loadMeshes && im.diag.ok()) convertMeshes(im);
  if (im.scene.mNumMeshes == 0 && im.scene.mNumAnimations == 0 && im.scene.mRootNode->mNumChildren == 0)
    im.warning("the file holds no meshes, no animations and no nodes besides the root");
  if (im.diag.ok()) validate(im);
}

// Reads the file once in a child process first: if Assimp crashes, hangs or
// runs out of memory there, the caller gets an error instead (isolated_call.hpp).
// The in-process read that follows is the same deterministic code on the same
// bytes, so it succeeds where the child did.
bool parsesInIsolation(const std::string& path, const ImportOptions& options, Diagnostics& diag) {
  const detail::IsolatedOutcome outcome = detail::runIsolated(
      [&] {
        Assimp::Importer importer;
        configure(importer);
        Diagnostics ignored;
        return readScene(importer, path, options.loadMeshes, ignored) ? 0 : 1;
      },
      options.parserTimeoutSeconds, options.parserMemoryLimitBytes);
  using Kind = detail::IsolatedOutcome::Kind;
  if (outcome.kind == Kind::Crashed || outcome.kind == Kind::TimedOut) {
    diag.error(path, "Assimp's reader " + outcome.describe(options.parserTimeoutSeconds) +
                         " on this file; it is malformed or too large, and nothing was loaded");
    return false;
  }
  return true;  // Completed (either way) or Unavailable: the in-process read reports the details
}

void importInto(ImportResult& result, const std::string& path, const ImportOptions& options) {
  Diagnostics& diag = result.diagnostics;
  if (!std::isfinite(options.extraScale) || options.extraScale <= 0.0f) {
    diag.error(path, "ImportOptions::extraScale must be a positive number, got " + std::to_string(options.extraScale));
    return;
  }
  if (!checkFile(path, diag)) return;
  if (options.isolateThirdPartyParsers && !parsesInIsolation(path, options, diag)) return;
  Assimp::Importer importer;
  configure(importer);
  const aiScene* scene = readScene(importer, path, options.loadMeshes, diag);
  if (!scene) return;
  Importing im{*scene, path, options, diag, {}, 1.0f, {}, {}, {}};
  convertScene(im);
  result.asset = std::move(im.asset);
}

}  // namespace

ImportResult importWithAssimp(const std::string& path, const ImportOptions& options) {
  ImportResult result;
  try {
    importInto(result, path, options);
  } catch (const std::exception& e) {
    result.diagnostics.error(path, std::string("import failed: ") + e.what());
  } catch (...) {
    result.diagnostics.error(path, "import failed with an unknown exception");
  }
  if (!result.diagnostics.ok()) result.asset.reset();
  return result;
}

}  // namespace marionette
