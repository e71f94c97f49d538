// Assimp importer: clips. One Clip per aiAnimation, in seconds from 0: keys
// sorted and deduplicated, FBX helper transforms folded in, all-ones scale
// tracks dropped, channels bound to joints by name.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "assimp_conversion.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/text.hpp"

namespace marionette::assimp_detail {
namespace {

namespace fs = std::filesystem;

// What Assimp's own tools assume when a file gives no tick rate.
constexpr double kDefaultTicksPerSecond = 25.0;

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

}  // namespace

void convertAnimations(Importing& im) {
  std::set<std::string> used;
  for (unsigned a = 0; a < im.scene.mNumAnimations; ++a) convertAnimation(im, *im.scene.mAnimations[a], a, used);
}

}  // namespace marionette::assimp_detail
