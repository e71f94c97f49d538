// Private to the glTF importer: glTF animations to Clips.
#pragma once
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "gltf_animation_events.hpp"
#include "gltf_skeleton.hpp"
#include "marionette/animation/clip.hpp"

namespace marionette::gltf_detail {

// The keys of one channel: times and `width` floats per value (three values per
// key for CUBICSPLINE).
struct ChannelKeys {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;
  std::vector<float> values;
};

class ClipBuilder {
 public:
  ClipBuilder(const Context& ctx, const AccessorReader& reader, const SkeletonMap& map,
              const std::vector<std::vector<int>>& morphs)
      : ctx_(ctx), reader_(reader), map_(map), morphs_(morphs) {}

  std::optional<Clip> build(std::size_t a) const {
    const tinygltf::Animation& anim = ctx_.model.animations[a];
    Clip clip;
    clip.name = ctx_.animationName(a);
    std::map<int, JointTrack> tracks;  // by joint, so they come out sorted
    Outside outside;
    for (std::size_t c = 0; c < anim.channels.size(); ++c)
      if (!addChannel(a, c, clip, tracks, outside)) return std::nullopt;
    if (outside.count > 0)
      ctx_.warning("animation '" + clip.name + "': " + std::to_string(outside.count) +
                   " channel(s) animate nodes outside the skeleton (e.g. " + outside.example + "); ignored");
    for (auto& [joint, track] : tracks) clip.tracks.push_back(std::move(track));
    clip.updateDuration();
    readAnimationEvents(ctx_, a, clip);
    return clip;
  }

 private:
  const Context& ctx_;
  const AccessorReader& reader_;
  const SkeletonMap& map_;
  const std::vector<std::vector<int>>& morphs_;

  struct Outside {
    int count = 0;
    std::string example;
  };

  std::string channelLabel(std::size_t a, std::size_t c) const {
    return "animation '" + ctx_.animationName(a) + "' channel " + std::to_string(c);
  }

  bool addChannel(std::size_t a, std::size_t c, Clip& clip, std::map<int, JointTrack>& tracks, Outside& outside) const {
    const tinygltf::AnimationChannel& ch = ctx_.model.animations[a].channels[c];
    const std::string where = channelLabel(a, c);
    if (!Context::inRange(ch.target_node, ctx_.model.nodes)) {
      ctx_.warning(where + " has no target node in this file; ignored");
      return true;
    }
    const auto node = static_cast<std::size_t>(ch.target_node);
    if (ch.target_path == "weights") return addMorphChannel(a, c, node, clip);
    if (ch.target_path != "translation" && ch.target_path != "rotation" && ch.target_path != "scale") {
      ctx_.warning(where + " animates '" + ch.target_path + "', which is not supported; ignored");
      return true;
    }
    const int joint = map_.nodeToJoint[node];
    if (joint < 0) {
      if (outside.count++ == 0) outside.example = ctx_.nodeLabel(node);
      return true;
    }
    JointTrack& track = tracks[joint];
    track.joint = joint;
    return ch.target_path == "rotation"
               ? addRotation(a, c, track.rotation)
               : addVec3(a, c, ch.target_path == "translation" ? track.translation : track.scale,
                         ch.target_path == "translation");
  }

  bool addVec3(std::size_t a, std::size_t c, Track<glm::vec3>& track, bool isTranslation) const {
    if (!track.empty()) return duplicate(a, c);
    ChannelKeys keys;
    if (!readKeys(a, c, 3, {TINYGLTF_TYPE_VEC3}, IntegerMode::AsDeclared, keys)) return false;
    const float s = isTranslation ? ctx_.options.extraScale : 1.0f;
    track.interpolation = keys.interpolation;
    track.times = std::move(keys.times);
    for (std::size_t i = 0; i + 2 < keys.values.size(); i += 3)
      track.values.emplace_back(keys.values[i] * s, keys.values[i + 1] * s, keys.values[i + 2] * s);
    return true;
  }

