// compare_ozz: the per-character cost of Marionette's runtime (what marionette_bench's
// Runtime/Sample1 and Runtime/Blend3 measure) against ozz-animation on the same data.
//
// Marionette: exactly tests/bench/runtime_bench.cpp (loadBenchAsset, fillScene,
// runtimeBench): 1000 characters in a Scene, one clip at weight 1 (Sample1) or three
// at 0.5/0.3/0.2 (Blend3), character i starting at 0.013*i s, Scene::update(1/60).
//
// ozz: a RawSkeleton made from the Rig's Skeleton, RawAnimations from the importer's
// clips (not the Rig's optimized copies), reduced by AnimationOptimizer at its default
// setting and at that setting / 100, built by AnimationBuilder. Per character: one
// SamplingJob::Context per animation, SoA local buffers, BlendingJob (Blend3),
// LocalToModelJob (root = Skeleton::rootTransform, as Marionette's localToModel), and
// the palette model * inverseBind; its own clock, looping as WrapMode::Loop.
//
// Timing is interleaved in this process: per round, Marionette F frames, then each ozz
// variant F frames (one untimed frame before each). Also printed: animation sizes,
// per-character runtime state and the model-space error of virtual vertices against
// the raw clip sampled by Marionette.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <time.h>

#include <marionette/animation/clip_binding.hpp>
#include <marionette/animation/pose.hpp>
#include <marionette/animation/sampling.hpp>
#include <marionette/io/import.hpp>
#include <marionette/scene/scene.hpp>

#include <ozz/animation/offline/animation_builder.h>
#include <ozz/animation/offline/animation_optimizer.h>
#include <ozz/animation/offline/raw_animation.h>
#include <ozz/animation/offline/raw_skeleton.h>
#include <ozz/animation/offline/skeleton_builder.h>
#include <ozz/animation/runtime/animation.h>
#include <ozz/animation/runtime/blending_job.h>
#include <ozz/animation/runtime/local_to_model_job.h>
#include <ozz/animation/runtime/sampling_job.h>
#include <ozz/animation/runtime/skeleton.h>
#include <ozz/base/containers/vector.h>
#include <ozz/base/maths/simd_math.h>
#include <ozz/base/maths/soa_transform.h>
#include <ozz/base/memory/unique_ptr.h>
#include <ozz/base/span.h>

namespace mar = marionette;
namespace oa = ozz::animation;
namespace om = ozz::math;

namespace {

constexpr int kCharacters = 1000;
constexpr double kDt = 1.0 / 60.0;
constexpr float kVertexDistance = 0.03f;  // virtual vertices 3 cm from each joint
constexpr int kAccuracySamples = 60;      // evenly spaced times per clip

inline void escape(const void* p) { asm volatile("" : : "g"(p) : "memory"); }

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// This thread's CPU seconds and involuntary context switches: wall time well above CPU
// time means something else ran on the core during a timed run.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
long involuntarySwitches() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return u.ru_nivcsw;
}

struct Timed {
  double wall = 0.0, cpu = 0.0;  // seconds
  long preempted = 0;            // involuntary context switches
};

// Runs `run(1)` untimed (brings this side's data back into cache after the other side
// ran), then times `run(frames)`.
template <class F>
Timed timeFrames(F&& run, long frames) {
  run(1);
  const long sw0 = involuntarySwitches();
  const double c0 = threadCpuSeconds();
  const auto t0 = Clock::now();
  run(frames);
  Timed t;
  t.wall = seconds(t0, Clock::now());
  t.cpu = threadCpuSeconds() - c0;
  t.preempted = involuntarySwitches() - sw0;
  return t;
}

// ---------------------------------------------------------------------------------------
// Marionette side: runtime_bench.cpp's loadBenchAsset, plus the clips it hands the Rig.

struct BenchAsset {
  std::string name;
  std::shared_ptr<const mar::Rig> rig;
  std::vector<std::string> clips;  // three clip names to play
  std::vector<mar::Clip> rawClips;  // the same clips as imported, bound to the rig's skeleton, not optimized
  std::string error;
};

BenchAsset loadBenchAsset(const std::string& which, const std::string& sharedDir) {
  auto shared = [&](const std::string& rel) { return sharedDir + "/assets/" + rel; };
  BenchAsset b;
  b.name = which;
  mar::ImportOptions noMesh;
  noMesh.loadMeshes = false;
  if (which == "Pab") {
    mar::ImportResult r = mar::importAsset(shared("characters/pab_arnaud.fbx"), noMesh);
    if (!r.ok()) return b.error = r.diagnostics.format(), b;
    auto asset = std::make_shared<mar::Asset>(std::move(*r.asset));
    auto rig = std::make_shared<mar::Rig>(asset);
    for (const char* m : {"walk", "jog", "crossarms"}) {
      mar::ImportResult c = mar::importAsset(shared(std::string("motions/fbx/pab_") + m + ".fbx"), noMesh);
      if (!c.ok() || c.asset->clips.empty()) return b.error = c.diagnostics.format(), b;
      rig->addClip(c.asset->clips.front(), c.asset->skeleton, m);
      b.clips.push_back(m);
      // What addClip optimizes: the clip bound by name to the character's skeleton.
      mar::Clip raw = mar::bindClipByName(c.asset->clips.front(), c.asset->skeleton, asset->skeleton);
      raw.name = m;
      b.rawClips.push_back(std::move(raw));
    }
    b.rig = rig;
  } else if (which == "RobotExpressive") {
    mar::ImportResult r = mar::importAsset(shared("characters/RobotExpressive.glb"), noMesh);
    if (!r.ok()) return b.error = r.diagnostics.format(), b;
    auto asset = std::make_shared<mar::Asset>(std::move(*r.asset));
    b.rig = std::make_shared<mar::Rig>(asset);
    b.clips = {"Idle", "Walking", "Running"};
    for (const std::string& name : b.clips) {
      auto it = std::find_if(asset->clips.begin(), asset->clips.end(), [&](const mar::Clip& c) { return c.name == name; });
      if (it == asset->clips.end()) return b.error = "no clip " + name, b;
      b.rawClips.push_back(*it);
    }
  } else {
    b.error = "unknown asset " + which + " (RobotExpressive or Pab)";
  }
  return b;
}

