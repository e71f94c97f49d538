// BVH writer: see marionette/io/bvh_writer.hpp for what the file holds and what
// is dropped. Two passes over the frames: the first finds which joints need
// position channels and which carry scale, the second writes the text.
#include "marionette/io/bvh_writer.hpp"

#include "marionette/core/float_chars.hpp"
#include "marionette/core/finite.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <system_error>

#include "file_write.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/core/text.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;

constexpr double kDefaultFrameRate = 30.0;
constexpr double kMaxFrameRate = 120.0;
// A derived rate this close above the cap is the cap written with few digits
// (CMU's "Frame Time: 0.0083333" is 120.0005 fps): keep its keys unresampled.
constexpr double kCapSlack = 1e-3;
// A final partial frame shorter than this fraction of a frame is rounding, not motion.
constexpr double kFrameSlack = 1e-3;
// cos x below this: gimbal lock, only z -/+ y is defined. Above it the doubles
// computed from a float quaternion still give y and z to about 1e-8 rad.
constexpr double kLockCos = 1e-8;
constexpr float kScaleTolerance = 1e-4f;      // |scale - 1| that counts as scale
constexpr double kRootSpaceTolerance = 1e-4;  // relative: non-uniform scale, shear
constexpr int kMaxPrecision = 9;
// Bounds the text to a few GB: more is a wrong frame rate, not a motion.
constexpr double kMaxValues = 5e8;

double degrees(double radians) { return radians * (180.0 / std::numbers::pi); }

// `angle` plus the multiple of 360 that brings it nearest to `target`.
double wrapToward(double angle, double target) { return angle + 360.0 * std::round((target - angle) / 360.0); }


// ---------------------------------------------------------------- names

// BVH names are single tokens; Assimp also splits tokens at braces.
std::string sanitizedName(const std::string& name, std::size_t index) {
  if (name.empty()) return "joint_" + std::to_string(index);
  std::string out = name;
  for (char& c : out) {
    const auto u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u == 0x7f || c == '{' || c == '}') c = '_';
  }
  return out;
}

struct Naming {
  std::vector<std::string> joints;   // by skeleton index
  std::string syntheticRoot;         // unique even when a joint is called MarionetteRoot
  std::vector<std::string> changed;  // "'old' -> 'new'" for the warning
};

Naming nameJoints(const Skeleton& skeleton) {
  Naming naming;
  std::set<std::string> used;
  for (std::size_t j = 0; j < skeleton.jointCount(); ++j) {
    const std::string& original = j < skeleton.names.size() ? skeleton.names[j] : std::string();
    std::string name = claimUniqueName(sanitizedName(original, j), used);
    if (name != original)
      naming.changed.push_back((original.empty() ? "joint " + std::to_string(j) + " (unnamed)" : "'" + original + "'") +
                               " -> '" + name + "'");
    naming.joints.push_back(std::move(name));
  }
  naming.syntheticRoot = claimUniqueName(kBvhSyntheticRoot, used);
  return naming;
}

// ---------------------------------------------------------------- the root's space

// Skeleton::rootTransform as translation, rotation and one uniform scale: all BVH holds.
struct RootSpace {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  double scale = 1.0;
};

