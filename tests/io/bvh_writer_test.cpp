// Tests of the BVH writer: Euler conventions at gimbal lock, continuity, names,
// what BVH cannot hold, errors, and (with Assimp) round trips of real motions and
// characters through a written file and Assimp's BVH reader. Missing data fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/io/bvh_writer.hpp"
#include "marionette/io/import.hpp"
#include "test_data.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;
using test::assimpModel;
using test::readFile;
using test::sharedAsset;

constexpr double kPi = 3.14159265358979323846;

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("marionette_bvh_writer_test_" + name)).string();
}

bool mentions(const Diagnostics& d, Severity severity, const std::string& text) {
  for (const Diagnostic& item : d.items)
    if (item.severity == severity && item.message.find(text) != std::string::npos) return true;
  return false;
}

glm::dmat3 matrixOf(const glm::dquat& q) { return glm::mat3_cast(glm::normalize(q)); }

double maxDifference(const glm::dmat3& a, const glm::dmat3& b) {
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) worst = std::max(worst, std::abs(a[c][r] - b[c][r]));
  return worst;
}

glm::quat euler(double zDeg, double xDeg, double yDeg) { return glm::quat(fromBvhEuler({zDeg, xDeg, yDeg})); }

// The values of each MOTION line of a BVH text.
std::vector<std::vector<double>> motionRows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  const std::size_t at = text.find("Frame Time:");
  if (at == std::string::npos) return rows;
  std::istringstream in(text.substr(text.find('\n', at) + 1));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream values(line);
    std::vector<double> row;
    for (double v; values >> v;) row.push_back(v);
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

// Indices of the rotation channels in a MOTION row, from the CHANNELS lines.
std::vector<std::size_t> rotationColumns(const std::string& text) {
  std::vector<std::size_t> columns;
  std::istringstream in(text.substr(0, text.find("MOTION")));
  std::size_t column = 0;
  for (std::string word; in >> word;) {
    if (word != "CHANNELS") continue;
    int count = 0;
    in >> count;
    for (int c = 0; c < count && in >> word; ++c, ++column)
      if (word.find("rotation") != std::string::npos) columns.push_back(column);
  }
  return columns;
}

// A chain of `count` joints, each 0.1 m above its parent.
Skeleton chain(std::size_t count) {
  Skeleton s;
  for (std::size_t j = 0; j < count; ++j) {
    Transform rest;
    rest.translation = j == 0 ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.1f, 0.0f);
    s.addJoint("j" + std::to_string(j), static_cast<int>(j) - 1, rest);
  }
  return s;
}

// A clip turning `joint` by `degrees` about `axis` over `seconds`, keyed every 5 degrees.
Clip spin(int joint, const glm::vec3& axis, float degrees, float seconds) {
  Clip clip;
  clip.name = "spin";
  JointTrack jt;
  jt.joint = joint;
  const int keys = static_cast<int>(std::abs(degrees) / 5.0f) + 1;
  for (int k = 0; k < keys; ++k) {
    const float f = static_cast<float>(k) / static_cast<float>(keys - 1);
    jt.rotation.times.push_back(f * seconds);
    jt.rotation.values.push_back(glm::angleAxis(glm::radians(f * degrees), axis));
  }
  clip.tracks.push_back(jt);
  clip.updateDuration();
  return clip;
}

// ---------------------------------------------------------------- Euler angles

TEST(BvhEulerTest, ConventionIsZThenXThenYOnColumnVectors) {
  // Rz(90) * Rx(90) * Ry(0) sends +Y to +Z by Rx, then +Z stays +Z under Rz.
  const glm::dvec3 y = fromBvhEuler({90.0, 90.0, 0.0}) * glm::dvec3(0, 1, 0);
  EXPECT_NEAR(y.z, 1.0, 1e-12);
  // Ry first: +Z goes to +X under Ry(90), then Rz(90) sends +X to +Y.
  const glm::dvec3 z = fromBvhEuler({90.0, 0.0, 90.0}) * glm::dvec3(0, 0, 1);
  EXPECT_NEAR(z.y, 1.0, 1e-12);
}

