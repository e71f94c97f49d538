// Deterministic direction sets on the sphere.
#pragma once
#include <glm/vec3.hpp>

#include <vector>

namespace marionette::prt {

// n unit vectors spread evenly over the sphere (the Fibonacci lattice, +Y polar axis): the
// normals of every lighting-error measurement and the fitting directions of ShRotation.
[[nodiscard]] std::vector<glm::dvec3> fibonacciSphere(int n);

}  // namespace marionette::prt