std::optional<RootSpace> rootSpace(const glm::mat4& m, Diagnostics& d, const std::string& file) {
  if (!isFinite(m)) {
    d.error(file, "the skeleton's rootTransform is not finite; nothing written");
    return std::nullopt;
  }
  if (std::abs(m[0][3]) > 1e-6f || std::abs(m[1][3]) > 1e-6f || std::abs(m[2][3]) > 1e-6f ||
      std::abs(m[3][3] - 1.0f) > 1e-6f) {
    d.error(file, "the skeleton's rootTransform is projective (last row not 0 0 0 1); BVH cannot hold it");
    return std::nullopt;
  }
  const glm::dmat3 linear(m);
  const double det = glm::determinant(linear);
  const glm::dvec3 lengths(glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2]));
  const double largest = std::max({lengths.x, lengths.y, lengths.z});
  const double smallest = std::min({lengths.x, lengths.y, lengths.z});
  if (!(smallest > 0.0) || std::abs(det) <= 1e-12 * largest * largest * largest) {
    d.error(file, "the skeleton's rootTransform is singular (a zero scale); BVH cannot hold it");
    return std::nullopt;
  }
  if (det < 0.0) {
    d.error(file,
            "the skeleton's rootTransform mirrors (negative determinant); BVH rotations cannot mirror, "
            "mirror the skeleton and clip first");
    return std::nullopt;
  }
  if (largest / smallest - 1.0 > kRootSpaceTolerance) {
    d.error(file, "the skeleton's rootTransform scales non-uniformly (" + std::to_string(lengths.x) + ", " +
                      std::to_string(lengths.y) + ", " + std::to_string(lengths.z) +
                      "); BVH holds no scale and only a uniform one can be folded into the lengths");
    return std::nullopt;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      if (std::abs(glm::dot(linear[a], linear[b])) > kRootSpaceTolerance * lengths[a] * lengths[b]) {
        d.error(file, "the skeleton's rootTransform has shear; BVH cannot hold it");
        return std::nullopt;
      }
  RootSpace space;
  space.scale = std::cbrt(det);
  space.rotation = glm::normalize(glm::quat_cast(linear / space.scale));
  space.translation = glm::dvec3(m[3]);
  return space;
}

// ---------------------------------------------------------------- frames

// Mean key spacing of the most densely keyed track: exact for evenly keyed clips
// (BVH, most glTF exports), so their keys are written as they are. Infinity when
// no track has two keys.
double densestKeySpacing(const Clip& clip) {
  double best = std::numeric_limits<double>::infinity();
  auto consider = [&](const std::vector<float>& times) {
    if (times.size() < 2) return;
    const double spacing = (static_cast<double>(times.back()) - times.front()) / static_cast<double>(times.size() - 1);
    if (spacing > 0.0) best = std::min(best, spacing);
  };
  for (const JointTrack& jt : clip.tracks) {
    consider(jt.translation.times);
    consider(jt.rotation.times);
    consider(jt.scale.times);
  }
  return best;
}

double frameTimeFor(const Clip& clip, const BvhWriteOptions& options) {
  if (options.frameRate > 0.0f) return 1.0 / options.frameRate;
  const double spacing = densestKeySpacing(clip);
  if (!std::isfinite(spacing)) return 1.0 / kDefaultFrameRate;
  if (1.0 / spacing > kMaxFrameRate * (1.0 + kCapSlack)) return 1.0 / kMaxFrameRate;
  return spacing;
}

template <class T>
bool valuesFinite(const Track<T>& track) {
  return std::all_of(track.values.begin(), track.values.end(), [](const T& v) { return isFinite(v); });
}

// ---------------------------------------------------------------- the file's joints

// One joint as written: a skeleton joint, or the synthetic root (joint -1).
struct FileJoint {
  int joint = -1;
  int depth = 0;
  bool positions = false;  // has Xposition Yposition Zposition channels
  bool leaf = false;
  int closeAfter = 0;  // braces to close after this joint's block (its subtree ends)
};

class BvhBuilder {
 public:
  BvhBuilder(const Skeleton& skeleton, const Clip& clip, const BvhWriteOptions& options, Diagnostics& d,
             std::string file)
      : skeleton_(skeleton), clip_(clip), options_(options), d_(d), file_(std::move(file)) {}

  std::string build();

 private:
  bool checkInputs();
  void scanFrames();
  void layOut();
  void writeHierarchy();
  bool writeMotion();
  void sample(std::size_t frame);

  // Local translation of a written joint in file units, and its rotation.
  [[nodiscard]] glm::dvec3 fileTranslation(int joint, const Transform& local) const;
  [[nodiscard]] glm::quat fileRotation(int joint, const Transform& local) const;
  [[nodiscard]] glm::dvec3 endSiteOffset(int joint) const;

  void indent(int depth) { text_.append(static_cast<std::size_t>(depth) * 2, ' '); }
  void number(double v);
  void vector(const glm::dvec3& v);

  const Skeleton& skeleton_;
  const Clip& clip_;
  const BvhWriteOptions& options_;
  Diagnostics& d_;
  std::string file_;

