// glTF writer: clips. Each is cleaned (duplicate key times merged, rotations
// normalized) and checked, then written as an animation: a sampler and channel
// per joint track, weights channels for the meshes its morph tracks drive.
#include "marionette/core/finite.hpp"

#include <algorithm>
#include <cmath>

#include "gltf_writer_context.hpp"

namespace marionette::gltf_writer_detail {
namespace {

// What cleaning a clip changed, for one warning per clip.
struct ClipRepairs {
  std::size_t duplicateKeys = 0;
  std::size_t zeroQuaternions = 0;
  std::size_t nonUnitQuaternions = 0;
  std::string firstDuplicate;  // where the first duplicate key was, for the message
};

// Drops keys whose time equals the previous key's (the first is kept, as the
// importer does), with their value block of `stride` values. Left alone when
// the sizes disagree: Clip::validate then names the problem.
template <class T>
std::size_t dropDuplicateTimes(std::vector<float>& times, std::vector<T>& values, std::size_t stride) {
  if (stride == 0 || values.size() != times.size() * stride) return 0;
  std::size_t kept = 0, dropped = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (kept > 0 && times[k] == times[kept - 1]) {
      ++dropped;
      continue;
    }
    times[kept] = times[k];
    std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(k * stride), stride,
                values.begin() + static_cast<std::ptrdiff_t>(kept * stride));
    ++kept;
  }
  times.resize(kept);
  values.resize(kept * stride);
  return dropped;
}

template <class T>
std::size_t perKey(const Track<T>& t) {
  return t.interpolation == Interpolation::CubicSpline ? 3 : 1;
}

// The clip as it will be written: duplicate key times merged, rotation values
// normalized (cubic-spline tangents are not unit quaternions and stay as they are).
Clip cleanClip(const Clip& in, const Skeleton& skeleton, ClipRepairs& r) {
  Clip c = in;
  auto note = [&](std::size_t dropped, std::size_t joint, const char* what) {
    if (dropped > 0 && r.firstDuplicate.empty())
      r.firstDuplicate = std::string(what) + " of joint '" +
                         (joint < skeleton.jointCount() ? skeleton.names[joint] : std::to_string(joint)) + "'";
    r.duplicateKeys += dropped;
  };
  for (JointTrack& jt : c.tracks) {
    const auto j = static_cast<std::size_t>(jt.joint);
    note(dropDuplicateTimes(jt.translation.times, jt.translation.values, perKey(jt.translation)), j, "translation");
    note(dropDuplicateTimes(jt.rotation.times, jt.rotation.values, perKey(jt.rotation)), j, "rotation");
    note(dropDuplicateTimes(jt.scale.times, jt.scale.values, perKey(jt.scale)), j, "scale");
    const std::size_t per = perKey(jt.rotation);
    for (std::size_t i = per == 3 ? 1 : 0; i < jt.rotation.values.size(); i += per) {
      glm::quat& q = jt.rotation.values[i];
      if (!isFinite(q)) continue;  // reported as non-finite later
      const float len2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
      if (!(len2 > 1e-30f)) {
        ++r.zeroQuaternions;
      } else if (std::fabs(len2 - 1.0f) > 1e-4f) {
        ++r.nonUnitQuaternions;
      }
      q = safeNormalize(q);  // also rounds near-unit ones: the validator's tolerance is tight
    }
  }
  for (MorphTrack& m : c.morphTracks) {
    const std::size_t per = m.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const std::size_t dropped = dropDuplicateTimes(m.times, m.weights, per * m.targets.size());
    if (dropped > 0 && r.firstDuplicate.empty()) r.firstDuplicate = "a morph-weight track";
    r.duplicateKeys += dropped;
  }
  c.updateDuration();
  return c;
}

std::string clipDataProblem(const Clip& c) {
  for (const JointTrack& jt : c.tracks) {
    const bool ok = allFinite(jt.translation.values) && allFinite(jt.scale.values) &&
                    allFinite(jt.rotation.values);
    if (!ok) return "joint " + std::to_string(jt.joint) + " has non-finite key values";
    for (const auto* times : {&jt.translation.times, &jt.rotation.times, &jt.scale.times})
      if (!times->empty() && times->front() < 0.0f)
        return "joint " + std::to_string(jt.joint) + " has a negative key time (" + std::to_string(times->front()) +
               "); glTF animation times must be >= 0";
  }
  for (const MorphTrack& m : c.morphTracks) {
    if (!allFinite(m.weights)) return "a morph-weight track has non-finite weights";
    if (!m.times.empty() && m.times.front() < 0.0f) return "a morph-weight track has a negative key time";
  }
  return {};
}

const char* interpolationName(Interpolation i) {
  switch (i) {
    case Interpolation::Step:
      return "STEP";
    case Interpolation::CubicSpline:
      return "CUBICSPLINE";
    default:
      return "LINEAR";
  }
}

// A cubic spline needs two keys; a single key is written as STEP with its value.
template <class T>
Track<T> writable(const Track<T>& t) {
  if (t.interpolation != Interpolation::CubicSpline || t.keyCount() != 1) return t;
  Track<T> out;
  out.interpolation = Interpolation::Step;
  out.times = t.times;
  out.values = {t.values[1]};
  return out;
}

}  // namespace