TEST(BvhEulerTest, GimbalLockAtPlusAndMinus90AboutXIsExact) {
  for (double x : {90.0, -90.0}) {
    // The pure rotation about X, exactly as a float quaternion holds it.
    const glm::quat pure = glm::angleAxis(static_cast<float>(x * kPi / 180.0), glm::vec3(1, 0, 0));
    const BvhEuler e = toBvhEuler(pure);
    EXPECT_NEAR(e.x, x, 1e-5);
    EXPECT_LT(maxDifference(matrixOf(fromBvhEuler(e)), matrixOf(glm::dquat(pure))), 1e-5) << x;
    // Locked with some z and y folded in, with and without a previous frame.
    for (double z : {-170.0, -30.0, 0.0, 45.0, 120.0}) {
      for (double y : {-60.0, 0.0, 15.0, 175.0}) {
        const glm::quat q = euler(z, x, y);
        const BvhEuler fresh = toBvhEuler(q);
        EXPECT_LT(maxDifference(matrixOf(fromBvhEuler(fresh)), matrixOf(glm::dquat(q))), 1e-5)
            << "z " << z << " x " << x << " y " << y;
        const BvhEuler before{z + 3.0, x - 2.0, y - 4.0};
        const BvhEuler next = toBvhEuler(q, &before);
        EXPECT_LT(maxDifference(matrixOf(fromBvhEuler(next)), matrixOf(glm::dquat(q))), 1e-5);
        EXPECT_LT(std::abs(next.x - before.x), 10.0);
      }
    }
  }
}

TEST(BvhEulerTest, RandomRotationsRoundTripAsMatrices) {
  std::uint32_t state = 12345;
  auto random = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / static_cast<float>(1u << 24) * 2.0f - 1.0f;
  };
  BvhEuler previous;
  for (int i = 0; i < 2000; ++i) {
    const glm::quat q = glm::normalize(glm::quat(random(), random(), random(), random()));
    const BvhEuler e = toBvhEuler(q, i % 2 ? &previous : nullptr);
    EXPECT_LT(maxDifference(matrixOf(fromBvhEuler(e)), matrixOf(glm::dquat(q))), 1e-6) << i;
    if (i % 2 == 0) {
      EXPECT_LE(std::abs(e.x), 90.0 + 1e-9);  // the principal solution without a previous frame
    }
    previous = e;
  }
}

TEST(BvhEulerTest, SpinOf720DegreesAboutYStaysContinuous) {
  const Skeleton s = chain(2);
  const Clip clip = spin(1, glm::vec3(0, 1, 0), 720.0f, 2.0f);
  Diagnostics d;
  BvhWriteOptions options;
  options.frameRate = 30.0f;
  const std::string text = bvhText(s, clip, options, d);
  ASSERT_TRUE(d.ok()) << d.format();
  const auto rows = motionRows(text);
  ASSERT_EQ(rows.size(), 61u);  // 2 s at 30 fps, both ends
  // Root: 3 positions and z x y; joint j1: z x y (its translation is not animated).
  ASSERT_EQ(rows[0].size(), 9u);
  for (std::size_t f = 1; f < rows.size(); ++f)
    for (std::size_t c = 6; c < 9; ++c) EXPECT_LT(std::abs(rows[f][c] - rows[f - 1][c]), 180.0) << f;
  // Each frame turns 12 degrees, and all of it shows in Y.
  EXPECT_NEAR(rows.back()[8] - rows.front()[8], 720.0, 1e-3);
}