  RootSpace space_;
  double lengthScale_ = 1.0;  // file units per skeleton unit below the root space
  bool synthetic_ = false;
  Naming naming_;
  double frameTime_ = 0.0;
  std::size_t frames_ = 1;
  std::vector<std::vector<int>> children_;
  std::vector<std::uint8_t> movesTranslation_;  // by joint
  std::vector<std::uint8_t> scaled_;            // by joint
  std::vector<FileJoint> order_;                // depth-first, as written
  std::vector<Transform> pose_;
  SamplingCursor cursor_;
  std::string text_;
  double zeroBelow_ = 0.0;
};

std::string BvhBuilder::build() {
  if (!checkInputs()) return {};
  scanFrames();
  layOut();
  text_.reserve(frames_ * order_.size() * 3 * static_cast<std::size_t>(options_.precision + 6));
  writeHierarchy();
  if (!writeMotion()) return {};
  return std::move(text_);
}

bool BvhBuilder::checkInputs() {
  const std::size_t n = skeleton_.jointCount();
  if (n == 0) {
    d_.error(file_, "the skeleton has no joints; nothing to write");
    return false;
  }
  if (std::string e = skeleton_.validate(); !e.empty()) {
    d_.error(file_, "invalid skeleton: " + e);
    return false;
  }
  if (std::string e = clip_.validate(n); !e.empty()) {
    d_.error(file_, "invalid clip: " + e);
    return false;
  }
  for (const JointTrack& jt : clip_.tracks)
    if (!valuesFinite(jt.translation) || !valuesFinite(jt.rotation) || !valuesFinite(jt.scale)) {
      d_.error(file_, "clip '" + clip_.name + "': joint '" + skeleton_.names[static_cast<std::size_t>(jt.joint)] +
                          "' has a non-finite key value; nothing written");
      return false;
    }
  if (!std::isfinite(options_.frameRate) || options_.frameRate < 0.0f) {
    d_.error(file_, "frame rate " + std::to_string(options_.frameRate) + " (expected > 0, or 0 to derive it)");
    return false;
  }
  if (!std::isfinite(options_.unitScale) || !(options_.unitScale > 0.0f)) {
    d_.error(file_, "unit scale " + std::to_string(options_.unitScale) + " (expected a positive number)");
    return false;
  }
  if (options_.precision < 0 || options_.precision > kMaxPrecision) {
    d_.error(file_, "precision " + std::to_string(options_.precision) + " (expected 0 to " +
                        std::to_string(kMaxPrecision) + " decimals)");
    return false;
  }
  const std::optional<RootSpace> space = rootSpace(skeleton_.rootTransform, d_, file_);
  if (!space) return false;
  space_ = *space;
  lengthScale_ = space_.scale * options_.unitScale;
  zeroBelow_ = 0.5 * std::pow(10.0, -options_.precision);

  frameTime_ = frameTimeFor(clip_, options_);
  const double duration = std::max(0.0, static_cast<double>(clip_.duration));
  const double spans = std::ceil(duration / frameTime_ - kFrameSlack);
  const double values = (std::max(spans, 0.0) + 1.0) * static_cast<double>(n + 1) * 6.0;
  if (!(values < kMaxValues)) {
    d_.error(file_, "clip '" + clip_.name + "' of " + std::to_string(duration) + " s at " +
                        std::to_string(1.0 / frameTime_) + " frames per second is too many values for a BVH file");
    return false;
  }
  frames_ = static_cast<std::size_t>(std::max(spans, 0.0)) + 1;

  naming_ = nameJoints(skeleton_);
  if (!naming_.changed.empty())
    d_.warning(file_, "joint names changed to be valid, unique BVH names: " + quotedNameList(naming_.changed));
  if (!clip_.morphTracks.empty())
    d_.warning(file_, "clip '" + clip_.name + "': BVH has no morph weights; " +
                          std::to_string(clip_.morphTracks.size()) + " morph tracks dropped");
  return true;
}

void BvhBuilder::sample(std::size_t frame) {
  const double t = std::min(static_cast<double>(frame) * frameTime_, static_cast<double>(clip_.duration));
  sampleClip(clip_, static_cast<float>(t), skeleton_.restPose, pose_, &cursor_);
}

