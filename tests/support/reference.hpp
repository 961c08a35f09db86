#pragma once
// The brute-force reference and the comparisons the accuracy suites make against it.
#include "core/bake/bake.hpp"
#include "core/accel/topology.hpp"

#include <cstddef>
#include <string>

namespace sdfgen::test {

// The mesh check of `mesh`, its tree built here.
MeshCheck checkMesh(const Mesh& mesh);

BakeResult bakeWith(const Mesh& mesh, int res, DistanceMethod method, SignMethod sign, int threads = 0, int rays = 64);

// The brute-force field of a named mesh at a resolution, computed once per test run (the bunny's
// is the slowest thing here and several tests compare against it).
const Field& bruteField(const std::string& name, const Mesh& mesh, int res);

// Sign disagreements of `test` with `reference`, split by whether the sample lies within one voxel
// of the surface (in either field).
struct SignCounts {
    std::size_t near = 0, nearWrong = 0, far = 0, farWrong = 0, referenceInside = 0;
};
SignCounts countSigns(const Field& test, const Field& reference);

} // namespace sdfgen::test
