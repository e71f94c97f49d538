// Contact shadows' CPU half (marionette_ar/contact_shadow.hpp): the directional + ambient fit
// of the SH light, and where a character stands from its joints.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "marionette_ar/contact_shadow.hpp"

namespace {

using namespace marionette::ar;

constexpr float kPi = 3.14159265358979f;

// The 9 irradiance coefficients of a delta light of irradiance `power` from `d` plus a constant
// radiance `ambient`, grey: L_i = power Y_i(d) (+ ambient 4 pi Y_0 in band 0), c_i = A_l L_i.
std::array<glm::vec3, 9> deltaPlusAmbient(glm::vec3 d, float power, float ambient) {
  d = glm::normalize(d);
  const float y[9] = {0.282095f,
                      0.488603f * d.x,
                      0.488603f * d.y,
                      0.488603f * d.z,
                      1.092548f * d.x * d.z,
                      1.092548f * d.x * d.y,
                      0.315392f * (3 * d.y * d.y - 1),
                      1.092548f * d.y * d.z,
                      0.546274f * (d.z * d.z - d.x * d.x)};
  const float band[3] = {kPi, 2 * kPi / 3, kPi / 4};
  std::array<glm::vec3, 9> c{};
  for (int i = 0; i < 9; ++i) {
    const int l = i == 0 ? 0 : i < 4 ? 1 : 2;
    float radiance = power * y[i];
    if (i == 0) radiance += ambient * 4 * kPi * 0.282095f;
    c[static_cast<std::size_t>(i)] = glm::vec3(band[l] * radiance);
  }
  return c;
}

TEST(ContactShadowLight, ADeltaLightIsFoundWithItsDirectionAndAllOfTheFloorsLight) {
  const glm::vec3 d = glm::normalize(glm::vec3(1, 2, 0.5f));
  const ShadowLight light = dominantLight(deltaPlusAmbient(d, 3.0f, 0.0f));
  EXPECT_NEAR(glm::dot(light.towardLight, d), 1.0f, 1e-5f);
  EXPECT_NEAR(light.directionality, 1.0f, 1e-4f);
  EXPECT_NEAR(light.directFraction, 1.0f, 1e-4f);
  EXPECT_NEAR(light.ambientFraction, 0.0f, 1e-4f);
}

TEST(ContactShadowLight, DeltaPlusAmbientSplitsTheFloorsLightAsTheModelSays) {
  const glm::vec3 d = glm::normalize(glm::vec3(-0.3f, 1, 0.2f));
  const float power = 2.0f, ambient = 0.5f;
  const ShadowLight light = dominantLight(deltaPlusAmbient(d, power, ambient));
  const float direct = power * d.y, sky = kPi * ambient;
  EXPECT_NEAR(light.directFraction, direct / (direct + sky), 1e-4f);
  EXPECT_NEAR(light.ambientFraction, sky / (direct + sky), 1e-4f);
  EXPECT_NEAR(light.directionality, power * 0.282095f / (power * 0.282095f + ambient * 4 * kPi * 0.282095f), 1e-4f);
  EXPECT_NEAR(glm::dot(light.towardLight, d), 1.0f, 1e-5f);
}

TEST(ContactShadowLight, UniformLightIsAllAmbientAndLightFromBelowCastsNothingOnTheFloor) {
  const ShadowLight uniform = dominantLight(deltaPlusAmbient(glm::vec3(0, 1, 0), 0.0f, 1.0f));
  EXPECT_NEAR(uniform.directFraction, 0.0f, 1e-6f);
  EXPECT_NEAR(uniform.ambientFraction, 1.0f, 1e-6f);
  EXPECT_NEAR(uniform.directionality, 0.0f, 1e-6f);
  const ShadowLight below = dominantLight(deltaPlusAmbient(glm::vec3(0.2f, -1, 0), 2.0f, 0.3f));
  EXPECT_EQ(below.directFraction, 0.0f);
  EXPECT_NEAR(below.ambientFraction, 1.0f, 1e-6f);
  EXPECT_LT(below.towardLight.y, 0.0f);
}

TEST(ContactShadowLight, NoLightAndNonFiniteLightGiveNoShadowAndNoNan) {
  for (const float bad : {0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::array<glm::vec3, 9> c{};
    c.fill(glm::vec3(bad));
    const ShadowLight light = dominantLight(c);
    EXPECT_EQ(light.directFraction, 0.0f) << bad;
    EXPECT_EQ(light.ambientFraction, 0.0f) << bad;
    EXPECT_TRUE(std::isfinite(light.towardLight.x) && std::isfinite(light.towardLight.y)) << bad;
  }
}

// A stick figure 1.7 m tall standing at (1, 0, 2), its feet 2 cm above the floor.
std::vector<glm::vec3> standing() {
  return {{1.1f, 0.02f, 2.0f}, {0.9f, 0.02f, 2.05f}, {1.1f, 0.5f, 2.0f}, {0.9f, 0.5f, 2.0f},
          {1.0f, 1.0f, 2.0f},  {1.0f, 1.4f, 2.0f},   {1.0f, 1.7f, 2.0f}, {1.3f, 1.4f, 2.0f}};
}

TEST(ContactShadowCaster, TheFeetAreTheContactsAndTheCatcherHoldsThem) {
  const std::vector<glm::vec3> joints = standing();
  const ShadowCaster c = shadowCaster(joints, glm::vec3(0, 1, 0));
  ASSERT_TRUE(c.valid);
  EXPECT_NEAR(c.height, 1.68f, 1e-5f);
  ASSERT_EQ(c.contactCount, 2u);  // the two feet, nothing else is within 8 % of the height
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(c.contacts[i].x, joints[i].x, 1e-6f);
    EXPECT_NEAR(c.contacts[i].y, joints[i].z, 1e-6f);
    EXPECT_NEAR(c.contacts[i].z, kContactDiscRadius * 1.68f, 1e-5f);
    EXPECT_NEAR(c.contacts[i].w, 1.0f - 0.02f / (kContactHeight * 1.68f), 1e-5f);
  }
  // Overhead light: the catcher is the footprint, centred under the figure, holding the sphere.
  EXPECT_NEAR(c.catcherCentre.x, 1.1f, 1e-5f);  // the joints span x 0.9 .. 1.3
  EXPECT_NEAR(c.catcherCentre.y, 2.025f, 1e-5f);
  EXPECT_NEAR(c.catcherHalfLength, c.radius, 1e-6f);
  EXPECT_NEAR(c.catcherHalfWidth, c.radius, 1e-6f);
  for (const glm::vec3& j : joints) EXPECT_LE(glm::distance(j, c.centre), c.radius);
}

TEST(ContactShadowCaster, ALowLightGrowsTheCatcherAwayFromTheLightAndNoFurtherThanThreeRadii) {
  const std::vector<glm::vec3> joints = standing();
  const ShadowCaster overhead = shadowCaster(joints, glm::vec3(0, 1, 0));
  const ShadowCaster fromPlusX = shadowCaster(joints, glm::normalize(glm::vec3(1, 1, 0)));
  EXPECT_LT(fromPlusX.catcherCentre.x, overhead.catcherCentre.x);  // the shadow falls toward -X
  EXPECT_NEAR(fromPlusX.catcherCentre.y, overhead.catcherCentre.y, 1e-5f);
  EXPECT_NEAR(fromPlusX.catcherAxis.x, -1.0f, 1e-6f);
  EXPECT_NEAR(fromPlusX.catcherHalfLength - overhead.catcherHalfLength, 0.5f * 1.7f, 1e-4f);  // the head's shadow, 1.7 m away
  EXPECT_NEAR(fromPlusX.catcherHalfWidth, overhead.catcherHalfWidth, 1e-6f);  // no wider
  const ShadowCaster grazing = shadowCaster(joints, glm::normalize(glm::vec3(1, 0.06f, 0)));
  EXPECT_NEAR(grazing.catcherHalfLength - overhead.catcherHalfLength, 1.5f * overhead.radius, 1e-4f);
}

TEST(ContactShadowCaster, NonFiniteJointsAreSkippedAndNothingAboveTheFloorIsNoCaster) {
  std::vector<glm::vec3> joints = standing();
  const ShadowCaster clean = shadowCaster(joints, glm::vec3(0, 1, 0));
  joints.push_back(glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f));
  joints.push_back(glm::vec3(0.0f, std::numeric_limits<float>::infinity(), 0.0f));
  const ShadowCaster withBad = shadowCaster(joints, glm::vec3(0, 1, 0));
  ASSERT_TRUE(withBad.valid);
  EXPECT_EQ(withBad.radius, clean.radius);
  EXPECT_EQ(withBad.contactCount, clean.contactCount);
  EXPECT_FALSE(shadowCaster({}, glm::vec3(0, 1, 0)).valid);
  const std::vector<glm::vec3> underground = {{0, -0.5f, 0}, {0, -1.0f, 0}};
  EXPECT_FALSE(shadowCaster(underground, glm::vec3(0, 1, 0)).valid);
}