TEST(BvhEulerTest, SpinAboutXThroughGimbalLockStaysContinuousAndExact) {
  const Skeleton s = chain(2);
  const Clip clip = spin(1, glm::vec3(1, 0, 0), -720.0f, 4.0f);  // passes x = +-90 eight times
  Diagnostics d;
  BvhWriteOptions options;
  options.frameRate = 36.0f;  // 5 degrees per frame: frames land exactly on the locks
  const std::string text = bvhText(s, clip, options, d);
  ASSERT_TRUE(d.ok()) << d.format();
  const auto rows = motionRows(text);
  ASSERT_EQ(rows.size(), 145u);
  std::vector<Transform> pose(2);
  for (std::size_t f = 0; f < rows.size(); ++f) {
    for (std::size_t c = 6; c < 9 && f > 0; ++c) EXPECT_LT(std::abs(rows[f][c] - rows[f - 1][c]), 10.0) << f;
    sampleClip(clip, static_cast<float>(f) / 36.0f, s.restPose, pose);
    const glm::dquat written = fromBvhEuler({rows[f][6], rows[f][7], rows[f][8]});
    EXPECT_LT(maxDifference(matrixOf(written), matrixOf(glm::dquat(pose[1].rotation))), 1e-5) << f;
  }
}

// ---------------------------------------------------------------- the file

TEST(BvhWriter, WritesHierarchyOffsetsAndEndSites) {
  Skeleton s = chain(3);
  s.restPose[1].rotation = glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 0, 1));  // a rest rotation
  Clip clip;  // no tracks: one frame of the rest pose
  Diagnostics d;
  BvhWriteOptions options;
  options.unitScale = 100.0f;
  options.precision = 3;
  const std::string text = bvhText(s, clip, options, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_EQ(text,
            "HIERARCHY\n"
            "ROOT j0\n{\n  OFFSET 0.000 100.000 0.000\n"
            "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
            "  JOINT j1\n  {\n    OFFSET 0.000 10.000 0.000\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
            "    JOINT j2\n    {\n      OFFSET 0.000 10.000 0.000\n      CHANNELS 3 Zrotation Xrotation Yrotation\n"
            "      End Site\n      {\n        OFFSET 0.000 10.000 0.000\n      }\n    }\n  }\n}\n"
            "MOTION\nFrames: 1\nFrame Time: 0.0333333333\n"
            "0.000 100.000 0.000 0.000 0.000 0.000 30.000 0.000 0.000 0.000 0.000 0.000\n");
}