// runtime_bench.cpp's fillScene.
void fillScene(mar::Scene& scene, const std::shared_ptr<const mar::Rig>& rig, const std::vector<std::string>& clips,
               int count, int layers) {
  const float weights[3] = {0.5f, 0.3f, 0.2f};
  for (int i = 0; i < count; ++i) {
    mar::Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    for (int l = 0; l < layers; ++l) {
      mar::PlayOptions o;
      o.weight = layers == 1 ? 1.0f : weights[l];
      o.startTime = 0.013 * i;  // each character at its own time: no shared cache lines
      c->play(l, clips[l], o);
    }
  }
  scene.update(1.0 / 60.0);  // warm-up
}

// ---------------------------------------------------------------------------------------
// ozz side, built from the same data.

om::Float4x4 toOzz(const glm::mat4& m) {
  om::Float4x4 r;
  for (int c = 0; c < 4; ++c) r.cols[c] = om::simd_float4::LoadPtrU(&m[c][0]);
  return r;
}

glm::mat4 toGlm(const om::Float4x4& m) {
  glm::mat4 r;
  for (int c = 0; c < 4; ++c) om::StorePtrU(m.cols[c], &r[c][0]);
  return r;
}

om::Transform toOzz(const mar::Transform& t) {
  return {om::Float3(t.translation.x, t.translation.y, t.translation.z),
          om::Quaternion(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w),
          om::Float3(t.scale.x, t.scale.y, t.scale.z)};
}

struct OzzRig {
  ozz::unique_ptr<oa::Skeleton> skeleton;
  std::vector<int> ozzToMar, marToOzz;  // ozz orders joints depth-first, Marionette parents-first
  om::Float4x4 root;                    // Skeleton::rootTransform
  ozz::vector<om::Float4x4> inverseBind;  // in ozz's joint order
};

void addRawJoint(const mar::Skeleton& s, const std::vector<std::vector<int>>& children, int j,
                 oa::offline::RawSkeleton::Joint& out, std::vector<int>& order) {
  order.push_back(j);
  out.name = s.names[static_cast<std::size_t>(j)].c_str();
  out.transform = toOzz(s.restPose[static_cast<std::size_t>(j)]);
  const std::vector<int>& kids = children[static_cast<std::size_t>(j)];
  out.children.resize(kids.size());
  for (std::size_t k = 0; k < kids.size(); ++k) addRawJoint(s, children, kids[k], out.children[k], order);
}

OzzRig makeOzzRig(const mar::Skeleton& s) {
  const std::size_t n = s.jointCount();
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (std::size_t j = 0; j < n; ++j) (s.parents[j] < 0 ? roots : children[static_cast<std::size_t>(s.parents[j])]).push_back(static_cast<int>(j));
  oa::offline::RawSkeleton raw;
  OzzRig r;
  raw.roots.resize(roots.size());
  for (std::size_t k = 0; k < roots.size(); ++k) addRawJoint(s, children, roots[k], raw.roots[k], r.ozzToMar);
  if (!raw.Validate()) throw std::runtime_error("RawSkeleton::Validate failed");
  r.skeleton = oa::offline::SkeletonBuilder()(raw);
  if (!r.skeleton) throw std::runtime_error("SkeletonBuilder failed");
  // SkeletonBuilder numbers joints in RawSkeleton::IterateJointsDF order, which is the
  // preorder addRawJoint recorded; check it against the built parents.
  r.marToOzz.assign(n, -1);
  for (std::size_t o = 0; o < n; ++o) r.marToOzz[static_cast<std::size_t>(r.ozzToMar[o])] = static_cast<int>(o);
  const auto parents = r.skeleton->joint_parents();
  if (parents.size() != n) throw std::runtime_error("ozz skeleton joint count differs");
  for (std::size_t o = 0; o < n; ++o) {
    const int mp = s.parents[static_cast<std::size_t>(r.ozzToMar[o])];
    if ((mp < 0 ? -1 : r.marToOzz[static_cast<std::size_t>(mp)]) != parents[o]) throw std::runtime_error("joint map mismatch");
  }
  r.root = toOzz(s.rootTransform);
  r.inverseBind.resize(n);
  for (std::size_t o = 0; o < n; ++o) r.inverseBind[o] = toOzz(s.inverseBind[static_cast<std::size_t>(r.ozzToMar[o])]);
  return r;
}

struct ConversionNotes {
  int stepTracks = 0, cubicTracks = 0, restFilled = 0;
};

// Keys of one Marionette track as ozz linear keys. Step keys get a hold key just before
// the next one; CubicSpline keys keep their values (tangents dropped).
template <class Key, class T, class F>
void convertTrack(const mar::Track<T>& t, const T& rest, float duration, F&& value, std::vector<Key>& keys,
                  ConversionNotes& notes) {
  keys.clear();
  if (t.empty()) {
    keys.push_back({0.0f, value(rest)});
    ++notes.restFilled;
    return;
  }
  const std::size_t stride = t.interpolation == mar::Interpolation::CubicSpline ? 3 : 1;
  const std::size_t offset = t.interpolation == mar::Interpolation::CubicSpline ? 1 : 0;
  notes.stepTracks += t.interpolation == mar::Interpolation::Step;
  notes.cubicTracks += t.interpolation == mar::Interpolation::CubicSpline;
  for (std::size_t k = 0; k < t.times.size(); ++k) {
    const T& v = t.values[k * stride + offset];
    keys.push_back({std::clamp(t.times[k], 0.0f, duration), value(v)});
    if (t.interpolation == mar::Interpolation::Step && k + 1 < t.times.size()) {
      const float hold = std::nextafter(t.times[k + 1], t.times[k]);
      if (hold > t.times[k]) keys.push_back({hold, value(v)});
    }
  }
}

