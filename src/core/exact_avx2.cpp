// The exact kernel's AVX2 copy (see core/kernel.hpp): its functions are compiled for AVX2
// (core/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
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

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/avx2_begin.inc"
#include "core/exact_kernel.inc"
#include "core/avx2_end.inc"
#endif
