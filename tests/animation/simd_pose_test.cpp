// The 4-wide (SSE2) pose code gives the same bits as its scalar definition: local-to-model
// against localToModelScalar, the fused palette against skinningPalette, and the blend
// accumulator against blendPoses, on skeletons whose joint counts leave every tail length
// (n mod 4), with masks, zero weights, weights below and above 1, and rotations that cancel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <random>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/pose.hpp"

using namespace marionette;

namespace {

bool sameBits(const void* a, const void* b, std::size_t bytes) { return std::memcmp(a, b, bytes) == 0; }

// The FMA build's promise (pose.hpp): within 2e-6 of the scalar values, relative to each
// matrix's largest element (a chain of products carries absolute, not per-element, error).
constexpr float kFusedBound = 2e-6f;

// Runs check(exact) under each SIMD path (pose.hpp); exact: the path promises the scalar bits.
template <class Check>
void onEverySimdPath(Check check) {
  for (const SimdPath path : {SimdPath::Baseline, SimdPath::Portable, SimdPath::Auto}) {
    setSimdPath(path);
    check(std::string(activeSimdPath()) != "avx2+fma");
  }
  setSimdPath(SimdPath::Auto);
}

// Transforms equal in their bits (exact), or each float within kFusedBound of the
// definition's, relative to its size or to 1, whichever is larger (the FMA build).
bool sameTransforms(const Transform* got, const Transform* want, std::size_t n, bool exact) {
  if (exact) return sameBits(got, want, n * sizeof(Transform));
  const float* a = &got[0].translation.x;
  const float* b = &want[0].translation.x;
  for (std::size_t i = 0; i < n * 10; ++i)
    if (!(std::abs(a[i] - b[i]) <= kFusedBound * std::max(1.0f, std::abs(b[i])))) return false;
  return true;
}

float largestRelativeDifference(const std::vector<glm::mat4>& got, const std::vector<glm::mat4>& want) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < got.size(); ++i) {
    float scale = 0.0f, diff = 0.0f;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        scale = std::max(scale, std::abs(want[i][c][r]));
        diff = std::max(diff, std::abs(got[i][c][r] - want[i][c][r]));
      }
    if (std::isnan(diff)) return diff;  // fails the bound
    worst = std::max(worst, scale > 0.0f ? diff / scale : diff);
  }
  return worst;
}

Transform randomTransform(std::mt19937& rng, bool scaled) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Transform t;
  t.translation = {u(rng) * 0.3f, u(rng) * 0.3f + 0.1f, u(rng) * 0.3f};
  t.rotation = safeNormalize(glm::quat(u(rng), u(rng), u(rng), u(rng)));
  if (scaled) t.scale = {1.0f + 0.5f * u(rng), 1.0f + 0.5f * u(rng), 1.0f + 0.5f * u(rng)};
  return t;
}

// A branching skeleton: each joint's parent is one of the few before it, some are roots.
Skeleton randomSkeleton(std::mt19937& rng, int joints) {
  Skeleton s;
  for (int j = 0; j < joints; ++j) {
    const int parent = j == 0 || j % 11 == 5 ? -1 : std::max(0, j - 1 - static_cast<int>(rng() % 3));
    s.addJoint("j" + std::to_string(j), parent, randomTransform(rng, j % 3 == 0),
               Transform{randomTransform(rng, false)}.matrix(), true);
  }
  s.rootTransform = Transform{{0.1f, -0.2f, 0.3f}, glm::angleAxis(0.4f, glm::vec3(0, 0, 1)), {0.01f, 0.01f, 0.01f}}.matrix();
  return s;
}

}  // namespace

