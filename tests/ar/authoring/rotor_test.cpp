// GA rotors (examples/ar/authoring/include/marionette_ar/authoring/rotor.hpp): conventions,
// the algebra against quaternions and matrices, exp/log at the ends of their range, the paper's
// local and global modes, drift over a million steps against a double oracle, closed loops, and
// gimbal lock against an Euler-angle baseline measured in the same test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette_ar/authoring/rotor.hpp"

namespace {

using namespace marionette::ar::ga;

constexpr double kPi = 3.14159265358979323846;

template <class T>
double distance(const Vector<T>& a, const Vector<T>& b) {
  return std::sqrt(double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y) + double(a.z - b.z) * (a.z - b.z));
}

// The angle between two rotations (degrees), whatever the rotors' signs.
template <class A, class B>
double angleBetweenDeg(const BasicRotor<A>& a, const BasicRotor<B>& b) {
  const RotorD da{a.s, a.b23, a.b31, a.b12}, db{b.s, b.b23, b.b31, b.b12};
  const RotorD d = (db * da.reverse()).normalized();
  return angle(d) * 180.0 / kPi;
}

RotorD randomRotor(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  return RotorD{n(rng), n(rng), n(rng), n(rng)}.normalized();
}

TEST(Rotor, HandednessAndPlanesArePinned) {
  // +90 degrees in e1^e2 (about +Z) maps +X to +Y, as glm's quaternion about +Z does.
  const Rotor z = rotation(kPlaneZ<float>, float(kPi / 2));
  EXPECT_LT(distance(z.apply(Vector<float>{1, 0, 0}), Vector<float>{0, 1, 0}), 1e-6);
  const glm::vec3 q = glm::angleAxis(float(kPi / 2), glm::vec3(0, 0, 1)) * glm::vec3(1, 0, 0);
  EXPECT_LT(distance(z.apply(Vector<float>{1, 0, 0}), Vector<float>{q.x, q.y, q.z}), 1e-6);
  // e2^e3 turns +Y to +Z (about +X); e3^e1 turns +Z to +X (about +Y).
  EXPECT_LT(distance(rotation(kPlaneX<float>, float(kPi / 2)).apply(Vector<float>{0, 1, 0}), Vector<float>{0, 0, 1}), 1e-6);
  EXPECT_LT(distance(rotation(kPlaneY<float>, float(kPi / 2)).apply(Vector<float>{0, 0, 1}), Vector<float>{1, 0, 0}), 1e-6);
  // The rotor of that rotation is cos(theta/2) - sin(theta/2) e12.
  EXPECT_NEAR(z.s, std::cos(kPi / 4), 1e-7);
  EXPECT_NEAR(z.b12, -std::sin(kPi / 4), 1e-7);
  // Composition: (B A) applies A first.
  const Rotor x = rotation(kPlaneX<float>, float(kPi / 2));
  const Vector<float> v = (z * x).apply(Vector<float>{0, 1, 0});  // y -> z (x), then z stays (z)
  EXPECT_LT(distance(v, Vector<float>{0, 0, 1}), 1e-6);
}