  bool addRotation(std::size_t a, std::size_t c, Track<glm::quat>& track) const {
    if (!track.empty()) return duplicate(a, c);
    ChannelKeys keys;
    // KHR_mesh_quantization allows normalized byte/short rotations.
    if (!readKeys(a, c, 4, {TINYGLTF_TYPE_VEC4}, IntegerMode::Normalized, keys)) return false;
    track.interpolation = keys.interpolation;
    track.times = std::move(keys.times);
    for (std::size_t i = 0; i + 3 < keys.values.size(); i += 4) {
      // glTF stores x, y, z, w; glm::quat's constructor takes w, x, y, z.
      glm::quat q(keys.values[i + 3], keys.values[i], keys.values[i + 1], keys.values[i + 2]);
      // Cubic tangents are not unit quaternions; keep those (and their values) as stored.
      track.values.push_back(track.interpolation == Interpolation::CubicSpline ? q : safeNormalize(q));
    }
    return true;
  }

  bool addMorphChannel(std::size_t a, std::size_t c, std::size_t node, Clip& clip) const {
    const std::string where = channelLabel(a, c);
    const int mesh = ctx_.model.nodes[node].mesh;
    if (mesh < 0 || morphs_[static_cast<std::size_t>(mesh)].empty()) {
      ctx_.warning(where + " animates morph weights of " + ctx_.nodeLabel(node) +
                   ", which has no morph targets; ignored");
      return true;
    }
    const std::vector<int>& targets = morphs_[static_cast<std::size_t>(mesh)];
    ChannelKeys keys;
    if (!readKeys(a, c, targets.size(), {TINYGLTF_TYPE_SCALAR}, IntegerMode::Normalized, keys)) return false;
    MorphTrack track;
    track.interpolation = keys.interpolation;
    track.targets = targets;
    track.times = std::move(keys.times);
    track.weights = std::move(keys.values);
    clip.morphTracks.push_back(std::move(track));
    return true;
  }

  bool duplicate(std::size_t a, std::size_t c) const {
    ctx_.warning(channelLabel(a, c) + " animates a property that an earlier channel already animates; ignored");
    return true;
  }

  bool interpolation(const std::string& name, Interpolation& out) const {
    if (name == "LINEAR" || name.empty())
      out = Interpolation::Linear;
    else if (name == "STEP")
      out = Interpolation::Step;
    else if (name == "CUBICSPLINE")
      out = Interpolation::CubicSpline;
    else
      return false;
    return true;
  }

  // Reads a channel's sampler: times, and `width` floats per value.
  bool readKeys(std::size_t a, std::size_t c, std::size_t width, std::initializer_list<int> types, IntegerMode mode,
                ChannelKeys& keys) const {
    const tinygltf::Animation& anim = ctx_.model.animations[a];
    const tinygltf::AnimationChannel& ch = anim.channels[c];
    const std::string where = channelLabel(a, c);
    if (!Context::inRange(ch.sampler, anim.samplers)) {
      ctx_.error(where + " refers to sampler " + std::to_string(ch.sampler) + ", which does not exist");
      return false;
    }
    const tinygltf::AnimationSampler& sampler = anim.samplers[static_cast<std::size_t>(ch.sampler)];
    if (!interpolation(sampler.interpolation, keys.interpolation)) {
      ctx_.error(where + " has unknown interpolation '" + sampler.interpolation + "'");
      return false;
    }
    auto input = reader_.floats(sampler.input, where + " input", {TINYGLTF_TYPE_SCALAR});
    if (!input) return false;
    auto output = reader_.floats(sampler.output, where + " output", types, mode);
    if (!output) return false;
    const std::size_t per = keys.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const std::size_t expected = input->count * per * width;
    if (output->values.size() != expected) {
      ctx_.error(where + ": output " + AccessorReader::label(sampler.output, "") + " has " +
                 std::to_string(output->values.size()) + " numbers, expected " + std::to_string(expected) + " for " +
                 std::to_string(input->count) + " keys");
      return false;
    }
    return dropDuplicateTimes(where, input->values, output->values, per * width, keys);
  }

