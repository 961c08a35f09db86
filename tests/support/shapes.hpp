#pragma once
// Generated test meshes whose true signed distance is known in closed form.
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>

namespace sdfgen::test {

// Icosahedron subdivided `levels` times, vertices on the sphere of `radius` about the origin.
Mesh icosphere(float radius, int levels);
// The largest distance between the icosphere's faces and its sphere (the sphere minus the inradius).
float icosphereSag(float radius, int levels);
float sphereDistance(const glm::vec3& p, float radius);

// Axis-aligned box about the origin, two triangles per face.
Mesh box(const glm::vec3& halfExtent);
float boxDistance(const glm::vec3& p, const glm::vec3& halfExtent);

// Torus about the y axis: ring radius `major`, tube radius `minor`, vertices on the exact torus.
Mesh torus(float major, float minor, int ringSegments, int tubeSegments);
float torusDistance(const glm::vec3& p, float major, float minor);
// An upper bound on how far the torus mesh strays from the exact torus.
float torusSag(float major, float minor, int ringSegments, int tubeSegments);

// Path of the bundled model.
const char* bundledBunnyPath();

} // namespace sdfgen::test
