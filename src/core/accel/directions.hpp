#pragma once
#include <glm/vec3.hpp>
#include <vector>

namespace sdfgen {

// `count` unit vectors spread evenly over the sphere: the spherical Fibonacci lattice, each point
// owning an equal area band in z and a golden-angle step in longitude. count >= 1.
std::vector<glm::vec3> sphereDirections(int count);

} // namespace sdfgen
