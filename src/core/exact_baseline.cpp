// The exact kernel's baseline copy (see core/kernel.hpp): compiled with the flags of the build
// (x86-64's SSE2 unless SDFGEN_NATIVE), for CPUs without AVX2 and for checking the AVX2 copy.
#include "core/exact.hpp"
#include "core/geometry.hpp"
#include "core/kernel.hpp"
#include "core/parallel.hpp"
#include "core/sample_positions.hpp"
#include "core/topology.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#define SDFGEN_KERNEL_NAMESPACE baseline
#include "core/exact_kernel.inc"