TEST(SimdPose, LocalToModelIsBitIdenticalToTheScalarDefinition) {
  std::mt19937 rng(7);
  float fusedWorst = 0.0f;
  for (int joints : {1, 2, 3, 4, 5, 6, 7, 8, 9, 43, 54, 67}) {
    const Skeleton s = randomSkeleton(rng, joints);
    std::vector<Transform> local(static_cast<std::size_t>(joints));
    for (Transform& t : local) t = randomTransform(rng, true);
    std::vector<glm::mat4> wide(local.size()), scalar(local.size()), fused(local.size()), palette(local.size()),
        reference(local.size());
    setSimdPath(SimdPath::Portable);
    localToModel(s, local, wide);
    localToModelScalar(s, local, scalar);
    EXPECT_TRUE(sameBits(wide.data(), scalar.data(), wide.size() * sizeof(glm::mat4))) << joints << " joints";
    for (std::size_t j = 0; j < local.size(); ++j) reference[j] = affineMultiply(scalar[j], s.inverseBind[j]);
    const PaletteBasis basis = PaletteBasis::of(s.inverseBind);
    // SSE2 and the AVX build (where the CPU has it) give the scalar bits; the FMA build
    // (Auto, where the CPU has AVX2 + FMA) is held within its stated bound instead.
    for (const SimdPath path : {SimdPath::Baseline, SimdPath::Portable, SimdPath::Auto}) {
      setSimdPath(path);
      const bool exact = std::string(activeSimdPath()) != "avx2+fma";
      const auto matches = [&](const std::vector<glm::mat4>& got, const std::vector<glm::mat4>& want) {
        if (exact) return sameBits(got.data(), want.data(), got.size() * sizeof(glm::mat4));
        const float worst = largestRelativeDifference(got, want);
        fusedWorst = std::max(fusedWorst, worst);
        return worst <= kFusedBound;
      };
      for (const PaletteBasis* b : {static_cast<const PaletteBasis*>(nullptr), &basis}) {
        std::fill(fused.begin(), fused.end(), glm::mat4(0.0f));
        std::fill(palette.begin(), palette.end(), glm::mat4(0.0f));
        localToModelAndPalette(s, local, fused, palette, b);
        EXPECT_TRUE(matches(fused, scalar)) << joints << " joints, " << activeSimdPath() << (b ? ", basis" : "");
        EXPECT_TRUE(matches(palette, reference)) << joints << " joints, " << activeSimdPath() << (b ? ", basis" : "");
      }
      localToModel(s, local, wide);
      EXPECT_TRUE(matches(wide, scalar)) << joints << " joints, " << activeSimdPath();
    }
    setSimdPath(SimdPath::Auto);
    skinningPalette(scalar, s.inverseBind, palette);
    EXPECT_TRUE(sameBits(palette.data(), reference.data(), palette.size() * sizeof(glm::mat4))) << joints << " joints";
    // And the value is the definition's: the full product of the local matrices.
    const glm::mat4 last = modelMatrixOf(s, local, joints - 1);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(wide.back()[c][r], last[c][r], 1e-5f);
  }
  if (fusedWorst > 0.0f) std::printf("FMA build: largest difference %.2e of the largest element (bound %.0e)\n", fusedWorst, kFusedBound);
}

TEST(SimdPose, FusedPaletteKeepsTheSpanContract) {
  std::mt19937 rng(3);
  const Skeleton s = randomSkeleton(rng, 10);
  std::vector<Transform> local(10);
  for (Transform& t : local) t = randomTransform(rng, true);
  std::vector<glm::mat4> model(10, glm::mat4(7.0f)), palette(6, glm::mat4(7.0f));
  localToModelAndPalette(s, std::span<const Transform>(local).first(8), model, palette);
  EXPECT_EQ(model[8], glm::mat4(7.0f));  // past the pose: untouched
  EXPECT_NE(model[7], glm::mat4(7.0f));
  EXPECT_NE(palette[5], glm::mat4(7.0f));
}

TEST(SimdPose, BlendAccumulatorIsBitIdenticalToBlendPoses) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int joints : {1, 3, 4, 5, 7, 8, 43, 54}) {
    const std::size_t n = static_cast<std::size_t>(joints);
    std::vector<Transform> rest(n), a(n), b(n), c(n), out1(n), out2(n);
    for (std::size_t j = 0; j < n; ++j) {
      rest[j] = randomTransform(rng, j % 2 == 0);
      a[j] = randomTransform(rng, true);
      b[j] = randomTransform(rng, false);
      c[j] = randomTransform(rng, true);
      if (j % 5 == 2) b[j].rotation = -a[j].rotation;  // same rotation, other sign
      if (j % 7 == 3) {  // a and c cancel: equal weight, opposite rotation after alignment
        c[j] = a[j];
        c[j].rotation = glm::quat(-a[j].rotation.w, a[j].rotation.x, -a[j].rotation.y, a[j].rotation.z);
      }
    }
    std::vector<float> mask(n), shortMask(n / 2 + 1);
    for (std::size_t j = 0; j < n; ++j) mask[j] = j % 4 == 1 ? 0.0f : u(rng);
    for (float& m : shortMask) m = u(rng);
    for (const auto& weights : {std::array<float, 3>{0.5f, 0.3f, 0.2f}, std::array<float, 3>{0.1f, 0.2f, 0.0f},
                                std::array<float, 3>{1.5f, 0.0f, 1.5f}, std::array<float, 3>{2.0f, 3.0f, 0.7f}}) {
      for (int masks = 0; masks < 3; ++masks) {
        const std::span<const float> m1 = masks == 0 ? std::span<const float>() : std::span<const float>(mask);
        const std::span<const float> m2 = masks == 2 ? std::span<const float>(shortMask) : std::span<const float>();
        const BlendLayer layers[] = {{a, weights[0]}, {b, weights[1], m1}, {c, weights[2], m2}};
        blendPoses(layers, rest, out1);
        onEverySimdPath([&](bool exact) {
          BlendAccumulator acc;
          acc.reset(n);
          acc.addNormal(a, weights[0], {}, rest);
          acc.addNormal(b, weights[1], m1, rest);
          acc.addNormal(c, weights[2], m2, rest);
          acc.finish(rest, out2);
          EXPECT_TRUE(sameTransforms(out2.data(), out1.data(), n, exact))
              << joints << " joints, weights " << weights[0] << " " << weights[1] << " " << weights[2] << ", masks "
              << masks << ", " << activeSimdPath();
        });
      }
    }
  }
}

