// The exact kernel's AVX2 copy (see core/kernel.hpp): its functions are compiled for AVX2 by a
// target pragma rather than a file-wide -mavx2, so that the inline functions of the headers
// (glm, the standard library) stay baseline code wherever the linker keeps one copy of them.
#if defined(__x86_64__) || defined(__i386__)
#include "core/exact.hpp"
#include "core/geometry.hpp"
#include "core/kernel.hpp"
#include "core/parallel.hpp"
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
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#include "core/exact_kernel.inc"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
