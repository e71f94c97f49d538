#include "prt_lighting.hpp"

#include <cstdio>
#include <filesystem>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/prt/progress_bar.hpp"
#include "marionette/prt/transfer_cache.hpp"
#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::ar {

std::string PrtAsset::describe(const std::string& name) const {
  char line[256];
  std::snprintf(line, sizeof line, "prt %s: %zu vertices, %d bands, %s, ", name.c_str(), vertexCount,
                relighter.bands(), shadowed ? "shadowed" : "unshadowed");
  if (fromCache) return line + ("from cache " + cachePath);
  char cost[96];
  std::snprintf(cost, sizeof cost, "%.2f s, %llu rays", seconds, static_cast<unsigned long long>(rays));
  return line + std::string(cost);
}

namespace {

// The model matrices of `clip` at `time` (clamped into the clip), played in place as the
// locomotion plays it: the root's own travel and turn taken out (AnimationClip::inPlaceRoot).
std::vector<glm::mat4> clipPose(const Skeleton& skeleton, const AnimationClip& clip, float time) {
  const float t = wrapClipTime(time, clip.clip.duration, WrapMode::Clamp);
  std::vector<Transform> local(skeleton.jointCount());
  sampleClip(clip.clip, t, skeleton.restPose, local);
  if (!clip.inPlaceRoot.tracks.empty()) sampleClipTracks(clip.inPlaceRoot, t, local);
  std::vector<glm::mat4> model(skeleton.jointCount());
  localToModel(skeleton, local, model);
  return model;
}

}  // namespace

bool loadPrtAsset(const Asset& asset, const Rig& rig, const ArPrt& settings, const std::string& scenePath, PrtAsset& out,
                  Diagnostics& diagnostics) {
  prt::BindPoseOptions options;
  if (!settings.poseClip.empty()) {
    const auto clip = rig.findClip(settings.poseClip);
    if (!clip) {
      std::string names;
      for (const auto& c : rig.clips()) names += (names.empty() ? "" : ", ") + c->clip.name;
      diagnostics.error(scenePath, "'environment.prt.pose.clip': '" + settings.poseClip + "' is not a clip of " +
                                       asset.sourcePath + " (its clips: " + (names.empty() ? "none" : names) + ")");
      return false;
    }
    options.skinnedSpace = prt::SkinnedSpace::Posed;
    options.poseModel = clipPose(asset.skeleton, *clip, settings.poseTime);
  }
  const prt::TransferMesh mesh = prt::bindPoseMesh(asset, diagnostics, options);
  // bindPoseMesh's errors skip bad primitives (left out of the mesh, drawn with the SH9
  // light); only a mesh without a vertex is fatal here.
  if (mesh.positions.empty()) {
    diagnostics.error(asset.sourcePath, "no vertex to compute the transfer of");
    return false;
  }

  prt::TransferOptions transferOptions;
  transferOptions.bands = settings.bands;
  transferOptions.raysPerVertex = settings.rays;
  transferOptions.shadowed = settings.mode == PrtMode::Shadowed;
  const std::string name = std::filesystem::path(asset.sourcePath).filename().string();
  prt::CachedTransfer cached = prt::cachedTransfer(mesh, transferOptions, settings.cache, diagnostics,
                                                   prt::terminalProgressBar("prt " + name));
  if (cached.transfer.vertexCount() != mesh.positions.size()) {
    diagnostics.error(asset.sourcePath, "the transfer could not be computed");
    return false;
  }
  out.primitiveVertexOffset = mesh.primitiveVertexOffset;
  out.vertexCount = mesh.positions.size();
  out.relighter = prt::TransferRelighter(cached.transfer);
  out.shadowed = transferOptions.shadowed;
  out.fromCache = cached.fromCache;
  out.cachePath = cached.path;
  out.seconds = cached.stats.seconds;
  out.rays = cached.stats.rays;
  return true;
}

glm::dmat3 worldToModelRotation(const glm::mat4& world) noexcept {
  // Gram-Schmidt on the columns (model axes in world space); a degenerate matrix gives the identity.
  glm::dvec3 x(world[0]), y(world[1]);
  const double lx = glm::length(x);
  if (!(lx > 1e-12)) return glm::dmat3(1.0);
  x /= lx;
  y -= glm::dot(y, x) * x;
  const double ly = glm::length(y);
  if (!(ly > 1e-12)) return glm::dmat3(1.0);
  y /= ly;
  const glm::dvec3 z = glm::cross(x, y);
  // The model-from-world rotation is the transpose of the world-from-model one.
  return glm::transpose(glm::dmat3(x, y, z));
}

void PrtCharacterLight::relight(const prt::ShCoefficients& worldRadiance, const glm::mat4& world,
                                const prt::ShRotation& rotation) noexcept {
  // L_model(w) = L_world(R w) with R = world's rotation: ShRotation gives f(M^-1 w), so M = R^T.
  rotation.rotate(worldToModelRotation(world), worldRadiance, modelRadiance_);
  asset_->relighter.relight(modelRadiance_, irradiance_);
}

}  // namespace marionette::ar