TEST(BvhWriter, AnimatedTranslationGetsPositionChannels) {
  const Skeleton s = chain(3);
  Clip clip;
  JointTrack jt;
  jt.joint = 2;
  jt.translation.times = {0.0f, 1.0f};
  jt.translation.values = {glm::vec3(0.0f, 0.1f, 0.0f), glm::vec3(0.0f, 0.2f, 0.0f)};
  clip.tracks.push_back(jt);
  JointTrack still;  // a translation track that never leaves rest adds no channels
  still.joint = 1;
  still.translation.times = {0.0f, 1.0f};
  still.translation.values = {glm::vec3(0.0f, 0.1f, 0.0f), glm::vec3(0.0f, 0.1f, 0.0f)};
  clip.tracks.insert(clip.tracks.begin(), still);
  clip.updateDuration();
  Diagnostics d;
  const std::string text = bvhText(s, clip, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(text.find("JOINT j1\n  {\n    OFFSET 0.000000 0.100000 0.000000\n    CHANNELS 3 "), std::string::npos)
      << text.substr(0, 600);
  EXPECT_NE(text.find("JOINT j2\n    {\n      OFFSET 0.000000 0.100000 0.000000\n      CHANNELS 6 "), std::string::npos)
      << text.substr(0, 600);
  const auto rows = motionRows(text);
  ASSERT_FALSE(rows.empty());
  ASSERT_EQ(rows.back().size(), 6u + 3u + 6u);
  EXPECT_NEAR(rows.back()[10], 0.2, 1e-6);  // j2's Yposition holds the full local translation
}

TEST(BvhWriter, SanitizesAndDeduplicatesNamesWithAWarning) {
  Skeleton s;
  s.addJoint("Hips", -1, {});
  s.addJoint("Left Arm", 0, {});
  s.addJoint("", 1, {});
  s.addJoint("a{b}", 0, {});
  s.addJoint("Hips", 0, {});
  s.addJoint("Left_Arm", 0, {});
  const std::vector<std::string> expected = {"Hips", "Left_Arm", "joint_2", "a_b_", "Hips_2", "Left_Arm_2"};
  EXPECT_EQ(bvhJointNames(s), expected);
  Diagnostics d;
  const std::string text = bvhText(s, {}, {}, d, "names.bvh");
  ASSERT_TRUE(d.ok()) << d.format();
  for (const std::string& name : expected) EXPECT_NE(text.find(" " + name + "\n"), std::string::npos) << name;
  EXPECT_TRUE(mentions(d, Severity::Warning, "'Left Arm' -> 'Left_Arm'")) << d.format();
  EXPECT_TRUE(mentions(d, Severity::Warning, "joint 2 (unnamed) -> 'joint_2'")) << d.format();
  EXPECT_TRUE(mentions(d, Severity::Warning, "'Hips' -> 'Hips_2'")) << d.format();
  EXPECT_EQ(d.items[0].file, "names.bvh");
}

TEST(BvhWriter, SeveralRootsGetASyntheticRoot) {
  Skeleton s;
  s.addJoint("a", -1, {});
  s.addJoint("b", -1, {});
  s.addJoint("MarionetteRoot", 1, {});
  Diagnostics d;
  const std::string text = bvhText(s, {}, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_EQ(text.rfind("HIERARCHY\nROOT MarionetteRoot_2\n", 0), 0u) << text;
  EXPECT_NE(text.find("  JOINT a\n"), std::string::npos);
  EXPECT_NE(text.find("    JOINT MarionetteRoot\n"), std::string::npos);
  EXPECT_TRUE(mentions(d, Severity::Warning, "synthetic root 'MarionetteRoot_2'")) << d.format();
  // Leaves without a bone length: a small End Site (1 cm when no bone has a length).
  EXPECT_NE(text.find("  End Site\n      {\n        OFFSET 0.000000 0.010000 0.000000\n"), std::string::npos) << text;
}

TEST(BvhWriter, ZeroLengthLeafGetsATenthOfTheMeanBoneAsEndSite) {
  Skeleton s = chain(3);
  s.restPose[1].translation = glm::vec3(0.3f, 0.0f, 0.0f);
  s.restPose[2].translation = glm::vec3(0.0f);  // mean bone length 0.3 (zero-length bones do not count)
  Diagnostics d;
  const std::string text = bvhText(s, {}, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(text.find("End Site\n      {\n        OFFSET 0.000000 0.030000 0.000000\n"), std::string::npos) << text;
}

TEST(BvhWriter, ScaleIsDroppedWithAWarningNamingTheJoints) {
  Skeleton s = chain(3);
  s.restPose[1].scale = glm::vec3(2.0f);
  Clip clip;
  JointTrack jt;
  jt.joint = 2;
  jt.scale.times = {0.0f, 1.0f};
  jt.scale.values = {glm::vec3(1.0f), glm::vec3(1.0f, 0.5f, 1.0f)};
  clip.tracks.push_back(jt);
  clip.updateDuration();
  Diagnostics d;
  const std::string text = bvhText(s, clip, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_FALSE(text.empty());
  EXPECT_TRUE(mentions(d, Severity::Warning, "'j1', 'j2'")) << d.format();
  EXPECT_FALSE(mentions(d, Severity::Warning, "'j0'")) << d.format();

  Diagnostics unscaled;
  (void)bvhText(chain(3), Clip{}, {}, unscaled);
  EXPECT_FALSE(unscaled.hasWarnings()) << unscaled.format();
}

TEST(BvhWriter, NanInTheClipIsAnErrorAndWritesNothing) {
  const Skeleton s = chain(2);
  Clip clip = spin(1, glm::vec3(0, 1, 0), 90.0f, 1.0f);
  clip.tracks[0].rotation.values[3].x = std::nanf("");
  const std::string path = tempPath("nan.bvh");
  fs::remove(path);
  const Diagnostics d = writeBvh(path, s, clip);
  EXPECT_FALSE(d.ok());
  EXPECT_TRUE(mentions(d, Severity::Error, "non-finite")) << d.format();
  EXPECT_TRUE(mentions(d, Severity::Error, "'j1'")) << d.format();
  EXPECT_EQ(d.items.back().file, path);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));

  Skeleton badRest = chain(2);
  badRest.restPose[1].translation.y = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(writeBvh(path, badRest, {}).ok());
  EXPECT_FALSE(fs::exists(path));
}

TEST(BvhWriter, UnwritablePathIsAnErrorNamingIt) {
  const std::string missingDir = tempPath("no_such_dir") + "/out.bvh";
  const Diagnostics d = writeBvh(missingDir, chain(2), {});
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.items.back().file, missingDir);
  EXPECT_TRUE(mentions(d, Severity::Error, "cannot open for writing")) << d.format();

  const std::string dir = fs::temp_directory_path().string();
  const Diagnostics onDir = writeBvh(dir, chain(2), {});
  ASSERT_FALSE(onDir.ok());
  EXPECT_TRUE(mentions(onDir, Severity::Error, "is a directory")) << onDir.format();
}

TEST(BvhWriter, RootTransformThatMirrorsOrScalesUnevenlyIsAnError) {
  Skeleton mirrored = chain(2);
  mirrored.rootTransform = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
  Diagnostics d;
  EXPECT_TRUE(bvhText(mirrored, {}, {}, d, "m.bvh").empty());
  EXPECT_TRUE(mentions(d, Severity::Error, "mirrors")) << d.format();

  Skeleton squashed = chain(2);
  squashed.rootTransform = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.5f, 1.0f));
  Diagnostics e;
  EXPECT_TRUE(bvhText(squashed, {}, {}, e, "s.bvh").empty());
  EXPECT_TRUE(mentions(e, Severity::Error, "non-uniformly")) << e.format();
}

