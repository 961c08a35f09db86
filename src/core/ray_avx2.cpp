// The ray kernel's AVX2 copy (see core/ray_tree.hpp): compiled for AVX2 by a target pragma rather
// than a file-wide -mavx2, so that the inline functions of the headers (glm, the standard library)
// stay baseline code wherever the linker keeps one copy of them.
#if defined(__x86_64__) || defined(__i386__)
#include "core/ray_tree.hpp"

#include <glm/geometric.hpp>
#include <cmath>
#include <cstring>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#include "core/ray_kernel.inc"
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
