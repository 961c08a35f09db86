#pragma once
// Eight-lane float/int vectors written with the GCC/Clang vector extension: with AVX enabled each
// operation is one instruction, elsewhere the compiler lowers it to narrower vectors. The same
// templates also accept plain float, so one routine serves both a single ray and a packet. The
// operations are in simd_ops.inc, which the exact kernel includes again for each instruction set
// it is compiled for (core/distance/exact_kernel.inc); the types are shared.
#include <cstdint>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace sdfgen {
namespace simd {
using f8 = float __attribute__((vector_size(32)));
using i8 = std::int32_t __attribute__((vector_size(32)));
} // namespace simd

#include "core/simd/simd_ops.inc"

} // namespace sdfgen