TEST(BvhWriter, UniformRootScaleAndRotationAreBakedIntoTheRoot) {
  Skeleton s = chain(2);
  // Z-up to Y-up and centimetres to metres, as an exporter's root node might say.
  s.rootTransform =
      glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(0.01f)), glm::radians(-90.0f), glm::vec3(1, 0, 0));
  s.restPose[0].translation = glm::vec3(0.0f, 0.0f, 100.0f);  // 1 m up in the file's Z-up centimetres
  s.restPose[1].translation = glm::vec3(0.0f, 0.0f, 10.0f);
  Diagnostics d;
  const std::string text = bvhText(s, {}, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(text.find("ROOT j0\n{\n  OFFSET 0.000000 1.000000 0.000000\n"), std::string::npos) << text;
  EXPECT_NE(text.find("OFFSET 0.000000 0.000000 0.100000\n"), std::string::npos) << text;
  const auto rows = motionRows(text);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(rows[0][1], 1.0, 1e-6);
  EXPECT_NEAR(rows[0][4], -90.0, 1e-6);  // the root's Xrotation carries the Z-up to Y-up turn
}

TEST(BvhWriter, FrameRateFromKeySpacingOrDefault) {
  const Skeleton s = chain(2);
  auto frameTime = [&](const Clip& clip, float rate) {
    Diagnostics d;
    BvhWriteOptions options;
    options.frameRate = rate;
    const std::string text = bvhText(s, clip, options, d);
    const std::size_t at = text.find("Frame Time: ");
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + 12));
  };
  EXPECT_NEAR(frameTime({}, 0.0f), 1.0 / 30.0, 1e-9);                                        // no keys
  EXPECT_NEAR(frameTime(spin(1, glm::vec3(0, 1, 0), 90.0f, 1.8f), 0.0f), 0.1, 1e-7);         // 19 keys over 1.8 s
  EXPECT_NEAR(frameTime(spin(1, glm::vec3(0, 1, 0), 900.0f, 0.9f), 0.0f), 1.0 / 120, 1e-9);  // 200 fps, capped
  EXPECT_NEAR(frameTime(spin(1, glm::vec3(0, 1, 0), 90.0f, 1.8f), 24.0f), 1.0 / 24, 1e-9);   // asked for
}