// Which joints the clip moves away from their rest translation (in written
// digits), and which carry a scale BVH cannot hold.
void BvhBuilder::scanFrames() {
  const std::size_t n = skeleton_.jointCount();
  pose_.assign(n, Transform{});
  movesTranslation_.assign(n, 0);
  scaled_.assign(n, 0);
  auto checkScale = [&](std::size_t j, const glm::vec3& s) {
    if (glm::any(glm::greaterThan(glm::abs(s - glm::vec3(1.0f)), glm::vec3(kScaleTolerance)))) scaled_[j] = 1;
  };
  for (std::size_t j = 0; j < n; ++j) checkScale(j, skeleton_.restPose[j].scale);
  cursor_.reset(clip_);
  for (std::size_t f = 0; f < frames_; ++f) {
    sample(f);
    for (const JointTrack& jt : clip_.tracks) {
      const auto j = static_cast<std::size_t>(jt.joint);
      const glm::dvec3 moved = glm::dvec3(pose_[j].translation - skeleton_.restPose[j].translation) * lengthScale_;
      if (std::max({std::abs(moved.x), std::abs(moved.y), std::abs(moved.z)}) >= zeroBelow_) movesTranslation_[j] = 1;
      checkScale(j, pose_[j].scale);
    }
  }
  std::vector<std::string> names;
  for (std::size_t j = 0; j < n; ++j)
    if (scaled_[j]) names.push_back(naming_.joints[j]);
  if (!names.empty())
    d_.warning(file_, "joints " + quotedNameList(names) +
                          " have a scale other than 1 at rest or in the clip; BVH has no scale, it is dropped");
}

void BvhBuilder::layOut() {
  const std::size_t n = skeleton_.jointCount();
  children_.assign(n, {});
  std::vector<int> roots;
  for (std::size_t j = 0; j < n; ++j) {
    const int p = skeleton_.parents[j];
    (p < 0 ? roots : children_[static_cast<std::size_t>(p)]).push_back(static_cast<int>(j));
  }
  synthetic_ = roots.size() > 1;
  if (synthetic_) {
    std::vector<std::string> names;
    for (int r : roots) names.push_back(naming_.joints[static_cast<std::size_t>(r)]);
    d_.warning(file_, "the skeleton has " + std::to_string(roots.size()) + " roots (" + quotedNameList(names) +
                          "); BVH has one ROOT, so they are children of a synthetic root '" + naming_.syntheticRoot +
                          "'");
  }
  // Depth-first without recursion: long chains (ropes, tails) stay off the call stack.
  struct Pending {
    int joint;
    int depth;
  };
  std::vector<Pending> stack;
  const int base = synthetic_ ? 1 : 0;
  if (synthetic_) order_.push_back({-1, 0, true, false, 0});
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, base});
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    const auto j = static_cast<std::size_t>(p.joint);
    const bool isRoot = !synthetic_ && p.depth == 0;
    order_.push_back({p.joint, p.depth, isRoot || movesTranslation_[j] != 0, children_[j].empty(), 0});
    for (auto c = children_[j].rbegin(); c != children_[j].rend(); ++c) stack.push_back({*c, p.depth + 1});
  }
  // A block closes when the next written joint is not deeper: close down to its depth.
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const int nextDepth = i + 1 < order_.size() ? order_[i + 1].depth : 0;
    order_[i].closeAfter = order_[i].depth - nextDepth + 1;
  }
}

glm::dvec3 BvhBuilder::fileTranslation(int joint, const Transform& local) const {
  if (joint < 0) return space_.translation * static_cast<double>(options_.unitScale);
  const glm::dvec3 t(local.translation);
  if (skeleton_.parents[static_cast<std::size_t>(joint)] >= 0 || synthetic_) return t * lengthScale_;
  // The single root lives in rootTransform's space: bake it in.
  return (space_.translation + space_.scale * (space_.rotation * t)) * static_cast<double>(options_.unitScale);
}

glm::quat BvhBuilder::fileRotation(int joint, const Transform& local) const {
  if (joint < 0) return glm::quat(space_.rotation);
  if (skeleton_.parents[static_cast<std::size_t>(joint)] >= 0 || synthetic_) return local.rotation;
  return glm::quat(space_.rotation * glm::dquat(local.rotation));
}