TEST(ContactShadowCaster, AtMostEightContactsTheLowestKept) {
  std::vector<glm::vec3> joints = {{0, 2.0f, 0}};
  for (int i = 0; i < 12; ++i) {  // 0 .. 11 cm up
    const float k = static_cast<float>(i);
    joints.push_back(glm::vec3(0.1f * k, 0.01f * k, 0));
  }
  const ShadowCaster c = shadowCaster(joints, glm::vec3(0, 1, 0));
  ASSERT_EQ(c.contactCount, kMaxContactPoints);
  for (std::size_t i = 0; i < c.contactCount; ++i) EXPECT_LT(c.contacts[i].x, 0.75f) << i;  // the 8 lowest
}

TEST(ContactShadowCaster, TheLightsViewHoldsTheSphereAndLooksAlongTheLight) {
  const std::vector<glm::vec3> joints = standing();
  const glm::vec3 d = glm::normalize(glm::vec3(0.4f, 1, -0.3f));
  const ShadowCaster c = shadowCaster(joints, d);
  const glm::mat4 m = lightViewProjection(c, d);
  for (const glm::vec3& j : joints) {
    const glm::vec4 p = m * glm::vec4(j, 1.0f);
    EXPECT_LE(std::abs(p.x), 1.0f);
    EXPECT_LE(std::abs(p.y), 1.0f);
    EXPECT_LE(std::abs(p.z), 1.0f);
  }
  // Two points on one ray of the light share the map's texel; the one nearer the light is nearer.
  const glm::vec4 a = m * glm::vec4(c.centre + 0.3f * d, 1.0f), b = m * glm::vec4(c.centre - 0.3f * d, 1.0f);
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_LT(a.z, b.z);
}

}  // namespace
