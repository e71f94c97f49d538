// Rotors of Euclidean 3D geometric algebra G(3,0): the even subalgebra, a scalar and the three
// unit bivectors e23, e31, e12, as a value type. The AR authoring path rotates characters with
// these (docs/authoring.md), as the seed paper does, instead of Euler angles.
//
// Conventions (pinned by tests/ar/authoring/rotor_test.cpp):
//  - e1, e2, e3 are the world's +X, +Y, +Z (the renderer's axes: +Y up).
//  - A rotation by angle theta in the plane of the unit bivector B is R = exp(-theta/2 B),
//    applied to a vector as the sandwich v' = R v ~R (~R the reverse).
//  - The plane e1^e2 = e12 turns +X towards +Y: it is the rotation about +Z, by the right-hand
//    rule, as the middleware's quaternions turn (+90 degrees about +Z maps +X to +Y). Likewise
//    e23 turns about +X and e31 about +Y. (The paper labels e1^e2 its "x" rotation: a rotation
//    in that plane turns about z; docs/authoring.md maps its equations onto these.)
//  - Composition: R2 R1 applies R1 first.
//  - Quaternion (w, x, y, z) = (s, -b23, -b31, -b12): the isomorphism i = -e23, j = -e31,
//    k = -e12, under which the two sandwiches agree.
//  - R and -R are the same rotation; log() returns the shorter arc (angle in [0, pi]).
//
// Everything is constexpr or inline, noexcept, allocation-free; T is float (the authoring path)
// or double (the tests' oracle).
#pragma once
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace marionette::ar::ga {

template <class T>
struct Vector {
  T x = 0, y = 0, z = 0;  // x e1 + y e2 + z e3
};

// b23 e23 + b31 e31 + b12 e12: an oriented plane with an area (its norm).
template <class T>
struct Bivector {
  T b23 = 0, b31 = 0, b12 = 0;
  [[nodiscard]] constexpr Bivector operator*(T k) const noexcept { return {b23 * k, b31 * k, b12 * k}; }
  [[nodiscard]] constexpr Bivector operator-() const noexcept { return {-b23, -b31, -b12}; }
  [[nodiscard]] T norm() const noexcept { return std::sqrt(b23 * b23 + b31 * b31 + b12 * b12); }
};

// The world's planes: the rotation about x is in e2^e3, about y in e3^e1, about z in e1^e2.
template <class T>
inline constexpr Bivector<T> kPlaneX{1, 0, 0};
template <class T>
inline constexpr Bivector<T> kPlaneY{0, 1, 0};
template <class T>
inline constexpr Bivector<T> kPlaneZ{0, 0, 1};

// The outer product a ^ b of two vectors.
template <class T>
[[nodiscard]] constexpr Bivector<T> wedge(const Vector<T>& a, const Vector<T>& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <class T>
struct BasicRotor {
  T s = 1, b23 = 0, b31 = 0, b12 = 0;  // s + b23 e23 + b31 e31 + b12 e12

  [[nodiscard]] static constexpr BasicRotor identity() noexcept { return {}; }

  // The geometric product (the bivector table: e23 e31 = -e12, e31 e12 = -e23, e12 e23 = -e31,
  // each squares to -1, and reversing an order flips the sign).
  [[nodiscard]] constexpr BasicRotor operator*(const BasicRotor& o) const noexcept {
    return {s * o.s - b23 * o.b23 - b31 * o.b31 - b12 * o.b12,
            s * o.b23 + b23 * o.s - b31 * o.b12 + b12 * o.b31,
            s * o.b31 + b31 * o.s - b12 * o.b23 + b23 * o.b12,
            s * o.b12 + b12 * o.s - b23 * o.b31 + b31 * o.b23};
  }
  [[nodiscard]] constexpr BasicRotor reverse() const noexcept { return {s, -b23, -b31, -b12}; }
  [[nodiscard]] constexpr BasicRotor operator-() const noexcept { return {-s, -b23, -b31, -b12}; }
  [[nodiscard]] constexpr T normSquared() const noexcept { return s * s + b23 * b23 + b31 * b31 + b12 * b12; }
  [[nodiscard]] T norm() const noexcept { return std::sqrt(normSquared()); }
  [[nodiscard]] constexpr Bivector<T> bivector() const noexcept { return {b23, b31, b12}; }

  // R / |R|; the identity for a zero or non-finite rotor.
  [[nodiscard]] BasicRotor normalized() const noexcept {
    const T n2 = normSquared();
    if (!(n2 > T(1e-30) && n2 < T(1e30))) return {};
    const T k = T(1) / std::sqrt(n2);
    return {s * k, b23 * k, b31 * k, b12 * k};
  }
  // One Newton step towards |R| = 1 (no square root): exact to second order in |R|^2 - 1, enough
  // for a rotor that drifted by rounding (docs/authoring.md measures the policy).
  [[nodiscard]] constexpr BasicRotor renormalizedCheaply() const noexcept {
    const T k = (T(3) - normSquared()) * T(0.5);
    return {s * k, b23 * k, b31 * k, b12 * k};
  }

  // R v ~R.
  [[nodiscard]] constexpr Vector<T> apply(const Vector<T>& v) const noexcept {
    // The quaternion form of the sandwich: u = -(b23, b31, b12), v' = v + 2 s (u x v) + 2 u x (u x v).
    const T ux = -b23, uy = -b31, uz = -b12;
    const T tx = T(2) * (uy * v.z - uz * v.y), ty = T(2) * (uz * v.x - ux * v.z), tz = T(2) * (ux * v.y - uy * v.x);
    return {v.x + s * tx + (uy * tz - uz * ty), v.y + s * ty + (uz * tx - ux * tz), v.z + s * tz + (ux * ty - uy * tx)};
  }
  // R B ~R: a bivector is the dual of a vector (B = I b with I = e123, which commutes with rotors),
  // so its components turn as that vector's.
  [[nodiscard]] constexpr Bivector<T> apply(const Bivector<T>& b) const noexcept {
    const Vector<T> v = apply(Vector<T>{b.b23, b.b31, b.b12});
    return {v.x, v.y, v.z};
  }
};

using Rotor = BasicRotor<float>;
using RotorD = BasicRotor<double>;

// exp(B) = cos|B| + B / |B| sin|B|: the rotor turning by 2 |B| in B's plane (R = exp(-theta/2 B)
// for a unit plane B). A series near zero: finite and accurate for any |B|.
template <class T>
[[nodiscard]] BasicRotor<T> exp(const Bivector<T>& b) noexcept {
  const T a2 = b.b23 * b.b23 + b.b31 * b.b31 + b.b12 * b.b12;
  const T a = std::sqrt(a2);
  // sin(a) / a: 1 - a^2/6 + a^4/120 below the point where the series is exact to rounding.
  const T sinc = a < T(1e-3) ? T(1) - a2 / T(6) + a2 * a2 / T(120) : std::sin(a) / a;
  return {std::cos(a), b.b23 * sinc, b.b31 * sinc, b.b12 * sinc};
}

// The bivector B with exp(B) = R (R unit), on the shorter arc: |B| in [0, pi/2] (a rotation of
// 0..pi). atan2 keeps it accurate at both ends (no acos near 1, no division by a small sine).
template <class T>
[[nodiscard]] Bivector<T> log(const BasicRotor<T>& rotor) noexcept {
  const BasicRotor<T> r = rotor.s < 0 ? -rotor : rotor;
  const T b = r.bivector().norm();
  if (!(b > T(0))) return {};
  const T angle = std::atan2(b, r.s);
  return r.bivector() * (angle / b);
}

// The rotation by `radians` in the plane of the unit bivector `plane`, right-handed about its dual axis.
template <class T>
[[nodiscard]] BasicRotor<T> rotation(const Bivector<T>& plane, T radians) noexcept {
  return exp(plane * (-radians * T(0.5)));
}

// The rotation angle of a rotor, 0..pi (radians).
template <class T>
[[nodiscard]] T angle(const BasicRotor<T>& r) noexcept {
  return T(2) * std::atan2(r.bivector().norm(), std::abs(r.s));
}

// The smallest rotor taking the direction of `from` to the direction of `to`: (1 + to from) / |...|.
// Opposite directions (no unique plane): a half turn in a plane containing `from`.
template <class T>
[[nodiscard]] BasicRotor<T> between(const Vector<T>& from, const Vector<T>& to) noexcept {
  const T la = std::sqrt(from.x * from.x + from.y * from.y + from.z * from.z);
  const T lb = std::sqrt(to.x * to.x + to.y * to.y + to.z * to.z);
  if (!(la > T(0)) || !(lb > T(0))) return {};
  const Vector<T> a{from.x / la, from.y / la, from.z / la}, b{to.x / lb, to.y / lb, to.z / lb};
  const T dot = a.x * b.x + a.y * b.y + a.z * b.z;
  const Bivector<T> w = wedge(b, a);  // b a = b.a + b^a
  BasicRotor<T> r{T(1) + dot, w.b23, w.b31, w.b12};
  if (r.normSquared() < T(1e-12)) {
    // Antiparallel: the plane of `from` and the world axis least aligned with it.
    const Vector<T> helper = std::abs(a.x) < T(0.6) ? Vector<T>{1, 0, 0} : Vector<T>{0, 1, 0};
    const Bivector<T> p = wedge(helper, a);
    r = {0, p.b23, p.b31, p.b12};
  }
  return r.normalized();
}

// The paper's two modes (docs/authoring.md):
// about a world axis (`plane` one of kPlaneX/Y/Z): R <- exp(-theta/2 B) R;
template <class T>
[[nodiscard]] BasicRotor<T> rotateGlobal(const BasicRotor<T>& r, const Bivector<T>& plane, T radians) noexcept {
  return rotation(plane, radians) * r;
}
// about the character's own axis: the world plane carried by the current rotor, B' = R B ~R,
// then R <- exp(-theta/2 B') R (equal to R exp(-theta/2 B)).
template <class T>
[[nodiscard]] BasicRotor<T> rotateLocal(const BasicRotor<T>& r, const Bivector<T>& plane, T radians) noexcept {
  return rotation(r.apply(plane), radians) * r;
}

// The authoring path's step: a turn about a local or a world axis, then exact renormalization.
// The policy is measured (Rotor.AMillionIncrementalStepsDriftBelowTheBudget, docs/authoring.md):
// after 10^6 float steps it keeps the norm within 1.2e-7 and the orientation within 0.0012 deg
// of a double oracle; the square-root-free Newton step keeps the norm but not the orientation
// budget (0.006 deg), and none lets the norm drift to 2e-4.
enum class Axes { Local, Global };
template <class T>
[[nodiscard]] BasicRotor<T> turn(const BasicRotor<T>& r, Axes axes, const Bivector<T>& plane, T radians) noexcept {
  return (axes == Axes::Local ? rotateLocal(r, plane, radians) : rotateGlobal(r, plane, radians)).normalized();
}

// Conversions. The middleware's glm::quat (w, x, y, z) and column-major matrices.
template <class T>
[[nodiscard]] constexpr glm::qua<T> toQuaternion(const BasicRotor<T>& r) noexcept {
  return glm::qua<T>(r.s, -r.b23, -r.b31, -r.b12);
}
template <class T>
[[nodiscard]] constexpr BasicRotor<T> fromQuaternion(const glm::qua<T>& q) noexcept {
  return {q.w, -q.x, -q.y, -q.z};
}
template <class T>
[[nodiscard]] glm::mat<3, 3, T> toMatrix3(const BasicRotor<T>& r) noexcept {
  const Vector<T> x = r.apply(Vector<T>{1, 0, 0}), y = r.apply(Vector<T>{0, 1, 0}), z = r.apply(Vector<T>{0, 0, 1});
  return glm::mat<3, 3, T>(x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z);
}
template <class T>
[[nodiscard]] glm::mat<4, 4, T> toMatrix4(const BasicRotor<T>& r) noexcept {
  return glm::mat<4, 4, T>(toMatrix3(r));
}
// The rotor of a rotation matrix (Shepperd's choice of the largest diagonal term: stable at any
// angle). The matrix's scale is ignored if uniform; the result is normalized.
template <class T>
[[nodiscard]] BasicRotor<T> fromMatrix(const glm::mat<3, 3, T>& m) noexcept {
  // m[c][r]: column c, row r.
  const T trace = m[0][0] + m[1][1] + m[2][2];
  T w, x, y, z;
  if (trace > m[0][0] && trace > m[1][1] && trace > m[2][2]) {
    const T k = std::sqrt(T(1) + trace) * T(2);
    w = T(0.25) * k;
    x = (m[1][2] - m[2][1]) / k;
    y = (m[2][0] - m[0][2]) / k;
    z = (m[0][1] - m[1][0]) / k;
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    const T k = std::sqrt(T(1) + m[0][0] - m[1][1] - m[2][2]) * T(2);
    w = (m[1][2] - m[2][1]) / k;
    x = T(0.25) * k;
    y = (m[1][0] + m[0][1]) / k;
    z = (m[2][0] + m[0][2]) / k;
  } else if (m[1][1] >= m[2][2]) {
    const T k = std::sqrt(T(1) + m[1][1] - m[0][0] - m[2][2]) * T(2);
    w = (m[2][0] - m[0][2]) / k;
    x = (m[1][0] + m[0][1]) / k;
    y = T(0.25) * k;
    z = (m[2][1] + m[1][2]) / k;
  } else {
    const T k = std::sqrt(T(1) + m[2][2] - m[0][0] - m[1][1]) * T(2);
    w = (m[0][1] - m[1][0]) / k;
    x = (m[2][0] + m[0][2]) / k;
    y = (m[2][1] + m[1][2]) / k;
    z = T(0.25) * k;
  }
  return fromQuaternion(glm::qua<T>(w, x, y, z)).normalized();
}

}  // namespace marionette::ar::ga