// Continues the bone into the leaf: the parent->joint offset again (in BVH's zero
// pose every joint frame is aligned, so that is the bone's direction), or a tenth
// of the mean bone length along +Y when the bone has no length.
glm::dvec3 BvhBuilder::endSiteOffset(int joint) const {
  const auto j = static_cast<std::size_t>(joint);
  const glm::dvec3 bone = glm::dvec3(skeleton_.restPose[j].translation) * lengthScale_;
  if (skeleton_.parents[j] >= 0 && glm::length(bone) > 2.0 * zeroBelow_) return bone;
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < skeleton_.jointCount(); ++k) {
    if (skeleton_.parents[k] < 0) continue;
    const double length = glm::length(glm::dvec3(skeleton_.restPose[k].translation));
    if (length > 0.0) {
      sum += length;
      ++count;
    }
  }
  const double length = count > 0 ? 0.1 * sum / count * lengthScale_ : 0.01 * options_.unitScale;
  return {0.0, std::max(length, 10.0 * zeroBelow_), 0.0};
}

void BvhBuilder::number(double v) {
  if (std::abs(v) < zeroBelow_) v = 0.0;  // no "-0.000000"
  char buffer[400];                       // fixed notation of any finite double fits
  const auto r = floatToChars(buffer, buffer + sizeof buffer, v, std::chars_format::fixed, options_.precision);
  text_.append(buffer, r.ptr);
}

void BvhBuilder::vector(const glm::dvec3& v) {
  number(v.x);
  text_ += ' ';
  number(v.y);
  text_ += ' ';
  number(v.z);
}

void BvhBuilder::writeHierarchy() {
  text_ += "HIERARCHY\n";
  for (const FileJoint& fj : order_) {
    const bool first = &fj == &order_.front();
    indent(fj.depth);
    text_ += first ? "ROOT " : "JOINT ";
    text_ += fj.joint < 0 ? naming_.syntheticRoot : naming_.joints[static_cast<std::size_t>(fj.joint)];
    text_ += '\n';
    indent(fj.depth);
    text_ += "{\n";
    indent(fj.depth + 1);
    text_ += "OFFSET ";
    vector(fj.joint < 0 ? fileTranslation(-1, {})
                        : fileTranslation(fj.joint, skeleton_.restPose[static_cast<std::size_t>(fj.joint)]));
    text_ += '\n';
    indent(fj.depth + 1);
    // Assimp reads positions only from a 6-channel joint, so a joint with positions has all six.
    text_ += fj.positions ? "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
                          : "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    if (fj.leaf) {
      indent(fj.depth + 1);
      text_ += "End Site\n";
      indent(fj.depth + 1);
      text_ += "{\n";
      indent(fj.depth + 2);
      text_ += "OFFSET ";
      vector(endSiteOffset(fj.joint));
      text_ += '\n';
      indent(fj.depth + 1);
      text_ += "}\n";
    }
    for (int k = 0; k < fj.closeAfter; ++k) {
      indent(fj.depth - k);
      text_ += "}\n";
    }
  }
}

bool BvhBuilder::writeMotion() {
  char frameTime[64];
  const auto r = floatToChars(frameTime, frameTime + sizeof frameTime, frameTime_, std::chars_format::general, 9);
  text_ += "MOTION\nFrames: " + std::to_string(frames_) + "\nFrame Time: " + std::string(frameTime, r.ptr) + "\n";
  std::vector<BvhEuler> previous(order_.size());
  cursor_.reset(clip_);
  for (std::size_t f = 0; f < frames_; ++f) {
    sample(f);
    for (std::size_t i = 0; i < order_.size(); ++i) {
      const FileJoint& fj = order_[i];
      const Transform& local = fj.joint < 0 ? Transform{} : pose_[static_cast<std::size_t>(fj.joint)];
      const BvhEuler angles = toBvhEuler(fileRotation(fj.joint, local), f > 0 ? &previous[i] : nullptr);
      previous[i] = angles;
      const glm::dvec3 t = fileTranslation(fj.joint, local);
      // Finite inputs can still overflow (1e38 m times a unit scale).
      if (!(isFinite(glm::dvec3(angles.x, angles.y, angles.z)) && isFinite(t))) {
        d_.error(file_,
                 "frame " + std::to_string(f) + ", joint '" +
                     (fj.joint < 0 ? naming_.syntheticRoot : naming_.joints[static_cast<std::size_t>(fj.joint)]) +
                     "': a value is not finite after unit scaling; nothing written");
        return false;
      }
      if (i > 0) text_ += ' ';
      if (fj.positions) {
        vector(t);
        text_ += ' ';
      }
      vector({angles.z, angles.x, angles.y});
    }
    text_ += '\n';
  }
  return true;
}

}  // namespace