oa::offline::RawAnimation makeRawAnimation(const mar::Clip& clip, const mar::Skeleton& s, const OzzRig& r,
                                           ConversionNotes& notes) {
  using RA = oa::offline::RawAnimation;
  RA raw;
  raw.name = clip.name.c_str();
  raw.duration = clip.duration > 0.0f ? clip.duration : 1.0f;
  const std::size_t n = s.jointCount();
  raw.tracks.resize(n);
  std::vector<const mar::JointTrack*> byJoint(n, nullptr);
  for (const mar::JointTrack& t : clip.tracks)
    if (t.joint >= 0 && static_cast<std::size_t>(t.joint) < n) byJoint[static_cast<std::size_t>(t.joint)] = &t;
  const mar::JointTrack none;
  std::vector<RA::TranslationKey> tk;
  std::vector<RA::RotationKey> rk;
  std::vector<RA::ScaleKey> sk;
  for (std::size_t j = 0; j < n; ++j) {
    const mar::JointTrack& t = byJoint[j] ? *byJoint[j] : none;
    const mar::Transform& rest = s.restPose[j];
    auto v3 = [](const glm::vec3& v) { return om::Float3(v.x, v.y, v.z); };
    auto q = [](const glm::quat& v) { return om::Quaternion(v.x, v.y, v.z, v.w); };
    convertTrack(t.translation, rest.translation, raw.duration, v3, tk, notes);
    convertTrack(t.rotation, rest.rotation, raw.duration, q, rk, notes);
    convertTrack(t.scale, rest.scale, raw.duration, v3, sk, notes);
    RA::JointTrack& out = raw.tracks[static_cast<std::size_t>(r.marToOzz[j])];
    out.translations.assign(tk.begin(), tk.end());
    out.rotations.assign(rk.begin(), rk.end());
    out.scales.assign(sk.begin(), sk.end());
  }
  if (!raw.Validate()) throw std::runtime_error("RawAnimation::Validate failed for " + clip.name);
  return raw;
}

// One ozz build of the three clips.
struct OzzVariant {
  std::string label;  // "ozz raw", "ozz 1mm/10cm", ...
  bool optimized = false;
  float tolerance = 0.0f, distance = 0.0f;
  std::vector<ozz::unique_ptr<oa::Animation>> animations;
};

OzzVariant makeVariant(const std::string& label, const std::vector<oa::offline::RawAnimation>& raws, const OzzRig& r,
                       bool optimize, float tolerance, float distance) {
  OzzVariant v;
  v.label = label;
  v.optimized = optimize;
  v.tolerance = tolerance;
  v.distance = distance;
  for (const auto& raw : raws) {
    oa::offline::RawAnimation optimized;
    const oa::offline::RawAnimation* source = &raw;
    if (optimize) {
      oa::offline::AnimationOptimizer optimizer;
      optimizer.setting = oa::offline::AnimationOptimizer::Setting(tolerance, distance);
      if (!optimizer(raw, *r.skeleton, &optimized)) throw std::runtime_error("AnimationOptimizer failed");
      source = &optimized;
    }
    oa::offline::AnimationBuilder builder;  // default: no iframes (iframe_interval 0)
    auto a = builder(*source);
    if (!a) throw std::runtime_error("AnimationBuilder failed");
    v.animations.push_back(std::move(a));
  }
  return v;
}

// Per-character ozz state: a context per animation, SoA local poses, model matrices, palette.
struct OzzCharacter {
  double time = 0.0;
  ozz::unique_ptr<oa::SamplingJob::Context> contexts[3];
  ozz::vector<om::SoaTransform> locals[3];
  ozz::vector<om::SoaTransform> blended;  // Blend3 only
  ozz::vector<om::Float4x4> model, palette;
};

// What SamplingJob::Context::Resize allocates for `tracks` tracks (sampling_job.cc):
// per SoA track two InterpSoaFloat3 (128 B), one InterpSoaQuaternion (160 B), 3*4 cache
// entries (48 B), plus 3 "outdated" bit bytes per 8 SoA tracks.
std::size_t contextBytes(int tracks) {
  const std::size_t soa = static_cast<std::size_t>((tracks + 3) / 4);
  return soa * (2 * (2 * 16 + 2 * sizeof(om::SoaFloat3)) + (2 * 16 + 2 * sizeof(om::SoaQuaternion)) + 3 * 4 * 4) +
         3 * ((soa + 7) / 8);
}

class OzzCrowd {
 public:
  OzzCrowd(const OzzRig& rig, const OzzVariant& variant, int count, int layers)
      : rig_(rig), variant_(variant), layers_(layers), characters_(static_cast<std::size_t>(count)) {
    const int joints = rig.skeleton->num_joints(), soa = rig.skeleton->num_soa_joints();
    for (int i = 0; i < count; ++i) {
      OzzCharacter& c = characters_[static_cast<std::size_t>(i)];
      c.time = 0.013 * i;
      for (int l = 0; l < layers; ++l) {
        c.contexts[l] = ozz::make_unique<oa::SamplingJob::Context>(variant.animations[static_cast<std::size_t>(l)]->num_tracks());
        c.locals[l].resize(static_cast<std::size_t>(soa));
      }
      if (layers > 1) c.blended.resize(static_cast<std::size_t>(soa));
      c.model.resize(static_cast<std::size_t>(joints));
      c.palette.resize(static_cast<std::size_t>(joints));
    }
    update(kDt);  // warm-up, as fillScene
  }