bool Writer::prepareClips() {
  for (const Clip& in : clips_) {
    ClipRepairs r;
    Clip c = cleanClip(in, skeleton_, r);
    if (std::string e = c.validate(skeleton_.jointCount()); !e.empty()) {
      error("cannot write clip '" + in.name + "': " + e);
      continue;
    }
    if (std::string e = clipDataProblem(c); !e.empty()) {
      error("cannot write clip '" + in.name + "': " + e);
      continue;
    }
    if (r.duplicateKeys > 0)
      warning("clip '" + in.name + "': merged " + std::to_string(r.duplicateKeys) +
              " key(s) with the same time as the key before (first in the " + r.firstDuplicate +
              " track); the first key of each time is kept");
    if (r.zeroQuaternions > 0)
      warning("clip '" + in.name + "': " + std::to_string(r.zeroQuaternions) +
              " zero rotation key(s) written as the identity rotation");
    if (r.nonUnitQuaternions > 0)
      warning("clip '" + in.name + "': " + std::to_string(r.nonUnitQuaternions) +
              " non-unit rotation key(s) normalized");
    cleanClips_.push_back(std::move(c));
  }
  return ok_;
}

struct Writer::Channels {
  Json samplers = Json::array();
  Json channels = Json::array();
  void add(int node, const char* path, int input, int output, Interpolation interp) {
    samplers.push_back({{"input", input}, {"output", output}, {"interpolation", interpolationName(interp)}});
    channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
  }
};

void Writer::vec3Channel(Channels& ch, int node, const char* path, const Track<glm::vec3>& track) {
  if (track.empty()) return;
  const Track<glm::vec3> t = writable(track);
  ch.add(node, path, buffer_.scalars(t.times, true), buffer_.vec3s(t.values, 0, false), t.interpolation);
}

void Writer::rotationChannel(Channels& ch, int node, const Track<glm::quat>& track) {
  if (track.empty()) return;
  const Track<glm::quat> t = writable(track);
  std::vector<float> xyzw;
  xyzw.reserve(t.values.size() * 4);
  for (const glm::quat& q : t.values) xyzw.insert(xyzw.end(), {q.x, q.y, q.z, q.w});
  ch.add(node, "rotation", buffer_.scalars(t.times, true),
         buffer_.floats(xyzw.data(), t.values.size(), 4, "VEC4", 0, false), t.interpolation);
}

// Morph weights: a glTF weights channel drives one node's mesh and lists a
// weight for each of that mesh's targets. Each mesh with targets gets the
// weights of the track(s) covering them; targets no track covers are 0.
void Writer::morphChannels(Channels& ch, const Clip& clip) {
  std::vector<char> used(clip.morphTracks.size(), 0);
  for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
    const Mesh& mesh = asset_.meshes[m];
    if (meshNode_[m] < 0 || mesh.morphTargets.empty()) continue;
    std::vector<std::size_t> covering;
    for (std::size_t k = 0; k < clip.morphTracks.size(); ++k)
      for (int t : clip.morphTracks[k].targets)
        if (std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), t) != mesh.morphTargets.end()) {
          covering.push_back(k);
          break;
        }
    if (covering.empty()) continue;
    // Several tracks on one mesh merge when they share their keys; otherwise the first wins.
    const MorphTrack& first = clip.morphTracks[covering[0]];
    std::vector<std::size_t> merged;
    for (std::size_t k : covering) {
      used[k] = 1;
      const MorphTrack& t = clip.morphTracks[k];
      if (t.times == first.times && t.interpolation == first.interpolation)
        merged.push_back(k);
      else
        warning("clip '" + clip.name + "': mesh '" + mesh.name +
                "' is driven by morph-weight tracks with different key times; only the first is written for it");
    }
    const std::size_t per = first.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const std::size_t targets = mesh.morphTargets.size();
    std::vector<float> out(first.times.size() * per * targets, 0.0f);
    for (std::size_t k : merged) {
      const MorphTrack& t = clip.morphTracks[k];
      for (std::size_t s = 0; s < t.targets.size(); ++s) {
        auto it = std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), t.targets[s]);
        if (it == mesh.morphTargets.end()) continue;
        const auto slot = static_cast<std::size_t>(it - mesh.morphTargets.begin());
        // Values are key-major (and in/value/out-major within a cubic key), then target.
        for (std::size_t e = 0; e < first.times.size() * per; ++e)
          out[e * targets + slot] = t.weights[e * t.targets.size() + s];
      }
    }
    ch.add(meshNode_[m], "weights", buffer_.scalars(first.times, true), buffer_.scalars(out, false),
           first.interpolation);
  }
  const auto unused = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  if (unused > 0)
    warning("clip '" + clip.name + "': " + std::to_string(unused) +
            " morph-weight track(s) drive no written mesh; dropped");
}

void Writer::writeAnimations() {
  Json animations = Json::array();
  for (const Clip& clip : cleanClips_) {
    Channels ch;
    for (const JointTrack& jt : clip.tracks) {
      vec3Channel(ch, jt.joint, "translation", jt.translation);
      rotationChannel(ch, jt.joint, jt.rotation);
      vec3Channel(ch, jt.joint, "scale", jt.scale);
    }
    morphChannels(ch, clip);
    if (ch.channels.empty()) {
      warning("clip '" + clip.name + "' has no keys; not written (a glTF animation needs a channel)");
      continue;
    }
    animations.push_back({{"name", clip.name}, {"samplers", std::move(ch.samplers)}, {"channels", std::move(ch.channels)}});
    if (!clip.events.empty()) {  // read back by the importer (gltf_animation_events.hpp)
      Json events = Json::array();
      for (const ClipEvent& e : clip.events) events.push_back({{"time", e.time}, {"name", e.name}});
      animations.back()["extras"] = {{"events", std::move(events)}};
    }
  }
  if (!animations.empty()) doc_["animations"] = std::move(animations);
}

}  // namespace marionette::gltf_writer_detail