TEST(Rotor, AlgebraAgreesWithQuaternionsAndMatrices) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0, 1);
  for (int i = 0; i < 1000; ++i) {
    const RotorD a = randomRotor(rng), b = randomRotor(rng);
    const glm::dquat qa = toQuaternion(a), qb = toQuaternion(b), qab = toQuaternion(a * b);
    const glm::dquat expected = qa * qb;
    EXPECT_NEAR(qab.w, expected.w, 1e-12);
    EXPECT_NEAR(qab.x, expected.x, 1e-12);
    EXPECT_NEAR(qab.y, expected.y, 1e-12);
    EXPECT_NEAR(qab.z, expected.z, 1e-12);
    const Vector<double> v{n(rng), n(rng), n(rng)};
    const glm::dvec3 qv = qa * glm::dvec3(v.x, v.y, v.z);
    EXPECT_LT(distance(a.apply(v), Vector<double>{qv.x, qv.y, qv.z}), 1e-12);
    // The reverse undoes, the matrix agrees, and the matrix comes back to the rotation.
    EXPECT_LT(distance((a.reverse() * a).apply(v), v), 1e-12);
    const glm::dvec3 mv = toMatrix3(a) * glm::dvec3(v.x, v.y, v.z);
    EXPECT_LT(distance(a.apply(v), Vector<double>{mv.x, mv.y, mv.z}), 1e-12);
    EXPECT_LT(angleBetweenDeg(fromMatrix(toMatrix3(a)), a), 1e-9);
    const glm::dvec4 m4 = toMatrix4(a) * glm::dvec4(v.x, v.y, v.z, 1.0);
    EXPECT_LT(distance(a.apply(v), Vector<double>{m4.x, m4.y, m4.z}), 1e-12);
    EXPECT_NEAR(m4.w, 1.0, 1e-15);
    // A bivector turns as the planes it spans: R (u ^ w) ~R = (R u) ^ (R w).
    const Vector<double> u{n(rng), n(rng), n(rng)}, w{n(rng), n(rng), n(rng)};
    const Bivector<double> turned = a.apply(wedge(u, w)), expectedPlane = wedge(a.apply(u), a.apply(w));
    EXPECT_NEAR(turned.b23, expectedPlane.b23, 1e-11);
    EXPECT_NEAR(turned.b31, expectedPlane.b31, 1e-11);
    EXPECT_NEAR(turned.b12, expectedPlane.b12, 1e-11);
    // Round trip through the middleware's quaternion.
    const RotorD back = fromQuaternion(qa);
    EXPECT_EQ(back.s, a.s);
    EXPECT_EQ(back.b12, a.b12);
  }
  // Matrices of half turns (Shepperd's other branches).
  for (const Bivector<double>& p : {kPlaneX<double>, kPlaneY<double>, kPlaneZ<double>, Bivector<double>{0.6, 0.0, 0.8}})
    for (double a : {kPi, kPi - 1e-7, kPi / 2}) {
      const RotorD r = rotation(p, a);
      EXPECT_LT(angleBetweenDeg(fromMatrix(toMatrix3(r)), r), 1e-6) << a;
    }
}

TEST(Rotor, ExpAndLogAreFiniteAndAccurateFromZeroToPi) {
  EXPECT_EQ(exp(Bivector<float>{}).s, 1.0f);
  const Bivector<float> zero = log(Rotor::identity());
  EXPECT_EQ(zero.norm(), 0.0f);
  for (double theta : {1e-12, 1e-8, 1e-6, 1e-4, 1e-3, 0.01, 0.5, 1.0, 2.0, 3.0, kPi - 1e-3, kPi - 1e-6}) {
    const Bivector<double> plane = Bivector<double>{0.36, -0.48, 0.8};
    const RotorD r = rotation(plane, theta);
    const Bivector<double> b = log(r);
    EXPECT_NEAR(b.norm(), theta / 2, 1e-12 * std::max(1.0, theta)) << theta;
    const RotorD again = exp(b);
    EXPECT_LT(angleBetweenDeg(again, r), 1e-9) << theta;
    // float too: no NaN near the identity, relative accuracy kept.
    const Rotor rf = rotation(Bivector<float>{0.36f, -0.48f, 0.8f}, float(theta));
    const Bivector<float> bf = log(rf);
    EXPECT_TRUE(std::isfinite(bf.b23) && std::isfinite(bf.b31) && std::isfinite(bf.b12)) << theta;
    EXPECT_NEAR(bf.norm(), theta / 2, 1e-6 * std::max(1.0, theta) + 1e-7 * theta) << theta;
  }
  // R and -R are the same rotation; log takes the shorter arc, so past pi it turns the other way.
  const RotorD r = rotation(kPlaneZ<double>, kPi + 0.2);
  EXPECT_LT(distance(r.apply(Vector<double>{1, 2, 3}), (-r).apply(Vector<double>{1, 2, 3})), 1e-12);
  EXPECT_NEAR(log(r).norm(), (kPi - 0.2) / 2, 1e-12);
  EXPECT_NEAR(angle(r), kPi - 0.2, 1e-12);
}