  void update(double dt) {
    static const float weights[3] = {0.5f, 0.3f, 0.2f};
    const std::size_t joints = static_cast<std::size_t>(rig_.skeleton->num_joints());
    for (OzzCharacter& c : characters_) {
      c.time += dt;
      oa::BlendingJob::Layer blendLayers[3];
      for (int l = 0; l < layers_; ++l) {
        const oa::Animation& a = *variant_.animations[static_cast<std::size_t>(l)];
        const double d = a.duration();  // WrapMode::Loop, as wrapClipTime
        double t = std::fmod(c.time, d);
        if (t < 0.0) t += d;
        oa::SamplingJob sampling;
        sampling.animation = &a;
        sampling.context = c.contexts[l].get();
        sampling.ratio = static_cast<float>(std::min(t, d) / d);
        sampling.output = ozz::make_span(c.locals[l]);
        sampling.Run();
        blendLayers[l].weight = weights[l];
        blendLayers[l].transform = ozz::make_span(c.locals[l]);
      }
      oa::LocalToModelJob ltm;
      ltm.skeleton = rig_.skeleton.get();
      ltm.root = &rig_.root;
      if (layers_ > 1) {
        oa::BlendingJob blend;
        blend.layers = ozz::span<const oa::BlendingJob::Layer>(blendLayers, static_cast<std::size_t>(layers_));
        blend.rest_pose = rig_.skeleton->joint_rest_poses();
        blend.output = ozz::make_span(c.blended);
        blend.Run();
        ltm.input = ozz::make_span(c.blended);
      } else {
        ltm.input = ozz::make_span(c.locals[0]);
      }
      ltm.output = ozz::make_span(c.model);
      ltm.Run();
      for (std::size_t j = 0; j < joints; ++j) c.palette[j] = c.model[j] * rig_.inverseBind[j];
    }
    escape(characters_.front().palette.data());
  }

  // Bytes of runtime state per character, by part.
  struct State {
    std::size_t contexts = 0, locals = 0, blended = 0, model = 0, palette = 0, other = 0;
    std::size_t total() const { return contexts + locals + blended + model + palette + other; }
  };
  State state() const {
    const OzzCharacter& c = characters_.front();
    State s;
    for (int l = 0; l < layers_; ++l) {
      s.contexts += sizeof(oa::SamplingJob::Context) + contextBytes(c.contexts[l]->max_tracks());
      s.locals += c.locals[l].capacity() * sizeof(om::SoaTransform);
    }
    s.blended = c.blended.capacity() * sizeof(om::SoaTransform);
    s.model = c.model.capacity() * sizeof(om::Float4x4);
    s.palette = c.palette.capacity() * sizeof(om::Float4x4);
    s.other = sizeof(OzzCharacter);
    return s;
  }

 private:
  const OzzRig& rig_;
  const OzzVariant& variant_;
  int layers_;
  std::vector<OzzCharacter> characters_;
};

// ---------------------------------------------------------------------------------------
// Sizes and state.

template <class T>
std::size_t trackBytes(const mar::Track<T>& t) {
  return t.times.size() * sizeof(float) + t.values.size() * sizeof(T);
}

std::size_t clipKeyBytes(const mar::Clip& c) {
  std::size_t b = 0;
  for (const mar::JointTrack& t : c.tracks) b += trackBytes(t.translation) + trackBytes(t.rotation) + trackBytes(t.scale);
  for (const mar::MorphTrack& m : c.morphTracks) b += (m.times.size() + m.weights.size()) * sizeof(float);
  return b;
}

std::size_t clipKeys(const mar::Clip& c) {
  std::size_t k = 0;
  for (const mar::JointTrack& t : c.tracks) k += t.translation.keyCount() + t.rotation.keyCount() + t.scale.keyCount();
  return k;
}

// Per-character heap Marionette's Character allocates (character.cpp): the local pose,
// the TransformBuffer (skinning + model matrices, morph weights), the morph scratch,
// and two SamplingCursors per playing layer (3 keys per joint track + 1 per morph track
// of the clip and of its inPlaceRoot). Not counted: the scene's shared FrameScratch,
// the Scene's unique_ptr, the name (short: in the string), allocator overhead.
struct MarionetteState {
  std::size_t object = 0, pose = 0, buffer = 0, morphs = 0, cursors = 0;
  std::size_t total() const { return object + pose + buffer + morphs + cursors; }
};

MarionetteState marionetteState(const mar::Character& c, const std::vector<std::shared_ptr<const mar::AnimationClip>>& played) {
  MarionetteState s;
  s.object = sizeof(mar::Character);
  s.pose = c.localPose().size() * sizeof(mar::Transform);
  const mar::TransformBuffer& b = c.transformBuffer();
  s.buffer = (b.skinningMatrices().size() + b.modelMatrices().size()) * sizeof(glm::mat4) + b.skinning3x4().size() * sizeof(float) +
             b.morphCount() * sizeof(float);
  s.morphs = c.rig().morphTargets().size() * sizeof(float);
  for (const auto& ac : played) {
    s.cursors += (ac->clip.tracks.size() * 3 + ac->clip.morphTracks.size()) * sizeof(std::uint32_t);
    s.cursors += (ac->inPlaceRoot.tracks.size() * 3 + ac->inPlaceRoot.morphTracks.size()) * sizeof(std::uint32_t);
  }
  return s;
}

// ---------------------------------------------------------------------------------------
// Accuracy: model-space positions of virtual vertices at +-3 cm along each joint's axes,
// against the raw clip sampled by Marionette (sampleClip + localToModel).

struct ErrorStats {
  float max = 0.0f, p99 = 0.0f, mean = 0.0f;
  std::string worstClip;
  int worstJoint = -1;
  float worstTime = 0.0f;
};

ErrorStats summarize(std::vector<float>& errors, const std::vector<std::string>& clipOf, const std::vector<int>& jointOf,
                     const std::vector<float>& timeOf) {
  ErrorStats s;
  if (errors.empty()) return s;
  const auto worst = std::max_element(errors.begin(), errors.end()) - errors.begin();
  s.max = errors[static_cast<std::size_t>(worst)];
  s.worstClip = clipOf[static_cast<std::size_t>(worst)];
  s.worstJoint = jointOf[static_cast<std::size_t>(worst)];
  s.worstTime = timeOf[static_cast<std::size_t>(worst)];
  double sum = 0.0;
  for (float e : errors) sum += e;
  s.mean = static_cast<float>(sum / static_cast<double>(errors.size()));
  const std::size_t k = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(errors.size()))) - 1;
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(k), errors.end());
  s.p99 = errors[k];
  return s;
}