BvhEuler toBvhEuler(const glm::quat& rotation, const BvhEuler* previous) noexcept {
  // Matrix entries m[row][column] of the unit quaternion, in double.
  const glm::dquat q = glm::normalize(glm::dquat(safeNormalize(rotation)));
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  const double m00 = 1.0 - 2.0 * (y * y + z * z), m01 = 2.0 * (x * y - w * z);
  const double m10 = 2.0 * (x * y + w * z), m11 = 1.0 - 2.0 * (x * x + z * z);
  const double m20 = 2.0 * (x * z - w * y), m21 = 2.0 * (y * z + w * x), m22 = 1.0 - 2.0 * (x * x + y * y);
  // Rz Rx Ry has m21 = sin x, (m20, m22) = cos x (-sin y, cos y), (m01, m11) = cos x (-sin z, cos z).
  const double cosX = std::hypot(m20, m22);
  BvhEuler a;
  a.x = degrees(std::atan2(m21, cosX));  // atan2, not asin: accurate near +-90
  if (cosX > kLockCos) {
    a.y = degrees(std::atan2(-m20, m22));
    a.z = degrees(std::atan2(-m01, m11));
  } else {
    // Locked: (m00, m10) = (cos, sin)(z + y) at x = 90, (z - y) at x = -90.
    a.y = previous ? previous->y : 0.0;
    a.z = degrees(std::atan2(m10, m00)) - (m21 > 0.0 ? a.y : -a.y);
  }
  if (!previous) return a;
  // The same rotation as (z + 180, 180 - x, y + 180); take whichever is nearer.
  auto unwrapped = [&](BvhEuler e) {
    e.z = wrapToward(e.z, previous->z);
    e.x = wrapToward(e.x, previous->x);
    e.y = wrapToward(e.y, previous->y);
    return e;
  };
  auto distance = [&](const BvhEuler& e) {
    return std::abs(e.z - previous->z) + std::abs(e.x - previous->x) + std::abs(e.y - previous->y);
  };
  const BvhEuler first = unwrapped(a);
  const BvhEuler second = unwrapped({a.z + 180.0, 180.0 - a.x, a.y + 180.0});
  return distance(second) < distance(first) ? second : first;
}

glm::dquat fromBvhEuler(const BvhEuler& e) noexcept {
  const double r = std::numbers::pi / 180.0;
  return glm::angleAxis(e.z * r, glm::dvec3(0, 0, 1)) * glm::angleAxis(e.x * r, glm::dvec3(1, 0, 0)) *
         glm::angleAxis(e.y * r, glm::dvec3(0, 1, 0));
}

std::vector<std::string> bvhJointNames(const Skeleton& skeleton) { return nameJoints(skeleton).joints; }

std::string bvhText(const Skeleton& skeleton, const Clip& clip, const BvhWriteOptions& options,
                    Diagnostics& diagnostics, const std::string& file) {
  try {
    return BvhBuilder(skeleton, clip, options, diagnostics, file).build();
  } catch (const std::exception& e) {  // only allocation can throw here
    diagnostics.error(file, std::string("cannot build the BVH text: ") + e.what());
    return {};
  }
}

Diagnostics writeBvh(const std::string& path, const Skeleton& skeleton, const Clip& clip,
                     const BvhWriteOptions& options) {
  Diagnostics d;
  try {
    if (path.empty()) {
      d.error(path, "no output path given for the BVH file");
      return d;
    }
    const std::string text = bvhText(skeleton, clip, options, d, path);
    if (d.ok()) detail::writeFileReplacing(path, text, "a BVH file path", d);
  } catch (const std::exception& e) {
    d.error(path, std::string("cannot write the BVH file: ") + e.what());
  }
  return d;
}

}  // namespace marionette
