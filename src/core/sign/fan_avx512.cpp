// The fan kernel's AVX-512 copy (see core/sign/fan_kernel.inc): eight lanes of doubles to a
// vector, compiled for AVX-512 (core/simd/avx512_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
#include "core/sign/fan_kernel.hpp"
#include "core/sign/winding_sign.hpp"

#include <immintrin.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE avx512
#define SDFGEN_KERNEL_AVX512 1
#include "core/simd/avx512_begin.inc"
#include "core/sign/fan_kernel.inc"
#include "core/simd/avx512_end.inc"
#endif
