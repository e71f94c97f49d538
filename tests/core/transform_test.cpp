#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "marionette/core/transform.hpp"
#include "slerp_acos.hpp"

using namespace marionette;

TEST(Transform, SafeNormalizeRejectsZeroAndNaN) {
  EXPECT_EQ(safeNormalize(glm::quat(0, 0, 0, 0)), glm::quat(1, 0, 0, 0));
  EXPECT_EQ(safeNormalize(glm::quat(NAN, 0, 0, 0)), glm::quat(1, 0, 0, 0));
  glm::quat q = safeNormalize(glm::quat(2, 0, 0, 0));
  EXPECT_FLOAT_EQ(q.w, 1.0f);
}

namespace {

// slerp by its definition, in double precision.
glm::dquat exactSlerp(const glm::quat& a, const glm::quat& b, double t) {
  const glm::dquat qa = glm::normalize(glm::dquat(a)), qb0 = glm::normalize(glm::dquat(b));
  const glm::dquat qb = glm::dot(qa, qb0) < 0.0 ? -qb0 : qb0;
  // The arc from the chord, accurate for close rotations too (acos of the dot is not).
  const double theta = 2.0 * std::atan2(glm::length(qa - qb), glm::length(qa + qb));
  if (theta < 1e-12) return qa;
  return glm::normalize(qa * (std::sin((1.0 - t) * theta) / std::sin(theta)) + qb * (std::sin(t * theta) / std::sin(theta)));
}

// The angle between two rotations, in radians (q and -q are the same rotation). q is
// normalized in double first: a float quaternion is unit to 6e-8, which alone would
// read as 3e-4 rad here.
double angleBetween(const glm::quat& q, const glm::dquat& exact) {
  const double d = std::min(std::abs(glm::dot(glm::normalize(glm::dquat(q)), exact)), 1.0);
  return 2.0 * std::atan2(std::sqrt(std::max(0.0, 1.0 - d * d)), d);
}

}  // namespace

// slerpShortest's series (no acos, no sin) against slerp in double precision: random
// pairs (most past 90 degrees apart, where the arc is halved), pairs within 3 degrees,
// nearly opposite ones, and pairs either side of the 90-degree switch, over t in [0, 1].
// Prints the worst errors, and those of the acos / sin form it replaced (docs/accuracy.md).
TEST(Transform, SlerpSeriesIsWithinAMicroradianOfTheExactSlerp) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const auto randomUnit = [&] { return safeNormalize(glm::quat(u(rng), u(rng), u(rng), u(rng))); };
  std::vector<std::pair<glm::quat, glm::quat>> far, close;
  for (int i = 0; i < 20000; ++i) {
    far.emplace_back(randomUnit(), randomUnit());
    const glm::quat a = randomUnit();
    const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng) + 2.0f));
    close.emplace_back(a, safeNormalize(a * glm::angleAxis(0.05f * std::abs(u(rng)), axis)));
  }
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f));
  for (const float angle : {1e-6f, 1e-4f, 0.01f, 0.03f, 0.3f, 1.0f, 1.5707f, 1.5708f, 1.5709f, 2.5f, 3.1f, 3.14159f}) {
    const glm::quat a = randomUnit();
    far.emplace_back(a, safeNormalize(a * glm::angleAxis(angle, axis)));
    far.emplace_back(a, -safeNormalize(a * glm::angleAxis(angle, axis)));  // the other sign: the same rotation
  }
  struct Worst {
    double series = 0.0, acos = 0.0, length = 0.0;
  };
  const auto measure = [](const std::vector<std::pair<glm::quat, glm::quat>>& pairs) {
    Worst w;
    for (const auto& [a, b] : pairs)
      for (int k = 0; k <= 20; ++k) {
        const float t = static_cast<float>(k) / 20.0f;
        const glm::dquat exact = exactSlerp(a, b, t);
        const glm::quat q = slerpShortest(a, b, t);
        w.series = std::max(w.series, angleBetween(q, exact));
        w.acos = std::max(w.acos, angleBetween(test::slerpAcos(a, b, t), exact));
        w.length = std::max(w.length, std::abs(static_cast<double>(glm::length(q)) - 1.0));
      }
    return w;
  };
  const Worst wf = measure(far), wc = measure(close);
  std::printf("slerp against double precision, worst angle: %zu random pairs: series %.2g rad, acos/sin %.2g rad; "
              "%zu pairs within 3 degrees: series %.2g rad, acos/sin %.2g rad; |length - 1| %.2g\n",
              far.size(), wf.series, wf.acos, close.size(), wc.series, wc.acos, std::max(wf.length, wc.length));
  // Goal: within a microradian of the exact slerp, and unit length.
  EXPECT_LT(wf.series, 1e-6);
  EXPECT_LT(wc.series, 1e-6);
  EXPECT_LT(std::max(wf.length, wc.length), 1e-6);
  // Regression: docs/accuracy.md ("Slerp") publishes 3.2e-7 (random) and 2.1e-7 (within 3 degrees)
  // for the series; 1.5x. On close pairs that bound is below the 6.1e-7 the acos / sin form
  // reaches, so putting that form back fails here; the last line checks the measure can tell.
  EXPECT_LT(wf.series, 4.8e-7);
  EXPECT_LT(wc.series, 3.2e-7);
  EXPECT_GT(wc.acos, 3.2e-7) << "the acos / sin form no longer exceeds the close-pair bound";
}

TEST(Transform, SlerpEndsAreTheInputsAndExtrapolationIsExact) {
  const glm::quat a = safeNormalize(glm::quat(0.9f, 0.1f, -0.3f, 0.2f));
  const glm::quat b = safeNormalize(a * glm::angleAxis(2.0f, glm::normalize(glm::vec3(1, 2, 3))));  // past 90 degrees
  const glm::quat c = safeNormalize(a * glm::angleAxis(0.5f, glm::normalize(glm::vec3(1, 2, 3))));
  for (const glm::quat& other : {b, c, -b}) {
    EXPECT_LT(angleBetween(slerpShortest(a, other, 0.0f), glm::normalize(glm::dquat(a))), 1e-6);
    EXPECT_LT(angleBetween(slerpShortest(a, other, 1.0f), glm::normalize(glm::dquat(other))), 1e-6);
    for (const float t : {-0.5f, 1.5f, 2.0f})  // additive layers over full weight extrapolate
      EXPECT_LT(angleBetween(slerpShortest(a, other, t), exactSlerp(a, other, t)), 1e-5) << t;
  }
}

TEST(Transform, SlerpOfBadInputIsNeverNaN) {
  const glm::quat a = safeNormalize(glm::quat(0.9f, 0.1f, -0.3f, 0.2f));
  const glm::quat nan(NAN, 0.0f, 0.0f, 0.0f), inf(INFINITY, 0.0f, 0.0f, 0.0f), zero(0.0f, 0.0f, 0.0f, 0.0f);
  for (const glm::quat& bad : {nan, inf, zero})
    for (const float t : {0.0f, 0.25f, 0.5f, 1.0f}) {
      const glm::quat q = slerpShortest(a, bad, t), r = slerpShortest(bad, a, t);
      EXPECT_TRUE(std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z));
      EXPECT_TRUE(std::isfinite(r.w) && std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z));
    }
  EXPECT_EQ(slerpShortest(a, a, NAN), a);  // a weight that is not a number leaves the first rotation
}