// ---------------------------------------------------------------- round trips through Assimp

#ifdef MARIONETTE_HAS_ASSIMP

struct RoundTripCase {
  std::string path;
  std::string clip;  // empty: the first
  float unitScale = 1.0f;
};

struct Measured {
  double maxError = 0.0;
  double height = 0.0;
  std::size_t frames = 0;
  double frameRate = 0.0;
  double maxAngleStep = 0.0;  // degrees, largest change of a rotation channel between frames
};

std::vector<glm::vec3> modelPositions(const Skeleton& s, const std::vector<Transform>& local) {
  std::vector<glm::mat4> model(s.jointCount());
  localToModel(s, local, model);
  std::vector<glm::vec3> out;
  for (const glm::mat4& m : model) out.emplace_back(m[3]);
  return out;
}

// Largest extent of the rest pose's joint positions: the character's height.
double heightOf(const Skeleton& s) {
  const std::vector<glm::vec3> p = modelPositions(s, s.restPose);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& v : p) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::vec3 e = hi - lo;
  return std::max({e.x, e.y, e.z});
}

// Writes `clip` as BVH, reads it back through Assimp and measures the largest
// model-space joint distance over the written frames.
void writeAndReread(const Skeleton& s, const Clip& clip, const std::string& out, float unitScale, Measured& m) {
  BvhWriteOptions options;
  options.unitScale = unitScale;
  const Diagnostics written = writeBvh(out, s, clip, options);
  ASSERT_TRUE(written.ok()) << written.format();
  if (written.hasWarnings()) std::cout << written.format();

  const std::string text = readFile(out);
  const auto rows = motionRows(text);
  const std::vector<std::size_t> columns = rotationColumns(text);
  ASSERT_FALSE(columns.empty());
  for (std::size_t f = 1; f < rows.size(); ++f)
    for (std::size_t col : columns)
      m.maxAngleStep = std::max(m.maxAngleStep, std::abs(rows[f][col] - rows[f - 1][col]));

  ImportOptions back;
  back.loadMeshes = false;
  back.extraScale = 1.0f / unitScale;  // the file is in file units; compare in the source's
  const ImportResult reread = importAsset(out, back);
  ASSERT_TRUE(reread.ok()) << reread.diagnostics.format() << "\n" << readFile(out).substr(0, 2000);
  const Skeleton& r = reread.asset->skeleton;
  ASSERT_EQ(reread.asset->clips.size(), 1u);
  const Clip& rc = reread.asset->clips[0];

  const std::vector<std::string> names = bvhJointNames(s);
  std::vector<std::size_t> match(s.jointCount());
  for (std::size_t j = 0; j < s.jointCount(); ++j) {
    const int k = r.findJoint(names[j]);
    ASSERT_GE(k, 0) << names[j];
    match[j] = static_cast<std::size_t>(k);
  }
  // The written frames are the re-read clip's keys (every joint has one per frame).
  ASSERT_FALSE(rc.tracks.empty());
  const std::vector<float>& times = rc.tracks[0].rotation.times;
  m.frames = times.size();
  m.frameRate = times.size() > 1 ? static_cast<double>(times.size() - 1) / times.back() : 0.0;
  m.height = heightOf(s);
  ASSERT_GT(m.height, 0.0);
  std::vector<Transform> sp(s.jointCount()), rp(r.jointCount());
  SamplingCursor sc, rcur;
  sc.reset(clip);
  rcur.reset(rc);
  for (float t : times) {
    sampleClip(clip, std::min(t, clip.duration), s.restPose, sp, &sc);
    sampleClip(rc, t, r.restPose, rp, &rcur);
    const std::vector<glm::vec3> ps = modelPositions(s, sp), pr = modelPositions(r, rp);
    for (std::size_t j = 0; j < s.jointCount(); ++j)
      m.maxError = std::max(m.maxError, static_cast<double>(glm::length(ps[j] - pr[match[j]])));
  }
  fs::remove(out);
}