TEST(SimdPose, BlendAccumulatorRereadsTheRestPoseAfterReset) {
  std::mt19937 rng(5);
  std::vector<Transform> rest(9), pose(9), out1(9), out2(9);
  for (Transform& t : pose) t = randomTransform(rng, false);
  BlendAccumulator acc;
  for (int round = 0; round < 2; ++round) {  // the same span, new values: reset must forget the old ones
    for (Transform& t : rest) t = randomTransform(rng, false);
    const BlendLayer layers[] = {{pose, 0.4f}};
    blendPoses(layers, rest, out1);
    acc.reset(9);
    acc.addNormal(pose, 0.4f, {}, rest);
    acc.finish(rest, out2);
    // The FMA build rounds differently, but a stale rest pose would be off by far more.
    EXPECT_TRUE(sameTransforms(out2.data(), out1.data(), 9, std::string(activeSimdPath()) != "avx2+fma")) << "round " << round;
  }
}

// blendOver (two groups of four joints at a time, the last ones padded) against its
// definition one joint at a time: glm::mix and slerpShortest, the layer as it is at weight 1. Poses include rotations
// past 90 degrees apart (the halved arc) beside ones that are not, in the same group.
TEST(SimdPose, BlendOverIsBitIdenticalToSlerpOneJointAtATime) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int joints : {1, 2, 3, 4, 5, 7, 8, 9, 12, 15, 16, 17, 43, 54}) {
    for (const float weight : {0.0f, 0.3f, 0.5f, 0.77f, 1.0f, 1.7f}) {
      for (int masked = 0; masked < 3; ++masked) {
        const std::size_t n = static_cast<std::size_t>(joints);
        std::vector<Transform> pose(n), layer(n);
        for (std::size_t j = 0; j < n; ++j) {
          pose[j] = randomTransform(rng, true);
          layer[j] = j % 3 == 0 ? randomTransform(rng, true) : pose[j];  // far apart, or close
          if (j % 3 == 1) layer[j].rotation = safeNormalize(pose[j].rotation * glm::angleAxis(0.3f, glm::vec3(0, 1, 0)));
          if (j % 5 == 2) layer[j].rotation = -layer[j].rotation;  // the other sign of the same rotation
        }
        // No mask; a mask with zeros, fractions and values over 1; a mask shorter than the pose.
        std::vector<float> mask;
        if (masked > 0)
          for (std::size_t j = 0; j < (masked == 1 ? n : n / 2); ++j) mask.push_back(j % 4 == 0 ? 0.0f : j % 4 == 1 ? 1.0f : 1.5f * u(rng));
        std::vector<Transform> expected = pose;
        const float lw = std::min(weight, 1.0f);
        for (std::size_t j = 0; j < n; ++j) {
          const float w = std::min(mask.empty() ? lw : (j < mask.size() ? lw * mask[j] : 0.0f), 1.0f);
          if (w <= 0.0f) continue;
          if (w >= 1.0f) {
            expected[j] = layer[j];
            continue;
          }
          expected[j].translation = glm::mix(pose[j].translation, layer[j].translation, w);
          expected[j].scale = glm::mix(pose[j].scale, layer[j].scale, w);
          expected[j].rotation = slerpShortest(pose[j].rotation, layer[j].rotation, w);
        }
        onEverySimdPath([&](bool exact) {
          std::vector<Transform> blended = pose;
          blendOver(blended, layer, weight, mask);
          EXPECT_TRUE(sameTransforms(blended.data(), expected.data(), n, exact))
              << joints << " joints, weight " << weight << ", mask " << masked << ", " << activeSimdPath();
        });
      }
    }
  }
}
