// The exact kernel's baseline copy (see core/distance/kernel.hpp): compiled with the flags of the build
// (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/distance/exact.hpp"
#include "core/mesh/geometry.hpp"
#include "core/distance/kernel.hpp"
#include "core/runtime/parallel.hpp"
#include "core/mesh/sample_positions.hpp"
#include "core/accel/topology.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE baseline
#include "core/distance/exact_kernel.inc"
