// The ray kernel's baseline copy (see core/accel/ray_tree.hpp): compiled with the flags of the build
// (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/accel/ray_tree.hpp"

#include <glm/geometric.hpp>
#include <cmath>
#include <cstring>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE baseline
#include "core/accel/ray_kernel.inc"
