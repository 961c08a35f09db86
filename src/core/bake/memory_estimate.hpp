#pragma once
// The dense bake's memory model: what bake() will hold at its peak, checked before it allocates
// (the narrow band's own estimate is in core/bake/band_bake.hpp).
#include "core/accel/bvh.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/run_control.hpp"

#include <cstdint>

namespace sdfgen {

// The peak bytes bake() allocates for this mesh, grid and settings, counting every buffer the
// chosen distance method and sign hold at once (see bake.cpp, exact.cpp, ray_generator.cpp,
// winding_sign.cpp, topology.cpp): per sample, the ray field, the distances, the nearest triangles, the
// inside flags and the result; per triangle and vertex, the topology; for the winding sign, the
// rows' crossings (estimated from the mesh's area projected along x); `onDevice` (the exact
// distances on a compute device), the device's host-side tables (src/gpu/gl_device.cpp: its
// tree's triangles, the pseudonormals, the closed surface's corners) and its per-sample crossing
// counts and sides; for a ray field, its own wide tree; for closest-point searches on the CPU,
// the wide tree (built by the first bake that needs it; counted even when a Model holds it
// already). Auto counts the dearer of its two choices. The binary tree is not counted: it exists
// before the bake. Given the tree, the rows' crossings count each set of exact copies of a
// triangle once (Bvh::copies), as the scan does. The projected area is summed in parallel on
// control.threads threads, in fixed blocks: the same estimate for any count.
std::uint64_t estimateBakeBytes(const Mesh& mesh, const Grid& grid, const BakeSettings& settings, bool onDevice = false,
                                const Bvh* tree = nullptr, const RunControl& control = {});

// Throws Error("grid NXxNYxNZ (method M, sign S) needs about X MiB but only Y MiB of memory is
// available") when the estimate exceeds the available memory.
void checkBakeMemory(const Mesh& mesh, const Bvh& tree, const Grid& grid, const BakeSettings& settings, bool onDevice,
                     const RunControl& control = {});

} // namespace sdfgen