TEST(Rotor, BetweenTwoVectors) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0, 1);
  for (int i = 0; i < 500; ++i) {
    const Vector<double> a{n(rng), n(rng), n(rng)}, b{n(rng), n(rng), n(rng)};
    const RotorD r = between(a, b);
    const double la = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z), lb = std::sqrt(b.x * b.x + b.y * b.y + b.z * b.z);
    const Vector<double> turned = r.apply(Vector<double>{a.x / la, a.y / la, a.z / la});
    EXPECT_LT(distance(turned, Vector<double>{b.x / lb, b.y / lb, b.z / lb}), 1e-12);
  }
  // Opposite and equal directions, and no direction at all.
  const RotorD half = between(Vector<double>{0, 0, 2}, Vector<double>{0, 0, -1});
  EXPECT_LT(distance(half.apply(Vector<double>{0, 0, 1}), Vector<double>{0, 0, -1}), 1e-12);
  EXPECT_LT(angleBetweenDeg(between(Vector<double>{1, 1, 0}, Vector<double>{2, 2, 0}), RotorD::identity()), 1e-9);
  const RotorD none = between(Vector<double>{0, 0, 0}, Vector<double>{1, 0, 0});
  EXPECT_EQ(none.s, 1.0);
  const Rotor nan = Rotor{std::nanf(""), 0, 0, 0}.normalized();
  EXPECT_EQ(nan.s, 1.0f);
  EXPECT_EQ((Rotor{0, 0, 0, 0}.normalized().s), 1.0f);
}

TEST(Rotor, LocalModeIsTheRightProduct) {
  // The paper's local mode (the world plane carried by the rotor) equals R exp(-theta/2 B).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> angleDist(-3.0f, 3.0f);
  for (int i = 0; i < 2000; ++i) {
    const RotorD rd = randomRotor(rng);
    const Rotor r{float(rd.s), float(rd.b23), float(rd.b31), float(rd.b12)};
    const Bivector<float> planes[3] = {kPlaneX<float>, kPlaneY<float>, kPlaneZ<float>};
    const Bivector<float> plane = planes[i % 3];
    const float theta = angleDist(rng);
    const Rotor local = rotateLocal(r, plane, theta), right = r * rotation(plane, theta);
    EXPECT_NEAR(local.s, right.s, 1e-6f);
    EXPECT_NEAR(local.b23, right.b23, 1e-6f);
    EXPECT_NEAR(local.b31, right.b31, 1e-6f);
    EXPECT_NEAR(local.b12, right.b12, 1e-6f);
    const Rotor global = rotateGlobal(r, plane, theta), left = rotation(plane, theta) * r;
    EXPECT_EQ(global.s, left.s);
    // A local turn about the character's own up keeps its up; a global one keeps the world's.
    const Vector<float> up = r.apply(Vector<float>{0, 1, 0});
    EXPECT_LT(distance(rotateLocal(r, kPlaneY<float>, theta).apply(Vector<float>{0, 1, 0}), up), 2e-6);
    const Vector<float> worldUpAfter = rotateGlobal(r, kPlaneY<float>, theta).apply(r.reverse().apply(Vector<float>{0, 1, 0}));
    EXPECT_LT(distance(worldUpAfter, Vector<float>{0, 1, 0}), 2e-6);
  }
}

// One authoring step as marionette-ar makes it: a local or a global turn, then the policy.
enum class Renormalize { Never, CheaplyEveryStep, CheaplyEvery10, ExactEveryStep };

Rotor step(const Rotor& r, bool local, const Bivector<float>& plane, float theta, int index, Renormalize policy) {
  Rotor next = local ? rotateLocal(r, plane, theta) : rotateGlobal(r, plane, theta);
  switch (policy) {
    case Renormalize::Never: break;
    case Renormalize::CheaplyEveryStep: next = next.renormalizedCheaply(); break;
    case Renormalize::CheaplyEvery10: if (index % 10 == 9) next = next.renormalizedCheaply(); break;
    case Renormalize::ExactEveryStep: next = next.normalized(); break;  // turn(): the authoring path's
  }
  return next;
}

