// The fan kernel's AVX2 copy (see core/sign/fan_kernel.inc): compiled for AVX2 (core/simd/avx2_begin.inc).
#if defined(__x86_64__) || defined(__i386__)
#include "core/sign/fan_kernel.hpp"
#include "core/sign/winding_sign.hpp"

#include <immintrin.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#define SDFGEN_KERNEL_NAMESPACE avx2
#define SDFGEN_KERNEL_AVX2 1
#include "core/simd/avx2_begin.inc"
#include "core/sign/fan_kernel.inc"
#include "core/simd/avx2_end.inc"
#endif