void roundTrip(const RoundTripCase& c, Measured& m) {
  MARIONETTE_REQUIRE_FILE(c.path);
  ImportOptions noMeshes;
  noMeshes.loadMeshes = false;
  const ImportResult source = importAsset(c.path, noMeshes);
  ASSERT_TRUE(source.ok()) << source.diagnostics.format();
  const Asset& a = *source.asset;
  ASSERT_FALSE(a.clips.empty());
  const Clip* clip = &a.clips[0];
  if (!c.clip.empty()) {
    auto it = std::find_if(a.clips.begin(), a.clips.end(), [&](const Clip& k) { return k.name == c.clip; });
    ASSERT_NE(it, a.clips.end()) << c.clip;
    clip = &*it;
  }
  writeAndReread(a.skeleton, *clip, tempPath(fs::path(c.path).stem().string() + ".bvh"), c.unitScale, m);
}

TEST(BvhWriterRoundTrip, RealMotionsAndCharactersKeepTheirJointPositions) {
  const std::vector<RoundTripCase> cases = {
      {sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), ""},
      {sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), ""},
      {sharedAsset("motions/bvh/pirouette.bvh"), ""},
      {assimpModel("BVH/01_01.bvh"), ""},
      {assimpModel("BVH/Boxing_Toes.bvh"), ""},
      {sharedAsset("characters/RobotExpressive.glb"), "Walking"},
      {sharedAsset("characters/CesiumMan.glb"), ""},
      {sharedAsset("characters/RobotExpressive.glb"), "Walking", 100.0f},  // centimetres in the file
  };
  for (const RoundTripCase& c : cases) {
    SCOPED_TRACE(c.path + " " + c.clip);
    Measured m;
    roundTrip(c, m);
    if (HasFatalFailure()) return;
    const double relative = m.maxError / m.height;
    std::cout << "[ bvh round trip ] " << fs::path(c.path).filename().string() << (c.clip.empty() ? "" : " ") << c.clip
              << " unitScale " << c.unitScale << ": " << m.frames << " frames at " << m.frameRate
              << " fps, max joint error " << m.maxError << " / height " << m.height << " = " << relative
              << ", largest Euler step " << m.maxAngleStep << " deg\n";
    EXPECT_LT(relative, 1e-4);
    // Unwrapping keeps every channel within 180 degrees of its previous frame; a
    // larger step is a wrap (179 -> -179) that readers would interpolate as a spin.
    // Steps near 180 do occur where a joint passes close to gimbal lock (x = +-90).
    EXPECT_LE(m.maxAngleStep, 180.0);
  }
}