TEST(Rotor, AMillionIncrementalStepsDriftBelowTheBudget) {
  // Random steps of up to 5 degrees, local and global alternating, about the three axes; float
  // with each policy against the same steps in double (renormalized exactly: the oracle).
  constexpr int kSteps = 1000000;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> angleDist(-5 * kPi / 180, 5 * kPi / 180);
  std::vector<double> angles(kSteps);
  for (double& a : angles) a = angleDist(rng);
  const Bivector<double> planesD[3] = {kPlaneX<double>, kPlaneY<double>, kPlaneZ<double>};
  const Bivector<float> planes[3] = {kPlaneX<float>, kPlaneY<float>, kPlaneZ<float>};
  RotorD oracle = RotorD::identity();
  for (int i = 0; i < kSteps; ++i) {
    const bool local = i % 2 == 0;
    oracle = (local ? rotateLocal(oracle, planesD[i % 3], angles[i]) : rotateGlobal(oracle, planesD[i % 3], angles[i])).normalized();
  }
  struct Result {
    const char* name;
    Renormalize policy;
    double normError = 0, angleDeg = 0;
  } results[] = {{"never", Renormalize::Never}, {"cheap, every step", Renormalize::CheaplyEveryStep},
                 {"cheap, every 10", Renormalize::CheaplyEvery10}, {"exact, every step", Renormalize::ExactEveryStep}};
  for (Result& res : results) {
    Rotor r = Rotor::identity();
    for (int i = 0; i < kSteps; ++i) {
      r = step(r, i % 2 == 0, planes[i % 3], float(angles[i]), i, res.policy);
      res.normError = std::max(res.normError, std::abs(double(r.norm()) - 1.0));
    }
    res.angleDeg = angleBetweenDeg(r, oracle);
    std::printf("[ rotor drift ] %-18s after %d steps: norm error max %.2e, orientation %.5f deg\n", res.name, kSteps,
                res.normError, res.angleDeg);
  }
  // The policy the authoring path uses (kStepPolicy, docs/authoring.md): exact every step. The
  // cheap Newton step keeps the norm but lets the orientation wander past the budget (float
  // rounding of the products, a random walk: 0.006 deg after a million steps).
  EXPECT_LE(results[3].normError, 1e-6);
  EXPECT_LE(results[3].angleDeg, 0.005);
  // Without any, the norm drifts: the policy is needed (the test can fail).
  EXPECT_GT(results[0].normError, 100 * results[3].normError);
}

TEST(Rotor, TurnIsTheStepWithItsPolicy) {
  const Rotor r = rotation(Bivector<float>{0.6f, 0.0f, 0.8f}, 0.7f);
  const Rotor a = turn(r, Axes::Local, kPlaneY<float>, 0.1f), b = rotateLocal(r, kPlaneY<float>, 0.1f).normalized();
  EXPECT_EQ(a.s, b.s);
  EXPECT_EQ(a.b31, b.b31);
  const Rotor c = turn(r, Axes::Global, kPlaneX<float>, -0.2f), d = rotateGlobal(r, kPlaneX<float>, -0.2f).normalized();
  EXPECT_EQ(c.b23, d.b23);
  EXPECT_EQ(c.b12, d.b12);
}

TEST(Rotor, ClosedLoopsComeBackToTheIdentity) {
  for (const Bivector<float>& plane : {kPlaneX<float>, kPlaneY<float>, kPlaneZ<float>}) {
    Rotor r = Rotor::identity(), q = Rotor::identity();
    for (int i = 0; i < 360; ++i) r = rotateLocal(r, plane, float(kPi / 180)).renormalizedCheaply();
    for (int i = 0; i < 4; ++i) q = rotateGlobal(q, plane, float(kPi / 2)).renormalizedCheaply();
    // 360 degrees is -1 as a rotor: the same rotation as the identity.
    const Rotor shortest = r.s < 0 ? -r : r;
    EXPECT_NEAR(shortest.s, 1.0f, 1e-5f);
    EXPECT_LT(shortest.bivector().norm(), 1e-5f);
    const Rotor sq = q.s < 0 ? -q : q;
    EXPECT_NEAR(sq.s, 1.0f, 1e-5f);
    EXPECT_LT(sq.bivector().norm(), 1e-5f);
  }
}

// An Euler-angle baseline (yaw about Y, then pitch about X, then roll about Z: R = Ry Rx Rz, the
// order of a typical authoring panel), extracted back from the oracle's matrix after each step.
struct Euler {
  double yaw, pitch, roll;
};
glm::dmat3 eulerMatrix(const Euler& e) {
  const glm::dmat4 m = glm::rotate(glm::dmat4(1), e.yaw, glm::dvec3(0, 1, 0)) *
                       glm::rotate(glm::dmat4(1), e.pitch, glm::dvec3(1, 0, 0)) *
                       glm::rotate(glm::dmat4(1), e.roll, glm::dvec3(0, 0, 1));
  return glm::dmat3(m);
}
Euler eulerOf(const glm::dmat3& m) {
  // R = Ry Rx Rz: m[2][1] = -sin(pitch) (column 2, row 1).
  const double sp = std::clamp(-m[2][1], -1.0, 1.0);
  Euler e{0, std::asin(sp), 0};
  if (std::abs(sp) < 1 - 1e-12) {
    e.yaw = std::atan2(m[2][0], m[2][2]);
    e.roll = std::atan2(m[0][1], m[1][1]);
  } else {  // gimbal lock: yaw and roll turn about the same axis; all of it goes to yaw
    e.yaw = std::atan2(-m[0][2], m[0][0]);
  }
  return e;
}

