// libFuzzer target: glTF JSON, GLB, VRM and VRMA bytes, read by importGltf (which takes
// a path: the input is written to a temporary .glb when it starts with the "glTF" magic,
// else .gltf) with the default options (no files outside the model's folder), and the same
// bytes by importAssetFromMemory through a file reader that has no other file. Contract:
// no crash; a failure has an error and every diagnostic names the file; a success holds a
// valid skeleton, clips and meshes (indices and joints in range) with finite numbers
// only, and sampling each clip gives a finite pose, also once prepared as a Rig does
// (optimized and compacted: the compact keys decode to a finite pose, four-wide and
// track by track alike). Built and run by scripts/fuzz.
#include <cstring>
#include <string_view>
#include <utility>

#include "fuzz_support.hpp"
#include "marionette/animation/animation_clip.hpp"
#include "marionette/animation/sampling.hpp"

namespace {

using namespace marionette;
using fuzz::finiteAll;
using fuzz::require;

void checkSkeleton(const Skeleton& s) {
  require(s.validate().empty(), "the skeleton does not validate");
  const std::size_t n = s.jointCount();
  require(s.names.size() == n && s.parents.size() == n && s.restPose.size() == n && s.inverseBind.size() == n,
          "skeleton arrays differ in size");
  for (std::size_t j = 0; j < n; ++j) {
    require(s.parents[j] < static_cast<int>(j), "a parent comes after its child");
    const Transform& t = s.restPose[j];
    for (int c = 0; c < 3; ++c)
      require(std::isfinite(t.translation[c]) && std::isfinite(t.scale[c]) && std::isfinite(t.rotation[c]),
              "rest pose not finite");
    require(std::isfinite(t.rotation.w), "rest rotation not finite");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) require(std::isfinite(s.inverseBind[j][c][r]), "inverse bind not finite");
  }
}

void checkMeshes(const Asset& a) {
  const std::size_t joints = a.skeleton.jointCount();
  for (const Mesh& mesh : a.meshes) {
    for (int m : mesh.morphTargets)
      require(m >= 0 && static_cast<std::size_t>(m) < a.morphTargets.size(), "mesh morph target out of range");
    require(mesh.joint < static_cast<int>(joints), "mesh attached to a joint out of range");
    for (const MeshPrimitive& p : mesh.primitives) {
      const std::size_t n = p.positions.size();
      require(finiteAll(p.positions) && finiteAll(p.normals) && finiteAll(p.uvs) && finiteAll(p.weights),
              "vertex data not finite");
      require((p.normals.empty() || p.normals.size() == n) && (p.uvs.empty() || p.uvs.size() == n),
              "vertex attribute count differs from POSITION");
      require(p.indices.size() % 3 == 0, "indices are not whole triangles");
      for (std::uint32_t i : p.indices) require(i < n, "vertex index out of range");
      require(p.joints.size() == p.weights.size(), "JOINTS and WEIGHTS differ in size");
      for (const glm::u16vec4& j : p.joints)
        for (int c = 0; c < 4; ++c) require(j[c] < joints || joints == 0, "skin joint out of range");
      require(p.material < static_cast<int>(a.materials.size()) || a.materials.empty(), "material out of range");
      for (const MorphTargetDelta& d : p.morphTargets)
        require(finiteAll(d.positions) && finiteAll(d.normals), "morph target not finite");
    }
  }
}

void checkClips(const Asset& a) {
  const Skeleton& s = a.skeleton;
  std::vector<Transform> pose(s.jointCount());
  std::vector<float> weights(a.morphTargets.size(), 0.0f);
  for (const Clip& clip : a.clips) {
    require(clip.validate(s.jointCount()).empty(), "a clip does not validate");
    require(std::isfinite(clip.duration) && clip.duration >= 0.0f, "clip duration not finite");
    for (const JointTrack& t : clip.tracks)
      require(finiteAll(t.translation.times) && finiteAll(t.translation.values) && finiteAll(t.rotation.times) &&
                  finiteAll(t.rotation.values) && finiteAll(t.scale.times) && finiteAll(t.scale.values),
              "clip keys not finite");
    for (const MorphTrack& m : clip.morphTracks) {
      require(finiteAll(m.times) && finiteAll(m.weights), "morph keys not finite");
      for (int target : m.targets)
        require(target >= 0 && static_cast<std::size_t>(target) < weights.size(), "morph track target out of range");
    }
    for (float time : {0.0f, clip.duration * 0.37f, clip.duration}) {
      sampleClip(clip, time, s.restPose, pose);
      sampleMorphWeights(clip, time, weights);
      for (const Transform& t : pose)
        require(std::isfinite(t.rotation.w) && std::isfinite(t.rotation.x) && std::isfinite(t.translation.x) &&
                    std::isfinite(t.scale.x),
                "sampled pose not finite");
      require(finiteAll(weights), "sampled morph weights not finite");
    }
    // As a Rig prepares it: optimized and compacted (or kept in float form, with a reason).
    const auto prepared = makeAnimationClip(clip, s);
    require(prepared->compaction.compacted == !prepared->compact.empty(), "compaction stats disagree with the clip");
    require(prepared->compaction.compacted || !prepared->compaction.reason.empty(), "a clip left uncompacted gives no reason");
    std::vector<Transform> scalar(s.jointCount());
    for (float time : {0.0f, clip.duration * 0.37f, clip.duration}) {
      sampleAnimationClip(*prepared, time, true, s.restPose, pose);
      for (const Transform& t : pose)
        require(std::isfinite(t.rotation.w) && std::isfinite(t.rotation.x) && std::isfinite(t.translation.x) &&
                    std::isfinite(t.scale.x),
                "sampled compact pose not finite");
      if (prepared->compact.empty()) continue;
      std::copy(s.restPose.begin(), s.restPose.end(), scalar.begin());
      std::copy(s.restPose.begin(), s.restPose.end(), pose.begin());
      sampleCompactClipTracks(prepared->compact, time, pose);
      sampleCompactClipTracksScalar(prepared->compact, time, scalar);
      require(std::memcmp(pose.data(), scalar.data(), pose.size() * sizeof(Transform)) == 0,
              "four-wide compact decoding differs from the definition");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = fuzz::writeInput(data, size, glb ? "in.glb" : "in.gltf");
  // From the disk, and from memory through an engine's reader that has no other file (the
  // reader path: FolderGuard by path, buffers and images asked of the reader).
  const std::string memoryName = glb ? "pak/in.glb" : "pak/in.gltf";
  ImportOptions throughReader;
  throughReader.readFile = [](const std::string&, std::string&, std::string& why) {
    why = "not in the archive";
    return false;
  };
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  for (const auto& [r, name] : {std::pair{importGltf(path, ImportOptions{}), path},
                                std::pair{importAssetFromMemory(bytes, memoryName, throughReader), memoryName}}) {
    if (!r.ok()) {
      require(!r.asset, "a failed import returned an asset");
      fuzz::requireNamedFailure(r.diagnostics, name);
      continue;
    }
    require(fuzz::allName(r.diagnostics, name), "a warning does not name the file");
    checkSkeleton(r.asset->skeleton);
    checkMeshes(*r.asset);
    checkClips(*r.asset);
  }
  return 0;
}