  // Key times must increase. Exact repeats (some exporters write them) are
  // dropped, keeping the first key; going back in time is an error.
  bool dropDuplicateTimes(const std::string& where, const std::vector<float>& times, const std::vector<float>& values,
                          std::size_t stride, ChannelKeys& keys) const {
    std::size_t dropped = 0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (k > 0 && times[k] < times[k - 1]) {
        ctx_.error(where + ": key " + std::to_string(k) + " time " + std::to_string(times[k]) +
                   " is before the previous key's " + std::to_string(times[k - 1]) + "; times must increase");
        return false;
      }
      if (k > 0 && times[k] == times[k - 1]) {
        ++dropped;
        continue;
      }
      keys.times.push_back(times[k]);
      keys.values.insert(keys.values.end(), values.begin() + static_cast<std::ptrdiff_t>(k * stride),
                         values.begin() + static_cast<std::ptrdiff_t>((k + 1) * stride));
    }
    if (dropped > 0)
      ctx_.warning(where + ": dropped " + std::to_string(dropped) + " key(s) with the same time as the key before");
    return true;
  }
};

// ---- the "merged" clip -------------------------------------------------------------

// Legacy exporters (COLLADA2GLTF; CesiumMan) write one glTF animation per joint
// where the author meant one motion. When all animations have no real name
// (empty, or "animation_3", "Take 001"-style), animate disjoint joints and share
// one time range, we keep the per-joint clips and also append their union as a
// clip named "merged", the clip a user actually wants to play.
inline bool genericName(const std::string& name) {
  std::string lower;
  for (char ch : name) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (const char* prefix : {"animation", "anim", "take", "default", "action"}) {
    const std::string p(prefix);
    if (lower.rfind(p, 0) != 0) continue;
    const std::string rest = lower.substr(p.size());
    if (std::all_of(rest.begin(), rest.end(), [](char ch) {
          return std::isdigit(static_cast<unsigned char>(ch)) || ch == '_' || ch == ' ' || ch == '-' || ch == '.';
        }))
      return true;
  }
  return name.empty();
}

inline float firstKeyTime(const Clip& clip) {
  float t = INFINITY;
  for (const JointTrack& jt : clip.tracks)
    for (const auto* times : {&jt.translation.times, &jt.rotation.times, &jt.scale.times})
      if (!times->empty()) t = std::min(t, times->front());
  for (const MorphTrack& m : clip.morphTracks)
    if (!m.times.empty()) t = std::min(t, m.times.front());
  return t;
}

inline bool shouldMerge(const Context& ctx, const std::vector<Clip>& clips) {
  if (clips.size() < 2 || clips.size() != ctx.model.animations.size()) return false;
  for (const auto& a : ctx.model.animations)
    if (!genericName(a.name)) return false;
  std::set<int> joints;
  const float start = firstKeyTime(clips[0]);
  for (const Clip& clip : clips) {
    if (clip.tracks.empty() || std::fabs(clip.duration - clips[0].duration) > 1e-3f ||
        std::fabs(firstKeyTime(clip) - start) > 1e-3f || !clip.morphTracks.empty())
      return false;
    for (const JointTrack& jt : clip.tracks)
      if (!joints.insert(jt.joint).second) return false;
  }
  return true;
}

inline void appendMergedClip(const Context& ctx, std::vector<Clip>& clips) {
  if (!shouldMerge(ctx, clips)) return;
  Clip merged;
  merged.name = "merged";
  for (const Clip& clip : clips) merged.tracks.insert(merged.tracks.end(), clip.tracks.begin(), clip.tracks.end());
  for (const Clip& clip : clips) merged.events.insert(merged.events.end(), clip.events.begin(), clip.events.end());
  std::stable_sort(merged.events.begin(), merged.events.end(),
                   [](const ClipEvent& x, const ClipEvent& y) { return x.time < y.time; });
  std::sort(merged.tracks.begin(), merged.tracks.end(),
            [](const JointTrack& x, const JointTrack& y) { return x.joint < y.joint; });
  merged.updateDuration();
  clips.push_back(std::move(merged));
}

}  // namespace marionette::gltf_detail