TEST(Rotor, GimbalLockIsNothingSpecialForRotors) {
  for (double pitchDeg : {90.0, 89.9}) {
    const Euler start{0.3, pitchDeg * kPi / 180, -0.2};
    const glm::dmat3 m0 = eulerMatrix(start);
    const RotorD r0d = fromMatrix(m0);
    const Rotor r0{float(r0d.s), float(r0d.b23), float(r0d.b31), float(r0d.b12)};
    double rotorError = 0, eulerJump = 0, eulerMidpointDeg = 0, rotorMidpointDeg = 0;
    const Bivector<float> planes[3] = {kPlaneX<float>, kPlaneY<float>, kPlaneZ<float>};
    const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
      for (bool local : {true, false}) {
        const double theta = 1.0 * kPi / 180;
        const glm::dmat3 turn(glm::rotate(glm::dmat4(1), theta, axes[a]));
        const glm::dmat3 oracle = local ? m0 * turn : turn * m0;
        // The rotor step against the matrix oracle.
        const Rotor r = local ? rotateLocal(r0, planes[a], float(theta)) : rotateGlobal(r0, planes[a], float(theta));
        const glm::dmat3 rm(toMatrix3(r));
        for (int c = 0; c < 3; ++c)
          for (int row = 0; row < 3; ++row) rotorError = std::max(rotorError, std::abs(rm[c][row] - oracle[c][row]));
        // The Euler panel's angles before and after the same 1 degree step: how far they jump,
        // and how far their halfway point is from the true halfway orientation.
        const Euler e0 = eulerOf(m0), e1 = eulerOf(oracle);
        auto wrap = [](double d) { return std::remainder(d, 2 * kPi); };
        eulerJump = std::max({eulerJump, std::abs(wrap(e1.yaw - e0.yaw)), std::abs(wrap(e1.pitch - e0.pitch)),
                              std::abs(wrap(e1.roll - e0.roll))});
        const Euler mid{e0.yaw + wrap(e1.yaw - e0.yaw) / 2, e0.pitch + wrap(e1.pitch - e0.pitch) / 2,
                        e0.roll + wrap(e1.roll - e0.roll) / 2};
        const glm::dmat3 half(glm::rotate(glm::dmat4(1), theta / 2, axes[a]));
        const RotorD trueMid = fromMatrix(local ? m0 * half : half * m0);
        eulerMidpointDeg = std::max(eulerMidpointDeg, angleBetweenDeg(fromMatrix(eulerMatrix(mid)), trueMid));
        // The rotors' halfway point: the normalized mean (nlerp) on the shorter arc.
        const Rotor r1 = r.s * r0.s + r.b23 * r0.b23 + r.b31 * r0.b31 + r.b12 * r0.b12 < 0 ? -r : r;
        const Rotor rmid = Rotor{r0.s + r1.s, r0.b23 + r1.b23, r0.b31 + r1.b31, r0.b12 + r1.b12}.normalized();
        rotorMidpointDeg = std::max(rotorMidpointDeg, angleBetweenDeg(rmid, trueMid));
      }
    std::printf("[ gimbal lock ] pitch %.1f deg, 1 deg steps: rotor vs matrix %.2e; Euler angles jump %.2f deg, "
                "their halfway point %.3f deg off the true one (the rotors' %.5f deg)\n",
                pitchDeg, rotorError, eulerJump * 180 / kPi, eulerMidpointDeg, rotorMidpointDeg);
    EXPECT_LT(rotorError, 1e-6) << pitchDeg;
    EXPECT_GT(eulerJump * 180 / kPi, 1.0) << pitchDeg;  // the baseline is measured to misbehave
    EXPECT_GT(eulerMidpointDeg, 0.25) << pitchDeg;      // a quarter of the step off the path
    EXPECT_LT(rotorMidpointDeg, 1e-3) << pitchDeg;
  }
}

}  // namespace
