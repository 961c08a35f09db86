// The exact kernel's AVX2 copy (see core/distance/kernel.hpp): its functions are compiled for AVX2
// (core/simd/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
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

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/simd/avx2_begin.inc"
#include "core/distance/exact_kernel.inc"
#include "core/simd/avx2_end.inc"
#endif
