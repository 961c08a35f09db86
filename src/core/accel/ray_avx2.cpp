// The ray kernel's AVX2 copy (see core/accel/ray_tree.hpp): compiled for AVX2 (core/simd/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
#include "core/accel/ray_tree.hpp"

#include <glm/geometric.hpp>
#include <cmath>
#include <cstring>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/simd/avx2_begin.inc"
#include "core/accel/ray_kernel.inc"
#include "core/simd/avx2_end.inc"
#endif