// Per joint, the uniform scale of its rest model matrix (cube root of the determinant).
std::vector<float> restModelScales(const mar::Skeleton& s) {
  std::vector<float> out;
  for (const glm::mat4& m : s.restModelMatrices()) out.push_back(std::cbrt(std::fabs(glm::determinant(glm::mat3(m)))));
  return out;
}

// `modelAt(clip, time, out)` writes Marionette-ordered model matrices.
ErrorStats measureError(const BenchAsset& b, const std::function<void(std::size_t, float, std::vector<glm::mat4>&)>& modelAt) {
  const mar::Skeleton& s = b.rig->skeleton();
  const std::size_t n = s.jointCount();
  // 3 cm in model space: joint space is scaled by the joint's rest model scale (100 under
  // RobotExpressive's root transform), so the offsets are divided by it.
  const std::vector<float> scale = restModelScales(s);
  std::vector<mar::Transform> pose(n);
  std::vector<glm::mat4> ref(n), got(n);
  std::vector<float> errors;
  std::vector<std::string> clipOf;
  std::vector<int> jointOf;
  std::vector<float> timeOf;
  for (std::size_t c = 0; c < b.rawClips.size(); ++c) {
    const mar::Clip& raw = b.rawClips[c];
    for (int k = 0; k < kAccuracySamples; ++k) {
      const float t = raw.duration * static_cast<float>(k) / static_cast<float>(kAccuracySamples);
      mar::sampleClip(raw, t, s.restPose, pose);
      mar::localToModel(s, pose, ref);
      modelAt(c, t, got);
      for (std::size_t j = 0; j < n; ++j)
        for (int axis = 0; axis < 6; ++axis) {
          glm::vec4 o(0.0f, 0.0f, 0.0f, 1.0f);
          o[axis / 2] = (axis % 2 ? -kVertexDistance : kVertexDistance) / scale[j];
          errors.push_back(glm::length(glm::vec3(ref[j] * o) - glm::vec3(got[j] * o)));
          clipOf.push_back(raw.name);
          jointOf.push_back(static_cast<int>(j));
          timeOf.push_back(t);
        }
    }
  }
  return summarize(errors, clipOf, jointOf, timeOf);
}

ErrorStats marionetteError(const BenchAsset& b) {
  const mar::Skeleton& s = b.rig->skeleton();
  std::vector<mar::Transform> pose(s.jointCount());
  return measureError(b, [&](std::size_t c, float t, std::vector<glm::mat4>& out) {
    const auto ac = b.rig->findClip(b.clips[c]);
    mar::sampleClip(ac->clip, t, s.restPose, pose);
    mar::localToModel(s, pose, out);
  });
}

// The clip as the runtime samples it (the compact keys when it has them).
ErrorStats marionettePlayedError(const BenchAsset& b) {
  const mar::Skeleton& s = b.rig->skeleton();
  std::vector<mar::Transform> pose(s.jointCount());
  return measureError(b, [&](std::size_t c, float t, std::vector<glm::mat4>& out) {
    const auto ac = b.rig->findClip(b.clips[c]);
    mar::sampleAnimationClip(*ac, t, false, s.restPose, pose);
    mar::localToModel(s, pose, out);
  });
}

ErrorStats ozzError(const BenchAsset& b, const OzzRig& r, const OzzVariant& v) {
  const int n = r.skeleton->num_joints();
  oa::SamplingJob::Context context(n);
  ozz::vector<om::SoaTransform> local(static_cast<std::size_t>(r.skeleton->num_soa_joints()));
  ozz::vector<om::Float4x4> model(static_cast<std::size_t>(n));
  return measureError(b, [&](std::size_t c, float t, std::vector<glm::mat4>& out) {
    const oa::Animation& a = *v.animations[c];
    oa::SamplingJob sampling;
    sampling.animation = &a;
    sampling.context = &context;
    sampling.ratio = t / a.duration();
    sampling.output = ozz::make_span(local);
    if (!sampling.Run()) throw std::runtime_error("SamplingJob failed");
    oa::LocalToModelJob ltm;
    ltm.skeleton = r.skeleton.get();
    ltm.root = &r.root;
    ltm.input = ozz::make_span(local);
    ltm.output = ozz::make_span(model);
    if (!ltm.Run()) throw std::runtime_error("LocalToModelJob failed");
    for (int o = 0; o < n; ++o) out[static_cast<std::size_t>(r.ozzToMar[static_cast<std::size_t>(o)])] = toGlm(model[static_cast<std::size_t>(o)]);
  });
}

// The palettes of both sides for one character, once: a check that they compute the same thing.
float paletteDifference(const BenchAsset& b, const OzzRig& r) {
  const mar::Skeleton& s = b.rig->skeleton();
  std::vector<mar::Transform> pose(s.jointCount());
  std::vector<glm::mat4> model(s.jointCount()), palette(s.jointCount());
  mar::sampleClip(b.rawClips[0], 0.5f * b.rawClips[0].duration, s.restPose, pose);
  mar::localToModel(s, pose, model);
  mar::skinningPalette(model, s.inverseBind, palette);
  float worst = 0.0f;
  for (std::size_t o = 0; o < s.jointCount(); ++o) {
    const std::size_t m = static_cast<std::size_t>(r.ozzToMar[o]);
    const glm::mat4 p = toGlm(toOzz(model[m]) * r.inverseBind[o]);
    for (int c = 0; c < 4; ++c) worst = std::max(worst, glm::length(p[c] - palette[m][c]));
  }
  return worst;
}