TEST(BvhWriterRoundTrip, SeveralRootsInARotatedScaledSpaceWithMovingJoints) {
  // Z-up, half scale and offset (an exporter's root node), two roots, rest
  // rotations, and a non-root joint that slides: the paths real files did not take.
  Skeleton s;
  s.rootTransform =
      glm::rotate(glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 2.0f)), glm::vec3(0.5f)),
                  glm::radians(-90.0f), glm::vec3(1, 0, 0));
  auto rest = [](glm::vec3 t, float degrees, glm::vec3 axis) {
    Transform r;
    r.translation = t;
    r.rotation = glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
    return r;
  };
  s.addJoint("pelvis", -1, rest({0.0f, 0.0f, 1.0f}, 20.0f, {0, 0, 1}));
  s.addJoint("spine", 0, rest({0.0f, 0.0f, 0.3f}, -35.0f, {1, 1, 0}));
  s.addJoint("head", 1, rest({0.0f, 0.05f, 0.25f}, 10.0f, {0, 1, 0}));
  s.addJoint("prop", -1, rest({0.5f, 0.0f, 0.8f}, 90.0f, {0, 1, 0}));
  s.addJoint("tip", 3, rest({0.1f, 0.0f, 0.0f}, 0.0f, {0, 1, 0}));
  Clip clip;
  clip.name = "test";
  for (int j : {0, 1, 3, 4}) {
    JointTrack jt;
    jt.joint = j;
    for (int k = 0; k <= 30; ++k) {
      const float t = static_cast<float>(k) / 30.0f;
      const float turn = glm::radians(400.0f * t * static_cast<float>(j + 1));
      const Transform& r = s.restPose[static_cast<std::size_t>(j)];
      jt.rotation.times.push_back(t);
      jt.rotation.values.push_back(
          r.rotation * glm::angleAxis(turn, glm::normalize(glm::vec3(1.0f, 2.0f, 0.5f * static_cast<float>(j)))));
      if (j == 0 || j == 4) {
        jt.translation.times.push_back(t);
        jt.translation.values.push_back(r.translation + glm::vec3(0.3f * t, 0.1f * std::sin(6.0f * t), 0.0f));
      }
    }
    clip.tracks.push_back(jt);
  }
  clip.updateDuration();

  Diagnostics d;
  const std::string text = bvhText(s, clip, {}, d);
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_TRUE(mentions(d, Severity::Warning, "synthetic root")) << d.format();
  EXPECT_NE(text.find("    JOINT tip\n    {\n      OFFSET 0.050000 0.000000 0.000000\n      CHANNELS 6 "),
            std::string::npos)
      << text.substr(0, 1500);

  Measured m;
  writeAndReread(s, clip, tempPath("two_roots.bvh"), 1.0f, m);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_EQ(m.frames, 31u);
  std::cout << "[ bvh round trip ] two roots, rotated scaled space: max joint error " << m.maxError << " / height "
            << m.height << " = " << m.maxError / m.height << "\n";
  EXPECT_LT(m.maxError / m.height, 1e-5) << m.maxError;
}

TEST(BvhWriterRoundTrip, GimbalLockThroughAssimp) {
  // Joint j1 at exactly +90 then -90 about X, with turns about Z and Y folded in.
  const Skeleton s = chain(3);
  Clip clip;
  JointTrack jt;
  jt.joint = 1;
  const std::vector<glm::quat> rotations = {glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0)),
                                            glm::angleAxis(glm::radians(-90.0f), glm::vec3(1, 0, 0)),
                                            euler(40.0, 90.0, -25.0), euler(-130.0, -90.0, 70.0)};
  for (std::size_t k = 0; k < rotations.size(); ++k) {
    jt.rotation.times.push_back(static_cast<float>(k));
    jt.rotation.values.push_back(rotations[k]);
  }
  jt.rotation.interpolation = Interpolation::Step;
  clip.tracks.push_back(jt);
  clip.updateDuration();
  const std::string out = tempPath("gimbal.bvh");
  BvhWriteOptions options;
  options.frameRate = 1.0f;
  ASSERT_TRUE(writeBvh(out, s, clip, options).ok());
  const ImportResult back = importAsset(out);
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const JointTrack& j1 = back.asset->clips[0].tracks[1];
  ASSERT_EQ(back.asset->skeleton.names[1], "j1");
  ASSERT_EQ(j1.rotation.keyCount(), rotations.size());
  for (std::size_t k = 0; k < rotations.size(); ++k)
    EXPECT_LT(maxDifference(matrixOf(glm::dquat(j1.rotation.values[k])), matrixOf(glm::dquat(rotations[k]))), 1e-5)
        << k;
  fs::remove(out);
}

#endif  // MARIONETTE_HAS_ASSIMP

}  // namespace
}  // namespace marionette