// ---------------------------------------------------------------------------------------

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Options {
  std::vector<std::string> assets;
  std::string shared = COMPARE_OZZ_SHARED_DIR;
  std::string label = "marionette";
  int rounds = 7;
  double minSeconds = 0.3;
  long frames = 0;  // 0: calibrated
  bool accuracy = true;
};

void usage() {
  std::printf(
      "compare_ozz [--asset RobotExpressive|Pab]... [--shared DIR] [--rounds R] [--min-seconds S]\n"
      "            [--frames F] [--label TEXT] [--no-accuracy]\n"
      "Marionette's Runtime/Sample1 and Runtime/Blend3 (1000 characters) against ozz-animation on\n"
      "the same data; interleaved rounds, median us per character per frame. Pin it: taskset -c 1.\n");
}

void runAsset(const std::string& which, const Options& opt) {
  std::printf("\n==================== %s ====================\n", which.c_str());
  const auto loadStart = Clock::now();
  BenchAsset b = loadBenchAsset(which, opt.shared);
  if (!b.rig) {
    std::printf("cannot load %s: %s\n", which.c_str(), b.error.c_str());
    std::exit(1);
  }
  const mar::Skeleton& s = b.rig->skeleton();
  std::printf("joints %zu, morph targets %zu, clips %s/%s/%s (%.3f/%.3f/%.3f s), loaded in %.2f s\n", s.jointCount(),
              b.rig->morphTargets().size(), b.clips[0].c_str(), b.clips[1].c_str(), b.clips[2].c_str(),
              b.rawClips[0].duration, b.rawClips[1].duration, b.rawClips[2].duration, seconds(loadStart, Clock::now()));
  const glm::mat4& rt = s.rootTransform;
  std::printf("rootTransform column lengths %.4g %.4g %.4g, translation (%.4g %.4g %.4g); ozz gets it as LocalToModelJob::root\n",
              glm::length(glm::vec3(rt[0])), glm::length(glm::vec3(rt[1])), glm::length(glm::vec3(rt[2])), rt[3].x, rt[3].y, rt[3].z);
  {
    const std::vector<float> sc = restModelScales(s);
    float lo = 1e30f, hi = 0.0f, yLo = 1e30f, yHi = -1e30f;
    for (float v : sc) lo = std::min(lo, v), hi = std::max(hi, v);
    for (const glm::mat4& m : s.restModelMatrices()) yLo = std::min(yLo, m[3].y), yHi = std::max(yHi, m[3].y);
    std::printf("rest model scale of the joints %.4g..%.4g; rest joints span %.3f model units in y (model space is metres)\n",
                lo, hi, yHi - yLo);
    if (hi / lo > 1.001f || std::fabs(hi - 1.0f) > 1e-3f)
      std::printf("note: joint-local lengths are model lengths / %.4g here: ozz's optimizer tolerance and distance and Marionette's\n"
                  "      track tolerances are joint-local, so they mean %.4g times more in model space\n", hi, hi);
  }

  // ozz data.
  OzzRig r = makeOzzRig(s);
  ConversionNotes notes;
  std::vector<oa::offline::RawAnimation> raws;
  for (const mar::Clip& c : b.rawClips) raws.push_back(makeRawAnimation(c, s, r, notes));
  const oa::offline::AnimationOptimizer::Setting defaults;
  std::vector<OzzVariant> variants;
  variants.push_back(makeVariant("ozz raw", raws, r, false, 0.0f, 0.0f));
  char label[64];
  std::snprintf(label, sizeof label, "ozz %gmm/%gcm", defaults.tolerance * 1e3f, defaults.distance * 1e2f);
  variants.push_back(makeVariant(label, raws, r, true, defaults.tolerance, defaults.distance));
  std::snprintf(label, sizeof label, "ozz %gum/%gmm", defaults.tolerance / 100.0f * 1e6f, defaults.distance / 100.0f * 1e3f);
  variants.push_back(makeVariant(label, raws, r, true, defaults.tolerance / 100.0f, defaults.distance / 100.0f));
  std::printf("ozz conversion: %d tracks from the rest pose (no track), %d Step tracks (hold keys added), %d CubicSpline tracks (tangents dropped)\n",
              notes.restFilled, notes.stepTracks, notes.cubicTracks);
  std::printf("ozz optimizer settings (AnimationOptimizer::Setting{tolerance, distance}): defaults {%g m, %g m}, /100 {%g m, %g m}; no per-joint overrides\n",
              defaults.tolerance, defaults.distance, defaults.tolerance / 100.0f, defaults.distance / 100.0f);
  std::printf("palette check (raw clip, mid-time): max |ozz - Marionette| column difference %.3g\n", paletteDifference(b, r));

  // Sizes.
  std::printf("\nClip sizes (bytes; Marionette: times + values of every track; ozz: Animation::size())\n");
  std::printf("%-10s %10s %10s %12s %12s %10s", "clip", "raw keys", "raw B", "Mar clip B", "Mar inPlace", "Mar keys");
  for (const OzzVariant& v : variants) std::printf(" %16s", v.label.c_str());
  std::printf("\n");
  std::size_t total[6] = {};
  std::vector<std::size_t> ozzTotal(variants.size(), 0);
  for (std::size_t c = 0; c < b.clips.size(); ++c) {
    const auto ac = b.rig->findClip(b.clips[c]);
    const std::size_t row[5] = {clipKeys(b.rawClips[c]), clipKeyBytes(b.rawClips[c]), clipKeyBytes(ac->clip),
                                clipKeyBytes(ac->inPlaceRoot), clipKeys(ac->clip)};
    std::printf("%-10s %10zu %10zu %12zu %12zu %10zu", b.clips[c].c_str(), row[0], row[1], row[2], row[3], row[4]);
    for (int i = 0; i < 5; ++i) total[i] += row[i];
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const std::size_t sz = variants[v].animations[c]->size();
      ozzTotal[v] += sz;
      std::printf(" %16zu", sz);
    }
    std::printf("\n");
  }
  std::printf("%-10s %10zu %10zu %12zu %12zu %10zu", "total", total[0], total[1], total[2], total[3], total[4]);
  for (std::size_t v = 0; v < variants.size(); ++v) std::printf(" %16zu", ozzTotal[v]);
  std::printf("\n");
  {  // The compact clips the runtime samples (CompactClip::bytes(): track headers and data)
    std::printf("\nCompact clips (bytes = CompactClip::bytes(): tracks * sizeof(CompactTrack) %zu + data)\n", sizeof(mar::CompactTrack));
    std::printf("%-10s %10s %12s %12s %12s %12s %12s  %-22s %10s  %s\n", "clip", "compacted", "float B", "compact B", "inPl float B",
                "inPl cmpct B", "sum compact", "tracks 8/16/32/64", "maxErr mm", "resampled/timed");
    std::size_t tf = 0, tc = 0, tif = 0, tic = 0;
    for (std::size_t c = 0; c < b.clips.size(); ++c) {
      const auto ac = b.rig->findClip(b.clips[c]);
      const mar::CompactClipStats& a = ac->compaction;
      const mar::CompactClipStats& i = ac->compactionInPlaceRoot;
      char tr[64];
      std::snprintf(tr, sizeof tr, "%d/%d/%d/%d", a.tracks8, a.tracks16, a.tracks32, a.tracks64);
      std::printf("%-10s %10s %12zu %12zu %12zu %12zu %12zu  %-22s %10.4f  %d/%d %s\n", b.clips[c].c_str(), a.compacted ? "yes" : "no", a.floatBytes,
                  a.compactBytes, i.floatBytes, i.compactBytes, a.compactBytes + i.compactBytes, tr, a.maxError * 1e3f, a.tracksResampled,
                  a.tracksTimed, a.compacted ? "" : a.reason.c_str());
      std::printf("%-10s   (CompactClip::bytes(): clip %zu (%zu tracks, data %zu), inPlaceRoot %zu (%zu tracks, data %zu); inPlace compacted %s, maxErr %.4f mm)\n", "",
                  ac->compact.bytes(), ac->compact.tracks.size(), ac->compact.data.size(), ac->compactInPlaceRoot.bytes(),
                  ac->compactInPlaceRoot.tracks.size(), ac->compactInPlaceRoot.data.size(), i.compacted ? "yes" : "no", i.maxError * 1e3f);
      tf += a.floatBytes, tc += a.compactBytes, tif += i.floatBytes, tic += i.compactBytes;
    }
    std::printf("%-10s %10s %12zu %12zu %12zu %12zu %12zu\n", "total", "", tf, tc, tif, tic, tc + tic);
  }

  // Accuracy.
  if (opt.accuracy) {
    std::printf("\nAccuracy: |model-space position| error of 6 virtual vertices 3 cm (model space) from each joint, vs the raw clip\n"
                "sampled by Marionette (sampleClip + localToModel); %d evenly spaced times per clip, %zu joints, 3 clips\n",
                kAccuracySamples, s.jointCount());
    std::printf("%-22s %12s %12s %12s   %s\n", "side", "max (mm)", "p99 (mm)", "mean (mm)", "worst at");
    auto row = [&](const std::string& name, const ErrorStats& e) {
      std::printf("%-22s %12.4f %12.4f %12.4f   %s t=%.3f joint %d (%s)\n", name.c_str(), e.max * 1e3f, e.p99 * 1e3f,
                  e.mean * 1e3f, e.worstClip.c_str(), e.worstTime, e.worstJoint,
                  e.worstJoint >= 0 ? s.names[static_cast<std::size_t>(e.worstJoint)].c_str() : "");
    };
    row("Marionette (Rig clip)", marionetteError(b));
    row("Mar (as played)", marionettePlayedError(b));  // sampleAnimationClip: the compact keys
    for (const OzzVariant& v : variants) row(v.label, ozzError(b, r, v));
  }

  // Timing and state, per case.
  struct Row {
    std::string name;
    double mar = 0.0, marCpu = 0.0;  // medians, us per character per frame
    std::vector<double> ozz, ozzCpu;
    std::vector<double> ratioMin, ratioMax;  // per-round Marionette / ozz (wall)
    long frames = 0;
    double worstWallOverCpu = 1.0;  // largest wall / CPU time of a timed run
    long preempted = 0;             // involuntary context switches in all timed runs
  };
  std::vector<Row> rows;
  for (int layers : {1, 3}) {
    const std::string caseName = layers == 1 ? "Sample1" : "Blend3";
    mar::Scene scene;
    fillScene(scene, b.rig, b.clips, kCharacters, layers);
    std::vector<std::unique_ptr<OzzCrowd>> crowds;
    for (std::size_t v = 1; v < variants.size(); ++v)  // the optimized ones
      crowds.push_back(std::make_unique<OzzCrowd>(r, variants[v], kCharacters, layers));

    // State per character.
    std::vector<std::shared_ptr<const mar::AnimationClip>> played;
    for (int l = 0; l < layers; ++l) played.push_back(b.rig->findClip(b.clips[static_cast<std::size_t>(l)]));
    const MarionetteState ms = marionetteState(*scene.characters().front(), played);
    const OzzCrowd::State os = crowds.front()->state();
    std::printf("\n%s state per character (bytes):\n", caseName.c_str());
    std::printf("  Marionette %6zu = sizeof(Character) %zu + local pose %zu + TransformBuffer %zu (model+palette+morphs)"
                " + morph scratch %zu + sampling cursors %zu\n",
                ms.total(), ms.object, ms.pose, ms.buffer, ms.morphs, ms.cursors);
    std::printf("  ozz        %6zu = contexts %zu + SoA locals %zu + SoA blended %zu + model %zu + palette %zu + harness struct %zu\n",
                os.total(), os.contexts, os.locals, os.blended, os.model, os.palette, os.other);

    auto marFrames = [&](long f) {
      for (long i = 0; i < f; ++i) {
        scene.update(kDt);
        escape(scene.characters().front()->transformBuffer().skinning().data());
      }
    };
    auto ozzFrames = [&](std::size_t v) {
      return [&crowds, v](long f) {
        for (long i = 0; i < f; ++i) crowds[v]->update(kDt);
      };
    };
    long frames = opt.frames;
    if (frames <= 0) {  // F frames make the fastest side take at least minSeconds
      double fastest = timeFrames(marFrames, 3).wall / 3;
      for (std::size_t v = 0; v < crowds.size(); ++v) fastest = std::min(fastest, timeFrames(ozzFrames(v), 3).wall / 3);
      frames = std::max(3L, static_cast<long>(std::ceil(opt.minSeconds * 1.1 / fastest)));
    }
    Row row;
    row.name = caseName;
    row.frames = frames;
    const double perFrameChar = 1e6 / (static_cast<double>(frames) * kCharacters);
    std::vector<double> marUs, marCpu;
    std::vector<std::vector<double>> ozzUs(crowds.size()), ozzCpu(crowds.size());
    auto record = [&](const Timed& t, std::vector<double>& wall, std::vector<double>& cpu) {
      wall.push_back(t.wall * perFrameChar);
      cpu.push_back(t.cpu * perFrameChar);
      row.worstWallOverCpu = std::max(row.worstWallOverCpu, t.wall / t.cpu);
      row.preempted += t.preempted;
    };
    for (int round = 0; round < opt.rounds; ++round) {
      record(timeFrames(marFrames, frames), marUs, marCpu);
      for (std::size_t v = 0; v < crowds.size(); ++v) record(timeFrames(ozzFrames(v), frames), ozzUs[v], ozzCpu[v]);
    }
    row.mar = median(marUs);
    row.marCpu = median(marCpu);
    for (std::size_t v = 0; v < crowds.size(); ++v) {
      row.ozz.push_back(median(ozzUs[v]));
      row.ozzCpu.push_back(median(ozzCpu[v]));
      double lo = 1e300, hi = 0.0;
      for (int i = 0; i < opt.rounds; ++i) {
        lo = std::min(lo, marUs[static_cast<std::size_t>(i)] / ozzUs[v][static_cast<std::size_t>(i)]);
        hi = std::max(hi, marUs[static_cast<std::size_t>(i)] / ozzUs[v][static_cast<std::size_t>(i)]);
      }
      row.ratioMin.push_back(lo);
      row.ratioMax.push_back(hi);
    }
    rows.push_back(row);
  }

  std::printf("\nTiming (%s): median us per character per frame over %d interleaved rounds, %d characters, one thread\n",
              opt.label.c_str(), opt.rounds, kCharacters);
  std::printf("%-8s %7s %12s", "case", "frames", "Marionette");
  for (std::size_t v = 1; v < variants.size(); ++v) std::printf(" %16s", variants[v].label.c_str());
  for (std::size_t v = 1; v < variants.size(); ++v) std::printf("  %-26s", ("Mar/" + variants[v].label + " [round min-max]").c_str());
  std::printf("\n");
  for (const Row& row : rows) {
    std::printf("%-8s %7ld %12.3f", row.name.c_str(), row.frames, row.mar);
    for (double o : row.ozz) std::printf(" %16.3f", o);
    for (std::size_t v = 0; v < row.ozz.size(); ++v)
      std::printf("  %6.2f [%5.2f-%5.2f]%9s", row.mar / row.ozz[v], row.ratioMin[v], row.ratioMax[v], "");
    std::printf("\n");
  }
  std::printf("Same rounds in thread CPU time (us per character per frame), and what else ran on the core:\n");
  std::printf("%-8s %7s %12s", "case", "", "Marionette");
  for (std::size_t v = 1; v < variants.size(); ++v) std::printf(" %16s", variants[v].label.c_str());
  for (std::size_t v = 1; v < variants.size(); ++v) std::printf(" %12s", ("Mar/" + variants[v].label.substr(4)).c_str());
  std::printf("  %-14s %s\n", "max wall/cpu", "preemptions");
  for (const Row& row : rows) {
    std::printf("%-8s %7s %12.3f", row.name.c_str(), "cpu", row.marCpu);
    for (double o : row.ozzCpu) std::printf(" %16.3f", o);
    for (double o : row.ozzCpu) std::printf(" %12.2f", row.marCpu / o);
    std::printf("  %-14.3f %ld\n", row.worstWallOverCpu, row.preempted);
  }
  // One line per result for scripts: RESULT label asset case marionette_us ozz_us... ratios...
  for (const Row& row : rows) {
    std::printf("RESULT %s %s %s %.4f", opt.label.c_str(), which.c_str(), row.name.c_str(), row.mar);
    for (double o : row.ozz) std::printf(" %.4f", o);
    for (double o : row.ozz) std::printf(" %.4f", row.mar / o);
    std::printf("\n");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--asset") opt.assets.push_back(next());
    else if (a == "--shared") opt.shared = next();
    else if (a == "--rounds") opt.rounds = std::max(1, std::atoi(next().c_str()));
    else if (a == "--min-seconds") opt.minSeconds = std::atof(next().c_str());
    else if (a == "--frames") opt.frames = std::atol(next().c_str());
    else if (a == "--label") opt.label = next();
    else if (a == "--no-accuracy") opt.accuracy = false;
    else if (a == "-h" || a == "--help") return usage(), 0;
    else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      usage();
      return 2;
    }
  }
  if (opt.assets.empty()) opt.assets = {"RobotExpressive", "Pab"};
  std::printf("compare_ozz: %s; shared data %s\n", opt.label.c_str(), opt.shared.c_str());
  try {
    for (const std::string& a : opt.assets) runAsset(a, opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_ozz: %s\n", e.what());
    return 1;
  }
  return 0;
}
